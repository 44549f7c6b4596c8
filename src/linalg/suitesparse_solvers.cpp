// CHOLMOD (supernodal LL^T, simplicial LDL^T) and UMFPACK (LU) through Eigen's wrappers.
#include <Eigen/CholmodSupport>
#include <Eigen/UmfPackSupport>

#include <cmath>
#include <string>
#include <type_traits>

#include "linalg/cholmod_permuted_lower.hpp"
#include "linalg/cholmod_split.hpp"
#include "linalg/direct_solvers.hpp"

namespace fibrane::solve {
namespace {

using SpMat = Eigen::SparseMatrix<double>;

// Eigen's CHOLMOD wrapper with its factor (cholmod_factor) readable.
template <class Factorization>
struct ReadableFactor : Factorization {
  cholmod_factor* factor() const { return this->m_cholmodFactor; }
  // The supernodal numeric factorisation of s, the permuted lower triangle that cholmod_factorize would
  // build (CholmodPermutedLower), with the state Eigen's factorize() leaves.
  void factorize_permuted(cholmod_sparse* s) {
    cholmod_factor* f = this->m_cholmodFactor;
    const SerialLibraryRegions serial;
    const int ok = cholmod_super_numeric(s, nullptr, this->m_shiftOffset, f, &this->cholmod());
    this->m_info = ok && this->cholmod().status >= CHOLMOD_OK && f->minor == f->n ? Eigen::Success
                                                                                   : Eigen::NumericalIssue;
    this->m_factorizationIsOk = true;
  }
};

template <class Factorization>
constexpr bool kSupernodal = std::is_same_v<Factorization, Eigen::CholmodSupernodalLLT<SpMat, Eigen::Lower>>;

// Negative entries of D in a simplicial LDL^T factor. CHOLMOD stores the factor column by column
// (cholmod_factor: p = column starts, x = values); in a simplicial LDL^T factor (is_ll = 0,
// is_super = 0) the first entry of column j is the diagonal of L's column j, which holds D(j, j) (L's
// unit diagonal is implicit). An LL^T factor exists only for a positive definite matrix: 0.
int negative_pivots(const cholmod_factor& f) {
  if (f.is_ll) return 0;
  const auto* p = static_cast<const int*>(f.p);
  const auto* x = static_cast<const double*>(f.x);
  int negative = 0;
  for (size_t j = 0; j < f.n; ++j)
    if (x[p[j]] < 0) ++negative;
  return negative;
}

// CHOLMOD factorisations (lower triangle of a symmetric matrix), remembering which fill-reducing ordering
// won. CHOLMOD's default tries AMD and, where AMD's fill is high, METIS too, and keeps the better; a model's
// later patterns differ from the first only by the beam-shell coupling, so later analyses run only the method
// that won the first. At the bending example's paper mesh METIS wins (1 % less fill than AMD), and the later
// analyses are the faster for it (docs/performance.md, "Linear solver"). (Keeping the previous permutation
// itself for a new pattern was measured too: after a change of the coupling its factor was 4-10 % larger than
// a fresh ordering's, which costs more in the factorisations than the ordering does.)
template <class Factorization>
class CholmodSolver final : public LinearSolver {
 public:
  CholmodSolver(std::string name, long memory_limit_megabytes)
      : name_(std::move(name)), memory_limit_(memory_limit_megabytes) {
    fact_.cholmod().print = 0;  // failures are reported through factorize()'s return value
  }
  void analyze(const SpMat& a) override {
    cholmod_common& common = fact_.cholmod();
    if (chosen_ >= 0) {
      common.nmethods = 1;
      common.method[0].ordering = chosen_;
    }
    permuted_.clear();
    fact_.analyzePattern(a);  // frees the last factor
    hand_back_freed_memory();
    if (chosen_ < 0 && fact_.info() == Eigen::Success) chosen_ = common.method[common.selected].ordering;
    ++analyses_;
    negative_ = -1;
  }
  bool factorize_numeric(const SpMat& a) override {
    negative_ = -1;
    refusal_ = memory_refusal();
    if (!refusal_.empty()) return false;
    const BlasThreadsForFactor threads(static_cast<long>(fact_.cholmod().lnz));
    factorize_values(a);
    const bool ok = fact_.info() == Eigen::Success;
    negative_ = ok ? negative_pivots(*fact_.factor()) : -1;
    return ok;
  }
  std::string failure_detail() const override { return refusal_; }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const override {
    const BlasThreadsForFactor threads(static_cast<long>(fact_.cholmod().lnz));
    return fact_.solve(b);
  }
  Eigen::MatrixXd solve_columns(const Eigen::MatrixXd& b) const override {
    const BlasThreadsForFactor threads(static_cast<long>(fact_.cholmod().lnz));
    return fact_.solve(b);
  }
  std::string name() const override { return name_; }
  long factor_nonzeros() const override { return static_cast<long>(fact_.cholmod().lnz); }
  std::string analysis_summary() const override {
    const char* method = chosen_ == CHOLMOD_METIS ? "METIS" : chosen_ == CHOLMOD_AMD ? "AMD" : "CHOLMOD's choice";
    return std::to_string(analyses_) + " with " + method;
  }
  int negative_eigenvalues() const override { return negative_; }
  // A numeric factor back to a symbolic one of the same kind (cholmod_change_factor to CHOLMOD_PATTERN):
  // the values go, the analysis (Perm, ColCount, the supernodes) stays for the next factorize().
  void release_factor() override {
    auto* f = fact_.factor();
    if (!f || f->xtype == CHOLMOD_PATTERN) return;
    cholmod_change_factor(CHOLMOD_PATTERN, f->is_ll, f->is_super, true, true, f, &fact_.cholmod());
    permuted_.release_values();
    negative_ = -1;
  }
  long held_factor_entries() const override {
    const cholmod_factor* f = fact_.factor();
    if (!f || f->xtype == CHOLMOD_PATTERN) return 0;
    return static_cast<long>(f->is_super ? f->xsize : f->nzmax);
  }
  // Why the next numeric factorisation is not begun: its factor would exceed the memory limit
  // (factorization_memory_limit); empty when it fits or the memory is unknown. A factor that holds values
  // reuses them; a symbolic one gets its values (xsize entries for a supernodal factor, with the largest
  // update matrix, maxcsize; lnz and their row indices for a simplicial one).
  std::string memory_refusal() const {
    const cholmod_factor* f = fact_.factor();
    if (!f || f->xtype != CHOLMOD_PATTERN) return {};
    const double entries = f->is_super ? static_cast<double>(f->xsize + f->maxcsize) : 1.5 * fact_.cholmod().lnz;
    const double needed = entries * sizeof(double), limit = factorization_memory_limit(memory_limit_);
    if (limit <= 0 || needed <= limit) return {};
    constexpr double kMegabyte = 1 << 20;
    return "CHOLMOD's factor would need " + std::to_string(std::lround(needed / kMegabyte)) +
           " MB, more than the limit of " + std::to_string(std::lround(limit / kMegabyte)) + " MB";
  }
  // cholmod_factor::Perm: Perm[k] is the k-th pivot.
  std::vector<int> pivot_order() const {
    const cholmod_factor* f = fact_.factor();
    if (!f || !f->Perm) return {};
    const auto* perm = static_cast<const int*>(f->Perm);
    return std::vector<int>(perm, perm + f->n);
  }

 private:
  // The supernodal LL^T of a's values from the kept permuted lower triangle; cholmod_factorize's own path
  // for the simplicial LDL^T, for a matrix not compressed, or where the copy cannot be built.
  void factorize_values(const SpMat& a) {
    if constexpr (kSupernodal<Factorization>) {
      if (a.isCompressed() && (permuted_.built() || permuted_.build(a, *fact_.factor(), fact_.cholmod()))) {
        fact_.factorize_permuted(permuted_.fill(a));
        permuted_.drop_values();
        return;
      }
    }
    const SerialLibraryRegions serial;
    fact_.factorize(a);
  }

  mutable ReadableFactor<Factorization> fact_;
  CholmodPermutedLower permuted_;  // the supernodal factorisation's input, kept for the analysis's pattern
  std::string name_;
  int chosen_ = -1;  // the ordering method of the first analysis (CHOLMOD_AMD, CHOLMOD_METIS, ...)
  int analyses_ = 0;
  int negative_ = -1;  // of the last factorisation; -1 when it failed or none was made
  long memory_limit_;    // MB, as make_cholmod_llt takes it
  std::string refusal_;  // why the last factorisation was not begun; empty when it was
};

// What an UMFPACK status code means (UMFPACK user guide, "Error codes"); a warning (> 0) is a
// factorisation Eigen reports as failed, too.
std::string umfpack_status_text(long status) {
  switch (status) {
    case UMFPACK_WARNING_singular_matrix: return "singular matrix (a zero pivot)";
    case UMFPACK_WARNING_determinant_underflow: return "determinant underflow";
    case UMFPACK_WARNING_determinant_overflow: return "determinant overflow";
    case UMFPACK_ERROR_out_of_memory: return "out of memory";
    case UMFPACK_ERROR_invalid_Numeric_object: return "invalid Numeric object";
    case UMFPACK_ERROR_invalid_Symbolic_object: return "invalid Symbolic object";
    case UMFPACK_ERROR_argument_missing: return "argument missing";
    case UMFPACK_ERROR_n_nonpositive: return "n <= 0";
    case UMFPACK_ERROR_invalid_matrix: return "invalid matrix";
    case UMFPACK_ERROR_different_pattern: return "pattern differs from the analysis";
    case UMFPACK_ERROR_internal_error: return "internal error";
    default: return "status " + std::to_string(status);
  }
}

// UMFPACK keeps pointers to the matrix for iterative refinement in solve(), so the solver owns a copy.
// Index is int (umfpack_di_*, 32-bit integers) or long (umfpack_dl_*, 64-bit: no integer overflow in
// its work space at any size).
template <class Index>
class UmfpackSolver final : public LinearSolver {
  using Matrix = Eigen::SparseMatrix<double, Eigen::ColMajor, Index>;
  struct Lu : Eigen::UmfPackLU<Matrix> {
    double lu_nonzeros() const { return this->m_umfpackInfo[UMFPACK_LNZ] + this->m_umfpackInfo[UMFPACK_UNZ]; }
    long status() const { return static_cast<long>(this->m_fact_errorCode); }
  };

 public:
  void analyze(const SpMat& a) override {
    a_ = a;
    lu_.analyzePattern(a_);  // frees the last symbolic and numeric factors
    hand_back_freed_memory();
    status_ = lu_.status();
  }
  bool factorize_numeric(const SpMat& a) override {
    a_ = a;
    lu_.factorize(a_);
    status_ = lu_.status();
    return lu_.info() == Eigen::Success;
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const override { return lu_.solve(b); }
  std::string name() const override { return sizeof(Index) == 8 ? "umfpack64" : "umfpack"; }
  long factor_nonzeros() const override { return static_cast<long>(lu_.lu_nonzeros()); }
  std::string failure_detail() const override {
    return status_ != UMFPACK_OK ? "UMFPACK: " + umfpack_status_text(status_) : std::string();
  }

 private:
  Matrix a_;
  Lu lu_;
  long status_ = UMFPACK_OK;
};

using CholmodLLT = CholmodSolver<Eigen::CholmodSupernodalLLT<SpMat, Eigen::Lower>>;
using CholmodLDLT = CholmodSolver<Eigen::CholmodSimplicialLDLT<SpMat, Eigen::Lower>>;

}  // namespace

std::unique_ptr<LinearSolver> make_cholmod_llt(long memory_limit_megabytes) {
  return std::make_unique<CholmodLLT>("cholmod", memory_limit_megabytes);
}

std::unique_ptr<LinearSolver> make_cholmod_ldlt(long memory_limit_megabytes) {
  return std::make_unique<CholmodLDLT>("ldlt", memory_limit_megabytes);
}

std::vector<int> cholmod_pivot_order(const LinearSolver& solver) {
  if (std::vector<int> order = cholmod_split_pivot_order(solver); !order.empty()) return order;
  if (const auto* llt = dynamic_cast<const CholmodLLT*>(&solver)) return llt->pivot_order();
  if (const auto* ldlt = dynamic_cast<const CholmodLDLT*>(&solver)) return ldlt->pivot_order();
  return {};
}

std::unique_ptr<LinearSolver> make_umfpack(bool long_indices) {
  if (long_indices) return std::make_unique<UmfpackSolver<long>>();
  return std::make_unique<UmfpackSolver<int>>();
}

std::vector<int> cholmod_ordering(const SpMat& a) {
  CholmodLLT analysis("cholmod", kAvailableMemory);
  analysis.analyze(a);
  return analysis.pivot_order();
}

}  // namespace fibrane::solve
