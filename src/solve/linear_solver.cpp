#include "solve/linear_solver.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/UmfPackSupport>

#include "common/error.hpp"

namespace fibrane::solve {
namespace {

using SpMat = Eigen::SparseMatrix<double>;

// CHOLMOD factorisations (lower triangle of a symmetric matrix). Wrapper exposes the factor size.
template <class Factorization>
class CholmodSolver final : public LinearSolver {
 public:
  explicit CholmodSolver(std::string name) : name_(std::move(name)) {
    fact_.cholmod().print = 0;  // failures are reported through factorize()'s return value
  }
  void analyze(const SpMat& a) override { fact_.analyzePattern(a); }
  bool factorize(const SpMat& a) override {
    fact_.factorize(a);
    return fact_.info() == Eigen::Success;
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const override { return fact_.solve(b); }
  std::string name() const override { return name_; }
  long factor_nonzeros() const override {
    return static_cast<long>(const_cast<Factorization&>(fact_).cholmod().lnz);
  }

 private:
  Factorization fact_;
  std::string name_;
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

// Tries LL^T, then LDL^T, then LU; stays on the weakest method that was needed until the next analyze()
// (a tangent that lost definiteness usually stays indefinite for a while, e.g. past a limit point).
class AutoSolver final : public LinearSolver {
 public:
  void analyze(const SpMat& a) override {
    level_ = 0;
    make(level_)->analyze(a);
  }
  bool factorize(const SpMat& a) override {
    if (!current_) analyze(a);
    if (current_->factorize(a)) return true;
    while (level_ < 2) {
      make(++level_)->analyze(a);
      if (current_->factorize(a)) return true;
    }
    return false;
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const override { return current_->solve(b); }
  std::string name() const override { return "auto(" + (current_ ? current_->name() : "none") + ")"; }
  long factor_nonzeros() const override { return current_ ? current_->factor_nonzeros() : 0; }

 private:
  LinearSolver* make(int level) {
    if (level == 0) current_ = std::make_unique<CholmodLLT>("cholmod");
    if (level == 1) current_ = std::make_unique<CholmodLDLT>("ldlt");
    if (level == 2) current_ = std::make_unique<UmfpackSolver>();
    return current_.get();
  }
  int level_ = 0;
  std::unique_ptr<LinearSolver> current_;
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
    if (!symmetric) return std::make_unique<UmfpackSolver>();
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
