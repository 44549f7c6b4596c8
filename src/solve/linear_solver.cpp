#include "solve/linear_solver.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/UmfPackSupport>

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/error.hpp"

namespace fibrane::solve {
namespace {

using SpMat = Eigen::SparseMatrix<double>;

// CHOLMOD factorisations (lower triangle of a symmetric matrix), remembering which fill-reducing ordering
// won. CHOLMOD's default tries AMD and, where AMD's fill is high, METIS too, and keeps the better; a
// model's later patterns differ from the first only by the beam-shell coupling, so later analyses run only
// the method that won the first. At the bending example's paper mesh METIS wins (1 % less fill than AMD)
// and an analysis takes 1.18 s instead of 1.37 s. (Keeping the previous permutation itself for a new
// pattern was measured too: after a change of the coupling its factor was 4-10 % larger than a fresh
// ordering's, which costs more in the factorisations than the ordering does.)
template <class Factorization>
class CholmodSolver final : public LinearSolver {
 public:
  explicit CholmodSolver(std::string name) : name_(std::move(name)) {
    fact_.cholmod().print = 0;  // failures are reported through factorize()'s return value
  }
  void analyze(const SpMat& a) override {
    cholmod_common& common = fact_.cholmod();
    if (chosen_ >= 0) {
      common.nmethods = 1;
      common.method[0].ordering = chosen_;
    }
    fact_.analyzePattern(a);
    if (chosen_ < 0 && fact_.info() == Eigen::Success) chosen_ = common.method[common.selected].ordering;
    ++analyses_;
  }
  bool factorize(const SpMat& a) override {
    fact_.factorize(a);
    return fact_.info() == Eigen::Success;
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const override { return fact_.solve(b); }
  std::string name() const override { return name_; }
  long factor_nonzeros() const override { return static_cast<long>(fact_.cholmod().lnz); }
  std::string analysis_summary() const override {
    const char* method = chosen_ == CHOLMOD_METIS ? "METIS" : chosen_ == CHOLMOD_AMD ? "AMD" : "CHOLMOD's choice";
    return std::to_string(analyses_) + " with " + method;
  }

 private:
  mutable Factorization fact_;
  std::string name_;
  int chosen_ = -1;  // the ordering method of the first analysis (CHOLMOD_AMD, CHOLMOD_METIS, ...)
  int analyses_ = 0;
};

// UMFPACK keeps pointers to the matrix for iterative refinement in solve(), so the solver owns a copy.
class UmfpackSolver final : public LinearSolver {
  struct Lu : Eigen::UmfPackLU<SpMat> {
    double lu_nonzeros() const { return m_umfpackInfo[UMFPACK_LNZ] + m_umfpackInfo[UMFPACK_UNZ]; }
  };

 public:
  void analyze(const SpMat& a) override {
    a_ = a;
    lu_.analyzePattern(a_);
  }
  bool factorize(const SpMat& a) override {
    a_ = a;
    lu_.factorize(a_);
    return lu_.info() == Eigen::Success;
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const override { return lu_.solve(b); }
  std::string name() const override { return "umfpack"; }
  long factor_nonzeros() const override { return static_cast<long>(lu_.lu_nonzeros()); }

 private:
  SpMat a_;
  Lu lu_;
};

using CholmodLLT = CholmodSolver<Eigen::CholmodSupernodalLLT<SpMat, Eigen::Lower>>;
using CholmodLDLT = CholmodSolver<Eigen::CholmodSimplicialLDLT<SpMat, Eigen::Lower>>;

// Tries LL^T first at every factorisation, then LDL^T, then LU. An indefinite tangent is often a single
// wild Newton iterate: on the bending example at 300 x 75 x 75 only the first update of the first step was
// indefinite, and staying on LU afterwards cost 4.5 s per iteration against 1.9 s for LL^T (a failed LL^T
// attempt cost 1.1 s there, as CHOLMOD stops at the first non-positive pivot). The fallbacks keep their
// symbolic analysis until the next analyze().
class AutoSolver final : public LinearSolver {
 public:
  static constexpr Eigen::Index kSimplicialLimit = 20000;
  void analyze(const SpMat& a) override {
    if (!llt_) llt_ = std::make_unique<CholmodLLT>("cholmod");
    llt_->analyze(a);
    fallback_.reset();
    current_ = llt_.get();
  }
  bool factorize(const SpMat& a) override {
    if (!llt_) analyze(a);
    current_ = llt_.get();
    if (llt_->factorize(a)) return true;
    // CHOLMOD's LDL^T is simplicial (no BLAS-3 kernels): on the bending example at 400 x 100 x 100
    // (273 k unknowns) one factorisation did not finish in 10 minutes, where UMFPACK's multifrontal
    // LU takes seconds. Large indefinite matrices therefore go straight to LU.
    if (!fallback_) {
      if (a.rows() > kSimplicialLimit) fallback_ = std::make_unique<UmfpackSolver>();
      else fallback_ = std::make_unique<CholmodLDLT>("ldlt");
      fallback_->analyze(a);
    }
    current_ = fallback_.get();
    if (fallback_->factorize(a)) return true;
    if (fallback_->name() == "umfpack") return false;
    fallback_ = std::make_unique<UmfpackSolver>();  // LDL^T without pivoting can fail where LU does not
    fallback_->analyze(a);
    current_ = fallback_.get();
    return fallback_->factorize(a);
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const override { return current_->solve(b); }
  std::string name() const override { return "auto(" + (current_ ? current_->name() : "none") + ")"; }
  long factor_nonzeros() const override { return current_ ? current_->factor_nonzeros() : 0; }
  std::string analysis_summary() const override { return llt_ ? llt_->analysis_summary() : ""; }

 private:
  std::unique_ptr<LinearSolver> llt_, fallback_;
  LinearSolver* current_ = nullptr;
};

// For a model that cannot promise symmetry (point moments: Eq. (54)'s load stiffness is unsymmetric in
// general) but whose tangent may still be symmetric in the case at hand (a moment about a fixed axis on a
// beam kept in a plane: M . delta omega is then the variation of M theta). The values are compared with
// their mirror entries before every factorisation (one pass over the values through a map built at
// analyze(), ~1% of a factorisation), and the symmetric chain (supernodal LL^T, LDL^T, LU) is used while
// the matrix is symmetric to round-off; otherwise LU.
class SymmetryProbingSolver final : public LinearSolver {
 public:
  void analyze(const SpMat& a) override {
    build_mirror(a);
    symmetric_ = !mirror_.empty() && is_symmetric(a);
    pick(a);
  }
  bool factorize(const SpMat& a) override {
    // analyze() is the caller's duty on a new pattern; a matrix of another size is re-analysed here.
    if (!current_ || (structurally_symmetric_ && static_cast<Eigen::Index>(mirror_.size()) != a.nonZeros()))
      analyze(a);
    const bool now_symmetric = structurally_symmetric_ && is_symmetric(a);
    if (now_symmetric != symmetric_) {
      symmetric_ = now_symmetric;
      pick(a);
    }
    return current_->factorize(a);
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const override { return current_->solve(b); }
  std::string name() const override {
    return std::string(symmetric_ ? "symmetric-" : "") + (current_ ? current_->name() : "auto(none)");
  }
  long factor_nonzeros() const override { return current_ ? current_->factor_nonzeros() : 0; }
  std::string analysis_summary() const override { return symmetric_chain_ ? symmetric_chain_->analysis_summary() : ""; }

 private:
  // mirror_[k] = value index of the entry transposed to entry k; empty if the pattern is not symmetric.
  // One pass: walking the columns in order meets the entries (row, col) of a fixed row in increasing col,
  // which is the order of their mirrors (col, row) in column `row`, so a cursor per column finds them
  // (binary searches took ~1 s at the bending example's paper mesh).
  void build_mirror(const SpMat& a) {
    mirror_.clear();
    structurally_symmetric_ = false;
    if (a.rows() != a.cols() || !a.isCompressed()) return;
    const int* outer = a.outerIndexPtr();
    const int* inner = a.innerIndexPtr();
    std::vector<int> next(outer, outer + a.cols());
    std::vector<int> mirror(static_cast<size_t>(a.nonZeros()));
    for (Eigen::Index col = 0; col < a.cols(); ++col)
      for (int k = outer[col]; k < outer[col + 1]; ++k) {
        const int row = inner[k];
        const int m = next[row]++;
        if (m >= outer[row + 1] || inner[m] != col) return;
        mirror[static_cast<size_t>(k)] = m;
      }
    mirror_ = std::move(mirror);
    structurally_symmetric_ = true;
  }
  // Symmetric when every |a_ij - a_ji| <= 1e-12 max|a|: assembled tangents of symmetric element matrices
  // differ from their transpose by summation-order round-off only (~1e-16 relative, measured 1e-16 on
  // the bending example), while a genuinely unsymmetric load stiffness differs at O(load) level.
  bool is_symmetric(const SpMat& a) const {
    const double* v = a.valuePtr();
    const Eigen::Index nnz = a.nonZeros();
    double largest = 0, difference = 0;
#pragma omp parallel for reduction(max : largest, difference) schedule(static) if (nnz > 200000)
    for (Eigen::Index k = 0; k < nnz; ++k) {
      largest = std::max(largest, std::abs(v[k]));
      difference = std::max(difference, std::abs(v[k] - v[mirror_[static_cast<size_t>(k)]]));
    }
    return difference <= 1e-12 * largest;
  }
  // The symmetric chain is kept (with its ordering) while LU is in use.
  void pick(const SpMat& a) {
    if (symmetric_) {
      if (!symmetric_chain_) symmetric_chain_ = std::make_unique<AutoSolver>();
      current_ = symmetric_chain_.get();
    } else {
      if (!lu_) lu_ = std::make_unique<UmfpackSolver>();
      current_ = lu_.get();
    }
    current_->analyze(a);
  }

  bool symmetric_ = false, structurally_symmetric_ = false;
  std::vector<int> mirror_;
  std::unique_ptr<LinearSolver> symmetric_chain_, lu_;
  LinearSolver* current_ = nullptr;
};

}  // namespace

bool LinearSolver::analyze_if_needed(const SpMat& a, int pattern_version) {
  if (pattern_version == analyzed_version_ && a.rows() == analyzed_rows_ && a.nonZeros() == analyzed_nonzeros_)
    return false;
  analyze(a);
  analyzed_version_ = pattern_version;
  analyzed_rows_ = a.rows();
  analyzed_nonzeros_ = a.nonZeros();
  return true;
}

std::unique_ptr<LinearSolver> make_linear_solver(const std::string& kind, bool symmetric) {
  if (kind == "umfpack") return std::make_unique<UmfpackSolver>();
  if (kind == "auto") {
    if (!symmetric) return std::make_unique<SymmetryProbingSolver>();
    return std::make_unique<AutoSolver>();
  }
  if (kind == "cholmod" || kind == "ldlt") {
    if (!symmetric)
      throw InputError("linear solver '" + kind + "' needs a symmetric matrix; use 'umfpack' or 'auto'");
    if (kind == "cholmod") return std::make_unique<CholmodLLT>("cholmod");
    return std::make_unique<CholmodLDLT>("ldlt");
  }
  throw InputError("unknown linear solver '" + kind + "' (expected cholmod, ldlt, umfpack or auto)");
}

}  // namespace fibrane::solve
