#pragma once
// Solves with a matrix K whose skew part (K - K^T) / 2 lives on a few rows and columns, through a
// factorisation of its symmetric part S = (K + K^T) / 2 and an exact rank-m correction (Sherman-Morrison-
// Woodbury). With P the m unit columns of those rows and C = P^T (K - K^T) / 2 P, K = S + P C P^T and
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
  // After `symmetric` has factorised S: Z, C and M's LU for the skew rows `support` of `k`. False when
  // M is singular to working precision (K is then singular, or nearly, while S is not).
  bool prepare(const LinearSolver& symmetric, const Eigen::SparseMatrix<double>& k, std::vector<int> support);
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
