// The solvers that combine others: "auto" (AutoSolver) and its symmetry probe (SymmetryProbingSolver);
// the factory of the case files' kinds.
#include "linalg/linear_solver.hpp"

#include <malloc.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <utility>
#include <vector>

#include "common/error.hpp"
#include "common/system_memory.hpp"
#include "linalg/cholmod_split.hpp"
#include "linalg/direct_solvers.hpp"
#include "linalg/krylov_reuse.hpp"
#include "linalg/skew_correction.hpp"
#include "linalg/symmetry_probe.hpp"

namespace fibrane::solve {

void hand_back_freed_memory() {
  if (hand_back_needed()) malloc_trim(0);
}

void hand_back_all_freed_memory() { malloc_trim(0); }

double factorization_memory_limit(long megabytes) {
  constexpr double kMegabyte = 1 << 20;
  if (megabytes != kAvailableMemory) return std::max(megabytes, 0L) * kMegabyte;
  // Of the available memory, the share a factorisation may take and what is kept for the rest of the
  // step (the solves' vectors, the next evaluation's assembly).
  constexpr double kUsableShare = 0.95, kReserve = 256 * kMegabyte;
  const double available = static_cast<double>(available_memory());
  return available > 0 ? std::max(available * kUsableShare - kReserve, kMegabyte) : 0.0;
}

namespace {

using SpMat = Eigen::SparseMatrix<double>;

// MUMPS's options for `memory`: its limit, and out of core where a factorisation does not fit in memory.
MumpsOptions spilling_mumps(const SolverMemory& memory) {
  MumpsOptions o;
  o.memory_limit_megabytes = memory.limit_megabytes;
  o.out_of_core_directory = memory.spill_directory;
  o.out_of_core_when_needed = !memory.spill_directory.empty();
  return o;
}

// LL^T first, then a symmetric indefinite factorisation. An indefinite tangent is often a single wild
// Newton iterate: on the bending example at 300 x 75 x 75 only the first update of the first step was
// indefinite, and staying on LU afterwards cost more per iteration than LL^T (docs/performance.md,
// "Linear solver"). Past a limit point, though, every tangent is indefinite, and a failed LL^T attempt
// costs up to a factorisation (CHOLMOD stops at the first non-positive pivot, which for a few negative
// eigenvalues comes late). So after a matrix that the fallback found indefinite, the next one goes to the
// fallback first, and LL^T is first again once the fallback finds a matrix positive definite
// (negative_eigenvalues() == 0). The first tangent of a step (begin_step()) follows the last step's first:
// a predictor that overshoots (the secant on the full membrane from dt 0.03 on) makes every step start at an
// indefinite tangent between positive definite ones, so there the fallback is first if it was last time.
// The fallback is MUMPS's LDL^T with pivoting where fibrane has MUMPS: it gives the inertia at any size,
// its analysis takes CHOLMOD's pivot order (METIS or AMD, already computed for LL^T; on the bending
// example at 155 k unknowns MUMPS's own choice, AMF, took longer than CHOLMOD's whole analysis and gave 7 %
// more factor entries, 73.2 M against 68.3 M), and its failure means a numerically singular matrix, which
// is final. Without MUMPS it is CHOLMOD's simplicial LDL^T up to kSimplicialLimit unknowns, then
// UMFPACK's LU (no inertia, so never tried first): the simplicial LDL^T has no BLAS-3 kernels (impractical
// on the bending example at 400 x 100 x 100, 273 k unknowns: docs/performance.md, "Linear solver"),
// and without pivoting it can fail where LU does not.
// One factor at a time: before the fallback factorises, LL^T's values are freed (a failed LL^T's too) and
// its analysis kept; before LL^T factorises, the fallback goes, analysis and all (MUMPS 5.5 cannot free
// its factor alone), and is analysed again when next needed (without MUMPS, starting again at the
// simplicial LDL^T). The freed memory stays in the process for the other factor (handing it back to the
// system made every switch fault in fresh pages), so the peak is about the larger factor's, not both
// together's (docs/performance.md, "One factor at a time").
//
// With a spill directory (LinearSolverSettings::out_of_core_when_needed), MUMPS's LDL^T factorises out of
// core where its in-core factor does not fit the memory limit, and a matrix whose LL^T is refused for
// memory goes to it too.
class AutoSolver final : public LinearSolver {
 public:
  static constexpr Eigen::Index kSimplicialLimit = 20000;
  AutoSolver(bool split, SolverMemory memory) : split_(split), memory_(std::move(memory)) {}
  void analyze(const SpMat& a) override {
    fallback_.reset();  // first, so that llt_'s hand-back (direct_solvers.hpp) includes its factor
    if (!llt_)
      llt_ = split_ ? make_cholmod_split_llt({.memory_limit_megabytes = memory_.limit_megabytes})
                    : make_cholmod_llt(memory_.limit_megabytes);
    llt_->analyze(a);
    current_ = llt_.get();
  }
  bool factorize_numeric(const SpMat& a) override {
    if (!llt_) analyze(a);
    const bool first_of_step = std::exchange(step_starts_, false);
    if (!(fallback_first_ || (first_of_step && step_start_indefinite_))) {
      fallback_.reset();
      current_ = llt_.get();
      if (llt_->factorize(a)) {
        if (first_of_step) step_start_indefinite_ = false;
        return true;
      }
      // Refused for memory (the only failure CHOLMOD explains): the fallback's factor is no smaller in
      // core, but it may go out of core.
      if (!llt_->failure_detail().empty() && memory_.spill_directory.empty()) return false;
    }
    llt_->release_factor();
    const bool ok = factorize_fallback(a);
    fallback_first_ = ok && current_->negative_eigenvalues() > 0;
    if (first_of_step) step_start_indefinite_ = fallback_first_;
    return ok;
  }
  void begin_step() override { step_starts_ = true; }
  // Both factors go; LL^T's analysis stays.
  void release_factor() override {
    fallback_.reset();
    if (llt_) llt_->release_factor();
    current_ = llt_.get();
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const override { return current_->solve(b); }
  Eigen::MatrixXd solve_columns(const Eigen::MatrixXd& b) const override { return current_->solve_columns(b); }
  std::string name() const override { return "auto(" + (current_ ? current_->name() : "none") + ")"; }
  long factor_nonzeros() const override { return current_ ? current_->factor_nonzeros() : 0; }
  std::string analysis_summary() const override { return llt_ ? llt_->analysis_summary() : ""; }
  int negative_eigenvalues() const override { return current_ ? current_->negative_eigenvalues() : -1; }
  std::string failure_detail() const override { return current_ ? current_->failure_detail() : ""; }
  long held_factor_entries() const override {
    return (llt_ ? llt_->held_factor_entries() : 0) + (fallback_ ? fallback_->held_factor_entries() : 0);
  }

 private:
  bool split_;  // the LL^T in domains side by side (cholmod_split.hpp)
  SolverMemory memory_;
  bool factorize_fallback(const SpMat& a) {
    if (!fallback_) {
      if (mumps_available()) {
        MumpsOptions o = spilling_mumps(memory_);
        o.pivot_order = cholmod_pivot_order(*llt_);
        fallback_ = make_mumps(o);
      } else if (a.rows() > kSimplicialLimit) {
        fallback_ = make_umfpack(true);
      } else {
        fallback_ = make_cholmod_ldlt(memory_.limit_megabytes);
      }
      fallback_->analyze(a);
    }
    current_ = fallback_.get();
    if (fallback_->factorize(a)) return true;
    if (fallback_->name() != "ldlt") return false;
    fallback_ = make_umfpack(true);  // LDL^T without pivoting can fail where LU does not
    fallback_->analyze(a);
    current_ = fallback_.get();
    return fallback_->factorize(a);
  }

  std::unique_ptr<LinearSolver> llt_, fallback_;
  LinearSolver* current_ = nullptr;
  bool fallback_first_ = false;  // the last matrix was indefinite (by the fallback's count)
  bool step_starts_ = false;     // begin_step() was called: the next matrix is a step's first
  bool step_start_indefinite_ = false;  // the last step's first matrix was indefinite
};

// For a model that cannot promise symmetry (point moments: Eq. (54)'s load stiffness is unsymmetric in
// general) but whose tangent may still be symmetric in the case at hand (a moment about a fixed axis on a
// beam kept in a plane: M . delta omega is then the variation of M theta). The values are compared with
// their mirror entries before every factorisation, through a map built at analyze() (of the rows that
// set_skew_candidates() names, else of the whole matrix), and the symmetric chain (AutoSolver, or a MUMPS
// LDL^T for approximate or out-of-core factorisations) is used while the matrix is symmetric to round-off.
// An unsymmetric matrix whose skew part lives on at most kMaxSkewRows rows (the end control points of
// beams under point moments) is solved through the same chain's factorisation of its symmetric part and an
// exact low-rank correction (SkewCorrection); any other, or one where that fails, takes the LU.
class SymmetryProbingSolver final : public LinearSolver {
 public:
  using Factory = std::function<std::unique_ptr<LinearSolver>()>;
  SymmetryProbingSolver(Factory symmetric_chain, Factory lu)
      : make_symmetric_(std::move(symmetric_chain)), make_lu_(std::move(lu)) {}
  void analyze(const SpMat& a) override {
    if (candidates_) probe_.build(a, *candidates_);
    else probe_.build(a);
    pick(a, choose(a), true);
  }
  bool factorize_numeric(const SpMat& a) override {
    // analyze() is the caller's duty on a new pattern; a matrix of another size is re-analysed here.
    if (!current_ || (probe_.structurally_symmetric() && probe_.size() != a.nonZeros())) analyze(a);
    pick(a, choose(a), false);
    if (std::exchange(step_starts_, false) && path_ != Path::lu) current_->begin_step();
    if (path_ == Path::skew) {
      if (factorize_symmetric_part(a) && correction_.prepare(*current_)) return true;
      pick(a, Path::lu, false);  // S indefinite beyond the chain, or singular: this matrix goes to the LU
    }
    return current_->factorize(a);
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const override {
    return path_ == Path::skew ? correction_.apply(current_->solve(b)) : current_->solve(b);
  }
  Eigen::MatrixXd solve_columns(const Eigen::MatrixXd& b) const override {
    Eigen::MatrixXd x = current_->solve_columns(b);
    if (path_ == Path::skew)
      for (Eigen::Index j = 0; j < x.cols(); ++j) x.col(j) = correction_.apply(x.col(j));
    return x;
  }
  std::string name() const override {
    const std::string inner = current_ ? current_->name() : "auto(none)";
    if (path_ == Path::skew) return "symmetric-part(" + inner + ")+rank-" + std::to_string(correction_.rank());
    return (path_ == Path::symmetric ? "symmetric-" : "") + inner;
  }
  long factor_nonzeros() const override { return current_ ? current_->factor_nonzeros() : 0; }
  // The chain's factor goes; the LU, analysis and all, unless it is the current solver (which names the
  // path until the next factorisation).
  void release_factor() override {
    if (lu_ && current_ != lu_.get()) lu_.reset();
    if (symmetric_chain_) symmetric_chain_->release_factor();
  }
  long held_factor_entries() const override {
    return (symmetric_chain_ ? symmetric_chain_->held_factor_entries() : 0) + (lu_ ? lu_->held_factor_entries() : 0);
  }
  std::string analysis_summary() const override { return current_ ? current_->analysis_summary() : ""; }
  // The symmetric part's inertia is not the matrix's.
  int negative_eigenvalues() const override {
    return current_ && path_ != Path::skew ? current_->negative_eigenvalues() : -1;
  }
  bool exact() const override { return current_ ? current_->exact() : true; }
  std::string failure_detail() const override { return current_ ? current_->failure_detail() : ""; }
  // Passed on to the symmetric chain with the step's first matrix, once its path is known (the chain is
  // made at the first analysis, after Newton's first begin_step()).
  void begin_step() override { step_starts_ = true; }
  void set_skew_candidates(std::optional<std::vector<int>> rows) override { candidates_ = std::move(rows); }

 private:
  enum class Path { symmetric, skew, lu };
  // The path for a (support_ set for the skew path).
  Path choose(const SpMat& a) {
    support_ = probe_.skew_support(a);
    if (support_.empty() && probe_.structurally_symmetric() && probe_.size() == a.nonZeros()) return Path::symmetric;
    return !support_.empty() && support_.size() <= static_cast<size_t>(kMaxSkewRows) ? Path::skew : Path::lu;
  }
  // The chain's factorisation of S (SkewCorrection::symmetrize), written into a's own storage: a's values
  // in the skew rows' block are changed for the call and put back before this returns, also when the
  // chain throws. No solver keeps a reference to a matrix's values past its factorize().
  bool factorize_symmetric_part(const SpMat& a) {
    auto& k = const_cast<SpMat&>(a);  // the caller's matrix: its values are the same on return
    if (!correction_.symmetrize(k, support_)) return false;
    struct Restore {
      const SkewCorrection& correction;
      SpMat& k;
      ~Restore() { correction.restore(k); }
    } restore{correction_, k};
    return current_->factorize(k);
  }
  // Makes `path` current, analysing its solver if it is another one than before or `analyse` is set. The
  // symmetric chain (with its ordering) serves the symmetric and skew paths. One factor at a time: the
  // chain's factor is freed (its analysis kept) while the LU is in use, and the LU goes, analysis and all,
  // when the chain takes over again.
  void pick(const SpMat& a, Path path, bool analyse) {
    const bool was_lu = current_ && current_ == lu_.get();
    const bool switched = !current_ || was_lu != (path == Path::lu);
    path_ = path;
    if (path != Path::lu) {
      lu_.reset();
      if (!symmetric_chain_) symmetric_chain_ = make_symmetric_();
      current_ = symmetric_chain_.get();
    } else {
      if (symmetric_chain_ && !was_lu) symmetric_chain_->release_factor();
      if (!lu_) lu_ = make_lu_();
      current_ = lu_.get();
    }
    if (path != Path::skew) correction_.clear();
    if (analyse || switched) current_->analyze(a);  // hands the freed factor back (direct_solvers.hpp)
  }

  Factory make_symmetric_, make_lu_;
  SymmetryProbe probe_;
  std::optional<std::vector<int>> candidates_;  // the rows the probe compares (nullopt: all)
  Path path_ = Path::lu;
  std::vector<int> support_;
  SkewCorrection correction_;
  bool step_starts_ = false;  // begin_step() was called: the next matrix is a step's first
  std::unique_ptr<LinearSolver> symmetric_chain_, lu_;
  LinearSolver* current_ = nullptr;
};

}  // namespace

bool LinearSolver::needs_analysis(const SpMat& a, int pattern_version) const {
  return pattern_version != analyzed_version_ || a.rows() != analyzed_rows_ || a.nonZeros() != analyzed_nonzeros_;
}

bool LinearSolver::analyze_if_needed(const SpMat& a, int pattern_version) {
  if (!needs_analysis(a, pattern_version)) return false;
  analyze(a);
  analyzed_version_ = pattern_version;
  analyzed_rows_ = a.rows();
  analyzed_nonzeros_ = a.nonZeros();
  return true;
}

namespace {

// The LU of "auto" for unsymmetric matrices, and of "mumps-lu".
std::unique_ptr<LinearSolver> make_lu(MumpsOptions options) {
  if (!mumps_available()) return make_umfpack(true);
  options.unsymmetric = true;
  options.cholmod_ordering = true;
  return make_mumps(options);
}

}  // namespace

std::unique_ptr<LinearSolver> make_linear_solver(const std::string& kind, bool symmetric, bool split,
                                                 const SolverMemory& memory) {
  const MumpsOptions spill = spilling_mumps(memory);
  if (kind == "umfpack") return make_umfpack();
  if (kind == "umfpack64") return make_umfpack(true);
  if (kind == "mumps-lu") {
    if (!mumps_available()) throw InputError("linear solver 'mumps-lu': this fibrane was built without MUMPS");
    return make_lu(spill);
  }
  if (kind == "auto") {
    if (!symmetric)
      return std::make_unique<SymmetryProbingSolver>(
          [split, memory] { return std::make_unique<AutoSolver>(split, memory); }, [spill] { return make_lu(spill); });
    return std::make_unique<AutoSolver>(split, memory);
  }
  if (kind == "cholmod" || kind == "ldlt" || kind == "mumps") {
    if (!symmetric)
      throw InputError("linear solver '" + kind + "' needs a symmetric matrix; use 'auto', 'mumps-lu' or 'umfpack'");
    if (kind == "cholmod")
      return split ? make_cholmod_split_llt({.memory_limit_megabytes = memory.limit_megabytes})
                   : make_cholmod_llt(memory.limit_megabytes);
    if (kind == "ldlt") return make_cholmod_ldlt(memory.limit_megabytes);
    if (!mumps_available()) throw InputError("linear solver 'mumps': this fibrane was built without MUMPS");
    return make_mumps(spill);
  }
  throw InputError("unknown linear solver '" + kind +
                   "' (expected auto, cholmod, ldlt, mumps, mumps-lu, umfpack or umfpack64)");
}

namespace {

// The direct solver of `settings`; with approximate = false, its exact counterpart (double precision,
// full rank) for the same path. Out of core where the settings say so, exact or not.
std::unique_ptr<LinearSolver> make_direct(const LinearSolverSettings& settings, bool symmetric, bool approximate) {
  const bool when_needed = settings.out_of_core_when_needed;
  const bool out_of_core = !settings.out_of_core_directory.empty() && !when_needed;
  if (!approximate && !out_of_core)
    return make_linear_solver(settings.kind, symmetric, settings.split,
                              {.limit_megabytes = settings.memory_limit_megabytes,
                               .spill_directory = when_needed ? settings.out_of_core_directory : std::string()});
  const std::string what = !approximate ? "out_of_core" : settings.low_rank > 0 ? "low_rank" : "precision: single";
  if (!mumps_available()) throw InputError("'" + what + "' needs MUMPS, and this fibrane was built without it");
  MumpsOptions o;
  o.cholmod_ordering = true;
  o.single_precision = approximate && settings.precision == "single";
  o.low_rank = approximate && settings.low_rank > 0;
  o.low_rank_tolerance = settings.low_rank;
  o.out_of_core_directory = settings.out_of_core_directory;
  o.out_of_core_when_needed = when_needed;
  o.memory_limit_megabytes = settings.memory_limit_megabytes;
  if (settings.kind == "mumps-lu") return make_lu(o);
  if (settings.kind == "mumps" || settings.kind == "auto") {
    if (symmetric) return make_mumps(o);
    if (settings.kind == "auto")
      return std::make_unique<SymmetryProbingSolver>([o] { return make_mumps(o); }, [o] { return make_lu(o); });
    throw InputError("linear solver 'mumps' needs a symmetric matrix; use 'auto' or 'mumps-lu'");
  }
  throw InputError("'" + what + "' is a MUMPS factorisation: it needs solver auto, mumps or mumps-lu, not '" +
                   settings.kind + "'");
}

}  // namespace

std::unique_ptr<LinearSolver> make_linear_solver(const LinearSolverSettings& settings, bool symmetric) {
  const bool approximate = settings.precision == "single" || settings.low_rank > 0;
  std::unique_ptr<LinearSolver> direct = make_direct(settings, symmetric, approximate);
  if (!settings.krylov && !approximate) return direct;
  KrylovReuseOptions k;
  k.tolerance = settings.krylov_tolerance;
  k.max_iterations = settings.krylov_max_iterations;
  k.verbose = settings.verbose;
  KrylovReuseSolver::Factory exact;
  if (approximate) exact = [settings, symmetric] { return make_direct(settings, symmetric, false); };
  return std::make_unique<KrylovReuseSolver>(std::move(direct), k, symmetric, std::move(exact));
}

}  // namespace fibrane::solve
