#pragma once
// Preconditioned Krylov methods on operators: conjugate gradients for symmetric positive definite
// problems, restarted GMRES (right preconditioning) for any. KrylovReuseSolver uses them with an earlier
// or lower-precision factorisation as the preconditioner.
#include <functional>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

namespace fibrane::solve {

// out = Op(in); out has in's size on return.
using VectorOperator = std::function<void(const Eigen::VectorXd& in, Eigen::VectorXd& out)>;

// The outcome of one Krylov solve.
struct KrylovResult {
  Eigen::VectorXd x;
  int iterations = 0;             // operator applications after the initial residual
  double relative_residual = 0;   // |b - A x| / |b| of the returned x (recomputed, not the recurrence's)
  bool converged = false;         // relative_residual <= tolerance
  bool breakdown = false;         // CG met a direction of non-positive curvature (A or M not SPD)
};

// Preconditioned CG from x0 until |b - A x| <= tolerance |b| or max_iterations. A and the preconditioner
// M^-1 must be symmetric positive definite; a direction with p^T A p <= 0 stops it with breakdown = true.
KrylovResult preconditioned_cg(const VectorOperator& a, const VectorOperator& m_inverse, const Eigen::VectorXd& b,
                               const Eigen::VectorXd& x0, double tolerance, int max_iterations);

// GMRES(restart) with right preconditioning (A M^-1 y = b - A x0, x = x0 + M^-1 y), so its residual is the
// true residual of the unpreconditioned system; modified Gram-Schmidt with one reorthogonalisation, Givens
// rotations. Stops at |b - A x| <= tolerance |b|, after max_iterations operator applications, or when a
// cycle does not lower the true residual (the best iterate is returned).
KrylovResult preconditioned_gmres(const VectorOperator& a, const VectorOperator& m_inverse, const Eigen::VectorXd& b,
                                  const Eigen::VectorXd& x0, double tolerance, int max_iterations, int restart);

// y = A x for a column-major sparse matrix, split over OpenMP threads by columns (each thread sums its
// columns into its own vector; the partial vectors are added in thread order, so the result is the same
// for a given thread count).
void parallel_multiply(const Eigen::SparseMatrix<double>& a, const Eigen::VectorXd& x, Eigen::VectorXd& y);

}  // namespace fibrane::solve
