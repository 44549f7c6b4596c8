#pragma once
// Symmetric rank-one terms of a matrix held apart from its assembled part: K = A + sum_k c_k u_k u_k^T.
//
// A soft-minimum point's tangent (Sec. 7 of docs/interaction.md) is a sparse part plus one dense rank-one
// term c m m^T over its whole window, whose fill makes the window a dense block of the matrix. Assembled
// with those terms apart, the sparse part A keeps the pattern of the shell's own elements there, and a
// solve with K is a solve with A and a correction of the terms' rank (Sherman-Morrison-Woodbury,
// solve_with_rank_one_terms).
#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <vector>

namespace fibrane::solve {

class LinearSolver;

/// The terms c_k u_k u_k^T, each u_k a sparse vector over the matrix's rows (the reduced unknowns), and the
/// rows of the elements they were held apart from (`fill_rows`, in any order, repeats allowed): where a
/// row and a column both lie among those, an exact zero of the assembled part is the terms' fill or an
/// unused entry of their elements' blocks, which a factorisation of the assembled part may leave out.
struct RankOneTerms {
  std::vector<double> coefficient;
  std::vector<Eigen::SparseVector<double>> vector;
  std::vector<int> fill_rows;

  void clear() { coefficient.clear(), vector.clear(), fill_rows.clear(); }
  bool empty() const { return coefficient.empty(); }
  int size() const { return static_cast<int>(coefficient.size()); }
  void add(double c, Eigen::SparseVector<double> u) {
    coefficient.push_back(c);
    vector.push_back(std::move(u));
  }
  /// The terms restricted to the rows S (sorted): the columns u_k(S) of those terms that have an entry on S
  /// and a non-zero coefficient, as a dense |S| x m matrix, with their coefficients. K_SS = A_SS + U C U^T.
  void on_rows(const std::vector<int>& rows, Eigen::MatrixXd& u, Eigen::VectorXd& c) const;
  /// The whole sum_k c_k u_k u_k^T as a sparse matrix of size n x n (for checks).
  Eigen::SparseMatrix<double> assembled(Eigen::Index n) const;
};

/// The solution of (A + U diag(c) U^T) x = b from a factorisation of A (`a_solver`) by Sherman-Morrison-
/// Woodbury: x = x_A - Y (I + diag(c) U^T Y)^-1 diag(c) U^T x_A with x_A = A^-1 b and Y = A^-1 U (one
/// solve with U's columns together). The m x m system is solved by LU with full pivoting; where it is
/// numerically singular (K itself singular) x is NaN.
Eigen::VectorXd solve_with_rank_one_terms(const LinearSolver& a_solver, const Eigen::MatrixXd& u,
                                          const Eigen::VectorXd& c, const Eigen::VectorXd& b);

}  // namespace fibrane::solve
