#pragma once
// Solves with a matrix K whose skew part (K - K^T) / 2 lives on a few rows and columns, through a
// factorisation of a symmetric S that equals K outside them (in their block, K's symmetric part
// (K + K^T) / 2 made diagonally dominant) and an exact rank-m correction (Sherman-Morrison-Woodbury). With P
// the m unit columns of those rows and C = P^T (K - S) P, K = S + P C P^T and
//   K^{-1} b = y - Z M^{-1} C P^T y,   y = S^{-1} b,  Z = S^{-1} P,  M = I + C P^T Z,
// which costs m solves with S per factorisation (Z) and one per right-hand side. fibrane's unsymmetric
// tangents are of this kind: the load stiffness of point moments on a beam's end (Eq. (54), B8-B9)
// couples only that end's control points, so a symmetric factorisation (CHOLMOD's LL^T, half the entries
// of an LU) serves the whole full-membrane model.
//
// S is written into K's own storage and K's values are put back after the factorisation: S and K differ in
// the m x m block alone, and a copy of a tangent of 10^8 entries would cost gigabytes.
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include "linalg/linear_solver.hpp"

namespace fibrane::solve {

class SkewCorrection {
 public:
  // Makes k the symmetric S in place: the entries of the block support x support (rows sorted and unique)
  // become (k + k^T) / 2, and each support row's diagonal entry is raised to the sum of the row's
  // off-diagonal magnitudes, so that those rows (where a point moment's load stiffness also makes the
  // symmetric part indefinite) do not stop a Cholesky factorisation. Outside the block k must be
  // symmetric (to the round-off of its assembly): a symmetric factorisation reads one of its triangles.
  // Keeps k's values of the block and C = P^T (k - S) P. False, with k unchanged, where an entry of the
  // block has no mirror in k's pattern. A support row without a diagonal entry in the pattern is not made
  // dominant (the analysis was made for k's pattern: no entry is added).
  bool symmetrize(Eigen::SparseMatrix<double>& k, std::vector<int> support);
  // Puts k's own values back (k: the matrix symmetrize() changed, its pattern unchanged since).
  void restore(Eigen::SparseMatrix<double>& k) const;
  // After `symmetric` has factorised the S of the last symmetrize(): Z and M's LU. False when M is singular
  // to working precision (K is then singular, or nearly, while S is not).
  bool prepare(const LinearSolver& symmetric);
  // K^{-1} b from y = S^{-1} b.
  Eigen::VectorXd apply(const Eigen::VectorXd& y) const;
  int rank() const { return static_cast<int>(support_.size()); }
  void clear();

 private:
  std::vector<int> support_;
  Eigen::Index rows_ = 0;         // K's
  std::vector<int> changed_;      // value indices of the block's entries in k
  std::vector<double> original_;  // k's values there
  Eigen::MatrixXd z_, c_;
  Eigen::PartialPivLU<Eigen::MatrixXd> m_;
};

}  // namespace fibrane::solve
