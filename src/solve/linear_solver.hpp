#pragma once
// Sparse direct solvers behind one interface (SuiteSparse through Eigen's wrappers).
// Symbolic analysis (fill-reducing ordering, elimination tree) is split from the numeric factorisation
// so Newton iterations on an unchanged sparsity pattern only refactorise.
#include <memory>
#include <string>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

namespace fibrane::solve {

class LinearSolver {
 public:
  virtual ~LinearSolver() = default;
  virtual void analyze(const Eigen::SparseMatrix<double>& a) = 0;    // symbolic; reused while the pattern is unchanged
  virtual bool factorize(const Eigen::SparseMatrix<double>& a) = 0;  // false on failure (singular / not PD)
  virtual Eigen::VectorXd solve(const Eigen::VectorXd& b) const = 0;
  virtual std::string name() const = 0;
  virtual long factor_nonzeros() const = 0;
  // How the analyses went (how many, with which ordering method), for reports; may be empty.
  virtual std::string analysis_summary() const { return {}; }
  // Number of negative eigenvalues of the last factorised matrix (Sylvester's law of inertia applied to
  // the factorisation), or -1 where the factorisation does not tell.
  virtual int negative_eigenvalues() const { return -1; }

  // Calls analyze() unless the last analysis was for the same pattern version and matrix shape.
  // Used by newton_solve(); returns true if it analysed.
  bool analyze_if_needed(const Eigen::SparseMatrix<double>& a, int pattern_version);

 private:
  int analyzed_version_ = -1;
  Eigen::Index analyzed_rows_ = -1, analyzed_nonzeros_ = -1;
};

// kind: "cholmod" (supernodal LL^T, symmetric positive definite), "ldlt" (CHOLMOD simplicial LDL^T,
// symmetric indefinite without pivoting), "umfpack" (unsymmetric LU), "auto" (cholmod LL^T, falling back
// to ldlt (up to 20 000 unknowns; larger ones skip the simplicial LDL^T) then umfpack when a factorisation
// fails, trying LL^T first again at every factorisation; when symmetric == false it checks every matrix against
// its transpose and takes that chain while the values are symmetric to round-off (1e-12 of the largest
// entry), umfpack otherwise; the name then reads "symmetric-auto(...)" or "umfpack").
// Symmetric kinds read only the lower triangle, so they are refused (InputError) for symmetric == false.
std::unique_ptr<LinearSolver> make_linear_solver(const std::string& kind, bool symmetric);

}  // namespace fibrane::solve
