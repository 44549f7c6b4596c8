#pragma once
// Solves with a matrix K whose skew part (K - K^T) / 2 lives on a few rows and columns, through a
// factorisation of a symmetric S that equals K outside them (its symmetric part (K + K^T) / 2, made
// diagonally dominant in those rows) and an exact rank-m correction (Sherman-Morrison-Woodbury). With P
// the m unit columns of those rows and C = P^T (K - S) P, K = S + P C P^T and
//   K^{-1} b = y - Z M^{-1} C P^T y,   y = S^{-1} b,  Z = S^{-1} P,  M = I + C P^T Z,
// which costs m solves with S per factorisation (Z) and one per right-hand side. fibrane's unsymmetric
// tangents are of this kind: the load stiffness of point moments on a beam's end (Eq. (54), B8-B9)
// couples only that end's control points, so a symmetric factorisation (CHOLMOD's LL^T, half the entries
// of an LU) serves the whole full-membrane model.
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include "linalg/linear_solver.hpp"

namespace fibrane::solve {

class SkewCorrection {
 public:
  // After `symmetric` has factorised `s`, which equals k outside the rows and columns `support`: Z, C =
  // P^T (k - s) P and M's LU. False when M is singular to working precision (k is then singular, or
  // nearly, while s is not).
  bool prepare(const LinearSolver& symmetric, const Eigen::SparseMatrix<double>& k, const Eigen::SparseMatrix<double>& s,
               std::vector<int> support);
  // s = (k + k^T) / 2 (from symmetric_part) made diagonally dominant in the rows `support`: each of their
  // diagonal entries raised to the sum of the row's off-diagonal magnitudes, so that those rows (where a
  // point moment's load stiffness also makes the symmetric part indefinite) do not stop a Cholesky
  // factorisation; C takes the difference back.
  static void dominate_support(Eigen::SparseMatrix<double>& s, const std::vector<int>& support);
  // K^{-1} b from y = S^{-1} b.
  Eigen::VectorXd apply(const Eigen::VectorXd& y) const;
  int rank() const { return static_cast<int>(support_.size()); }
  void clear();

 private:
  std::vector<int> support_;
  Eigen::MatrixXd z_, c_;
  Eigen::PartialPivLU<Eigen::MatrixXd> m_;
};

}  // namespace fibrane::solve
