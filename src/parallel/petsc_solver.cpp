#include "parallel/petsc_solver.hpp"

#include <malloc.h>
#include <petscksp.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "parallel/row_pattern.hpp"
#include "linalg/symmetry_probe.hpp"

namespace fibrane::parallel {
namespace {

using SpMat = Eigen::SparseMatrix<double>;
using Clock = std::chrono::steady_clock;

void check(PetscErrorCode code, const char* what) {
  if (code != 0) throw std::runtime_error(std::string("PETSc: ") + what + " failed (error " + std::to_string(code) + ")");
}
#define FIBRANE_PETSC(call) check((call), #call)

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// The summand in the solver's numbering: B(row(i), row(j)) = A(i, j), each column's rows sorted. `a`
// itself when the numbering is the model's, else `storage`, which then holds B.
const SpMat& in_solver_rows(const SpMat& a, const solve::UnknownOwnership& o, SpMat& storage) {
  if (o.identity()) return a;
  if (o.unknowns() != a.rows()) throw std::logic_error("PETSc solver: the unknowns' owners do not match the tangent's size");
  const int n = static_cast<int>(a.cols());
  storage.resize(n, n);
  storage.resizeNonZeros(a.nonZeros());
  int* outer = storage.outerIndexPtr();
  outer[0] = 0;
  for (int r = 0; r < n; ++r) {
    const int j = o.unknown(r);
    outer[r + 1] = outer[r] + (a.outerIndexPtr()[j + 1] - a.outerIndexPtr()[j]);
  }
  std::vector<std::pair<int, double>> column;
  for (int r = 0; r < n; ++r) {
    column.clear();
    const int j = o.unknown(r);
    for (SpMat::InnerIterator it(a, j); it; ++it) column.emplace_back(o.row(static_cast<int>(it.index())), it.value());
    std::sort(column.begin(), column.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    for (std::size_t k = 0; k < column.size(); ++k) {
      storage.innerIndexPtr()[outer[r] + static_cast<int>(k)] = column[k].first;
      storage.valuePtr()[outer[r] + static_cast<int>(k)] = column[k].second;
    }
  }
  return storage;
}

// Eigen's and PETSc's index types must agree: the summand's index arrays go to MatSetValues as they are.
static_assert(sizeof(PetscInt) == sizeof(int) && sizeof(PetscScalar) == sizeof(double),
              "fibrane's PETSc solver expects 32-bit PetscInt and real double PetscScalar");

class PetscSolver final : public solve::LinearSolver {
 public:
  PetscSolver(const PetscSolverOptions& options, bool symmetric, const MpiDistribution& d,
              const solve::UnknownOwnership& ownership)
      : options_(options), symmetric_model_(symmetric), d_(d), own_(ownership) {}
  ~PetscSolver() override { release(); }
  PetscSolver(const PetscSolver&) = delete;
  PetscSolver& operator=(const PetscSolver&) = delete;

  void analyze(const SpMat& a) override;
  bool factorize_numeric(const SpMat& a) override;
  bool factorize_exactly(const SpMat& a) override;
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const override;
  std::string name() const override;
  long factor_nonzeros() const override;
  std::string analysis_summary() const override;
  int negative_eigenvalues() const override { return negative_; }
  void set_skew_candidates(std::optional<std::vector<int>> rows) override { candidates_ = std::move(rows); }

 private:
  void set_matrix(const SpMat& a);     // analyze() for a new size or symmetry, then set_values()
  void reset_solver();                 // a new KSP and MUMPS instance (the next factorisation analyses afresh)
  void drop_low_rank();                // full-rank factorisations from now on
  void release();                      // destroys the matrix, the KSP and the vectors
  void create_matrix(const SpMat& b);  // exact preallocation from the summands' patterns (solver rows)
  void create_solver();                // KSP, MUMPS settings, vectors
  void set_values(const SpMat& b);     // the sum of the summands' values (solver rows) into the matrix
  bool factor();                       // MUMPS on the current values; false if it failed
  Mat factor_matrix() const;
  int infog(int i) const;

  PetscSolverOptions options_;
  bool symmetric_model_;
  const MpiDistribution& d_;
  const solve::UnknownOwnership& own_;
  Mat a_ = nullptr;
  KSP ksp_ = nullptr;
  Vec b_ = nullptr, x_ = nullptr, x_all_ = nullptr;
  VecScatter to_all_ = nullptr;
  solve::SymmetryProbe probe_;
  std::optional<std::vector<int>> candidates_;  // set_skew_candidates()'s: the rows the probe compares
  bool cholesky_ = true;      // SBAIJ + LDL^T; otherwise AIJ + LU
  bool factored_ = false;     // the KSP holds a factorisation (possibly of an earlier tangent)
  bool fresh_ = false;        // ... of the matrix's current values
  mutable bool stale_ = false;  // a solve needed more than max_iterations: factorise the next tangent
  int negative_ = -1, analyses_ = 0, workspace_percent_ = 0;
  mutable int factorizations_ = 0, solves_ = 0, krylov_iterations_ = 0;
  mutable double set_seconds_ = 0, factor_seconds_ = 0, solve_seconds_ = 0;
};

void PetscSolver::release() {
  KSPDestroy(&ksp_);
  MatDestroy(&a_);
  VecDestroy(&b_);
  VecDestroy(&x_);
  VecDestroy(&x_all_);
  VecScatterDestroy(&to_all_);
  factored_ = fresh_ = false;
  negative_ = -1;
}

void PetscSolver::analyze(const SpMat& a) {
  release();
  // fibrane keeps freed memory in the process (run/process_environment.cpp: fewer page faults per
  // iteration); a new pattern's factor is larger and rarely fits the old one's place, so the freed
  // matrix and factor are handed back here, before the new ones are made, instead of adding to the peak.
  malloc_trim(0);
  cholesky_ = symmetric_model_ && !options_.lu;
  if (!symmetric_model_ && !options_.lu) {
    if (candidates_) probe_.build(a, *candidates_);
    else probe_.build(a);
    cholesky_ = d_.all(probe_.symmetric(a));
  }
  SpMat storage;
  create_matrix(in_solver_rows(a, own_, storage));
  create_solver();
  ++analyses_;
}

void PetscSolver::create_matrix(const SpMat& a) {
  const RowPattern rows = owned_rows(a, cholesky_, own_, d_);
  const int first = rows.first, end = rows.first + rows.rows();
  std::vector<PetscInt> diagonal(static_cast<size_t>(rows.rows()), 0), off(static_cast<size_t>(rows.rows()), 0);
  for (int r = 0; r < rows.rows(); ++r)
    for (int k = rows.begin[static_cast<size_t>(r)]; k < rows.begin[static_cast<size_t>(r) + 1]; ++k) {
      const int c = rows.columns[static_cast<size_t>(k)];
      ++(c >= first && c < end ? diagonal : off)[static_cast<size_t>(r)];
    }
  const PetscInt n = static_cast<PetscInt>(a.rows());
  FIBRANE_PETSC(MatCreate(d_.comm(), &a_));
  FIBRANE_PETSC(MatSetSizes(a_, end - first, end - first, n, n));
  FIBRANE_PETSC(MatSetType(a_, cholesky_ ? MATSBAIJ : MATAIJ));
  FIBRANE_PETSC(MatXAIJSetPreallocation(a_, 1, diagonal.data(), off.data(), diagonal.data(), off.data()));
  // The whole pattern now, as zeros: the assemblies then only add values, and an entry outside the
  // pattern would be an error instead of a silent reallocation.
  std::vector<PetscScalar> zeros;
  for (int r = 0; r < rows.rows(); ++r) {
    const PetscInt row = first + r;
    const int b = rows.begin[static_cast<size_t>(r)], count = rows.begin[static_cast<size_t>(r) + 1] - b;
    zeros.assign(static_cast<size_t>(count), 0.0);
    FIBRANE_PETSC(MatSetValues(a_, 1, &row, count, rows.columns.data() + b, zeros.data(), INSERT_VALUES));
  }
  FIBRANE_PETSC(MatAssemblyBegin(a_, MAT_FINAL_ASSEMBLY));
  FIBRANE_PETSC(MatAssemblyEnd(a_, MAT_FINAL_ASSEMBLY));
  FIBRANE_PETSC(MatSetOption(a_, MAT_NEW_NONZERO_LOCATION_ERR, PETSC_TRUE));
}

void PetscSolver::create_solver() {
  FIBRANE_PETSC(KSPCreate(d_.comm(), &ksp_));
  FIBRANE_PETSC(KSPSetOperators(ksp_, a_, a_));
  if (options_.low_rank > 0 && options_.method != PetscSolverOptions::Method::gmres)
    throw std::logic_error("PETSc solver: block low-rank factorisations need GMRES to refine them");
  if (options_.method == PetscSolverOptions::Method::gmres) {
    const PetscInt limit = 3 * options_.max_iterations;
    FIBRANE_PETSC(KSPSetType(ksp_, KSPGMRES));
    FIBRANE_PETSC(KSPGMRESSetRestart(ksp_, limit));
    FIBRANE_PETSC(KSPSetPCSide(ksp_, PC_RIGHT));
    FIBRANE_PETSC(KSPSetNormType(ksp_, KSP_NORM_UNPRECONDITIONED));
    FIBRANE_PETSC(KSPSetTolerances(ksp_, options_.relative_tolerance, PETSC_DEFAULT, PETSC_DEFAULT, limit));
  } else {
    FIBRANE_PETSC(KSPSetType(ksp_, KSPPREONLY));
  }
  PC pc;
  FIBRANE_PETSC(KSPGetPC(ksp_, &pc));
  FIBRANE_PETSC(PCSetType(pc, cholesky_ ? PCCHOLESKY : PCLU));
  FIBRANE_PETSC(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  FIBRANE_PETSC(PCFactorSetUpMatSolverType(pc));
  Mat f = factor_matrix();
  // The negative-eigenvalue count of a parallel LDL^T needs the root front outside ScaLAPACK.
  if (cholesky_ && d_.size() > 1) FIBRANE_PETSC(MatMumpsSetIcntl(f, 13, 1));
  if (workspace_percent_ > 0) FIBRANE_PETSC(MatMumpsSetIcntl(f, 14, workspace_percent_));
  if (options_.low_rank > 0) {
    FIBRANE_PETSC(MatMumpsSetIcntl(f, 35, 2));  // block low-rank factors, used in the solves too
    FIBRANE_PETSC(MatMumpsSetCntl(f, 7, options_.low_rank));
  }
  if (!options_.out_of_core_directory.empty()) {
    // PETSc leaves MUMPS's OOC_TMPDIR and OOC_PREFIX unset, and MUMPS then reads these variables when it
    // opens its files (each process's names carry its MUMPS rank as well).
    ::setenv("MUMPS_OOC_TMPDIR", options_.out_of_core_directory.c_str(), 1);
    ::setenv("MUMPS_OOC_PREFIX", ("fibrane-" + std::to_string(::getpid()) + "-").c_str(), 1);
    FIBRANE_PETSC(MatMumpsSetIcntl(f, 22, 1));
  }
  FIBRANE_PETSC(KSPSetFromOptions(ksp_));
  FIBRANE_PETSC(MatCreateVecs(a_, &x_, &b_));
  FIBRANE_PETSC(VecScatterCreateToAll(x_, &to_all_, &x_all_));
}

Mat PetscSolver::factor_matrix() const {
  PC pc;
  Mat f;
  FIBRANE_PETSC(KSPGetPC(ksp_, &pc));
  FIBRANE_PETSC(PCFactorGetMatrix(pc, &f));
  return f;
}

int PetscSolver::infog(int i) const {
  PetscInt value = 0;
  FIBRANE_PETSC(MatMumpsGetInfog(factor_matrix(), i, &value));
  return static_cast<int>(value);
}

// The summand's rows go to PETSc whole: row j of the upper triangle is column j's rows i >= j (SBAIJ);
// for AIJ the rows come from RowRounds. Entries of other processes' rows wait in PETSc's stash until an
// assembly sends them; sending them in kStashRounds rounds of rows (every process the same rounds: the
// flush is collective) bounds the stash to a fraction of the summand's entries in other rows.
void PetscSolver::set_values(const SpMat& a) {
  constexpr int kStashRounds = 8;
  const auto start = Clock::now();
  FIBRANE_PETSC(MatZeroEntries(a_));
  const int* outer = a.outerIndexPtr();
  const int* inner = a.innerIndexPtr();
  const double* values = a.valuePtr();
  const int n = static_cast<int>(a.cols());
  const int per_round = (n + kStashRounds - 1) / kStashRounds;
  RowRounds rounds(a);
  for (int first = 0; first < n; first += per_round) {
    if (first > 0) {
      FIBRANE_PETSC(MatAssemblyBegin(a_, MAT_FLUSH_ASSEMBLY));
      FIBRANE_PETSC(MatAssemblyEnd(a_, MAT_FLUSH_ASSEMBLY));
    }
    const int end = std::min(n, first + per_round);
    if (cholesky_) {
      for (PetscInt j = first; j < end; ++j) {
        const int* e = inner + outer[j + 1];
        const int* b = std::lower_bound(inner + outer[j], e, static_cast<int>(j));
        if (b != e) FIBRANE_PETSC(MatSetValues(a_, 1, &j, static_cast<PetscInt>(e - b), b, values + (b - inner), ADD_VALUES));
      }
      continue;
    }
    const RowPattern& rows = rounds.next(end);
    for (int r = 0; r < rows.rows(); ++r) {
      const PetscInt row = first + r;
      const int b = rows.begin[static_cast<size_t>(r)], count = rows.begin[static_cast<size_t>(r) + 1] - b;
      if (count > 0) FIBRANE_PETSC(MatSetValues(a_, 1, &row, count, rows.columns.data() + b, rounds.values().data() + b, ADD_VALUES));
    }
  }
  FIBRANE_PETSC(MatAssemblyBegin(a_, MAT_FINAL_ASSEMBLY));
  FIBRANE_PETSC(MatAssemblyEnd(a_, MAT_FINAL_ASSEMBLY));
  set_seconds_ += seconds_since(start);
}

// PETSc's MUMPS interface skips the numeric factorisation of an instance whose last MUMPS call failed
// (it takes that for a failed analysis), so a failure discards the KSP and its MUMPS instance: the next
// factorisation analyses afresh. A full work space (INFOG(1) = -8, -9: more delayed pivots than the
// analysis foresaw) is retried with ICNTL(14) doubled, up to three times, as the serial MUMPS solver does.
bool PetscSolver::factor() {
  for (int attempt = 0;; ++attempt) {
    const auto start = Clock::now();
    PC pc;
    FIBRANE_PETSC(KSPGetPC(ksp_, &pc));
    FIBRANE_PETSC(PCSetReusePreconditioner(pc, PETSC_FALSE));
    FIBRANE_PETSC(KSPSetUp(ksp_));
    // KSPSetUp sets up the preconditioner only once per KSP; PCSetUp factorises the matrix's new values
    // here (and not later, inside KSPSolve), so that the error check and the inertia below are this
    // factorisation's.
    FIBRANE_PETSC(PCSetUp(pc));
    MatFactorError error;
    FIBRANE_PETSC(MatFactorGetError(factor_matrix(), &error));
    const bool ok = d_.all(error == MAT_FACTOR_NOERROR);
    const int status = infog(1);
    factor_seconds_ += seconds_since(start);
    if (ok) {
      ++factorizations_;
      factored_ = fresh_ = true;
      stale_ = false;
      PetscInt negative = -1;
      if (cholesky_) FIBRANE_PETSC(MatGetInertia(factor_matrix(), &negative, nullptr, nullptr));
      negative_ = static_cast<int>(negative);
      return true;
    }
    const bool workspace = status == -8 || status == -9;
    if (workspace) workspace_percent_ = std::max(workspace_percent_, 20) * 2;
    reset_solver();
    if (!workspace || attempt == 3) return false;
  }
}

void PetscSolver::set_matrix(const SpMat& a) {
  PetscInt rows = -1;
  if (a_) FIBRANE_PETSC(MatGetSize(a_, &rows, nullptr));
  if (rows != static_cast<PetscInt>(a.rows())) analyze(a);  // analyze() is the caller's duty; a new size is caught
  else if (!symmetric_model_ && !options_.lu && d_.all(probe_.symmetric(a)) != cholesky_) analyze(a);  // the symmetry changed
  SpMat storage;
  set_values(in_solver_rows(a, own_, storage));
}

bool PetscSolver::factorize_numeric(const SpMat& a) {
  set_matrix(a);
  // GMRES keeps an earlier factorisation as its preconditioner; solve() refactorises when it does not do.
  if (options_.method == PetscSolverOptions::Method::gmres && factored_ && !stale_) {
    PC pc;
    FIBRANE_PETSC(KSPGetPC(ksp_, &pc));
    FIBRANE_PETSC(PCSetReusePreconditioner(pc, PETSC_TRUE));
    fresh_ = false;
    negative_ = -1;  // the factorisation belongs to an earlier tangent
    return true;
  }
  return factor();
}

void PetscSolver::reset_solver() {
  KSPDestroy(&ksp_);
  VecDestroy(&b_);
  VecDestroy(&x_);
  VecDestroy(&x_all_);
  VecScatterDestroy(&to_all_);
  create_solver();
  ++analyses_;  // the new MUMPS instance analyses at its first factorisation
  factored_ = fresh_ = false;
  negative_ = -1;
}

void PetscSolver::drop_low_rank() {
  options_.low_rank = 0;
  reset_solver();
}

// For callers that need this matrix's inertia (arc-length's sign rule): always a factorisation of it.
bool PetscSolver::factorize_exactly(const SpMat& a) {
  set_matrix(a);
  return factor();
}

Eigen::VectorXd PetscSolver::solve(const Eigen::VectorXd& b) const {
  const Eigen::Index n = b.size();
  if (!factored_ || !ksp_) return Eigen::VectorXd::Constant(n, std::numeric_limits<double>::quiet_NaN());
  const auto start = Clock::now();
  PetscInt first = 0, end = 0;
  FIBRANE_PETSC(VecGetOwnershipRange(b_, &first, &end));
  PetscScalar* local = nullptr;
  FIBRANE_PETSC(VecGetArray(b_, &local));
  for (PetscInt r = first; r < end; ++r) local[r - first] = b[own_.unknown(static_cast<int>(r))];
  FIBRANE_PETSC(VecRestoreArray(b_, &local));
  FIBRANE_PETSC(KSPSolve(ksp_, b_, x_));
  KSPConvergedReason reason;
  FIBRANE_PETSC(KSPGetConvergedReason(ksp_, &reason));
  PetscInt iterations = 0;
  FIBRANE_PETSC(KSPGetIterationNumber(ksp_, &iterations));
  krylov_iterations_ += static_cast<int>(iterations);
  if (iterations > options_.max_iterations) stale_ = true;
  if (reason < 0 && (!fresh_ || options_.low_rank > 0)) {
    // GMRES with an earlier tangent's factorisation did not converge: factorise this tangent. With a
    // fresh block low-rank factorisation that GMRES could not refine, factorise it in full from now on.
    solve_seconds_ += seconds_since(start);
    auto* self = const_cast<PetscSolver*>(this);
    if (fresh_) self->drop_low_rank();
    if (!self->factor()) return Eigen::VectorXd::Constant(n, std::numeric_limits<double>::quiet_NaN());
    return solve(b);
  }
  ++solves_;
  Eigen::VectorXd x(n);
  if (reason < 0) {
    x.setConstant(std::numeric_limits<double>::quiet_NaN());
  } else {
    FIBRANE_PETSC(VecScatterBegin(to_all_, x_, x_all_, INSERT_VALUES, SCATTER_FORWARD));
    FIBRANE_PETSC(VecScatterEnd(to_all_, x_, x_all_, INSERT_VALUES, SCATTER_FORWARD));
    const PetscScalar* all = nullptr;
    FIBRANE_PETSC(VecGetArrayRead(x_all_, &all));
    for (int r = 0; r < static_cast<int>(n); ++r) x[own_.unknown(r)] = all[r];
    FIBRANE_PETSC(VecRestoreArrayRead(x_all_, &all));
  }
  solve_seconds_ += seconds_since(start);
  return x;
}

std::string PetscSolver::name() const {
  const std::string mumps = std::string("mumps-") + (cholesky_ ? "ldlt" : "lu") + (options_.low_rank > 0 ? "-blr" : "") +
                            (options_.out_of_core_directory.empty() ? "" : "-ooc");
  const std::string kind = options_.method == PetscSolverOptions::Method::gmres ? "gmres(" + mumps + ")" : mumps;
  return "petsc-" + kind + (d_.size() > 1 ? fmt::format(" on {} processes", d_.size()) : "");
}

// INFOG(29): entries in the factors (negative: millions); before a factorisation the analysis's
// estimate INFOG(20).
long PetscSolver::factor_nonzeros() const {
  if (!ksp_ || !factored_) return 0;
  const int value = infog(29);
  return value >= 0 ? value : -1000000L * value;
}

std::string PetscSolver::analysis_summary() const {
  if (!ksp_ || !factored_) return fmt::format("{} analyses", analyses_);
  static const char* const orderings[] = {"AMD", "the given order", "AMF", "SCOTCH", "PORD", "METIS", "QAMD"};
  const int ordering = infog(7);
  const std::string method = ordering >= 0 && ordering <= 6 ? orderings[ordering] : fmt::format("ordering {}", ordering);
  // INFOG(21) / INFOG(22): the largest memory one process / all processes used in the factorisation (MB).
  return fmt::format("{} analyses with {} ({}), {} factorisations, {} solves, {} Krylov iterations; largest process "
                     "{} MB, all {} MB; times: values {:.3g} s, factorisations {:.3g} s, solves {:.3g} s",
                     analyses_, method, infog(32) == 2 ? "parallel" : "sequential", factorizations_, solves_,
                     krylov_iterations_, infog(21), infog(22), set_seconds_, factor_seconds_, solve_seconds_);
}

}  // namespace

std::unique_ptr<solve::LinearSolver> make_petsc_solver(const PetscSolverOptions& options, bool symmetric,
                                                       const MpiDistribution& distribution,
                                                       const solve::UnknownOwnership& ownership) {
  return std::make_unique<PetscSolver>(options, symmetric, distribution, ownership);
}

}  // namespace fibrane::parallel
