#pragma once
// A separator's dense front in the split Cholesky (cholmod_split.hpp).
#include <Eigen/Dense>
#include <utility>
#include <vector>

namespace fibrane::solve {

/// The dense matrix on a separator's rows S and its boundary B (rows of separators above it):
///   F = [F_SS *; F_BS F_BB],
/// assembled from K's entries with a row or column in S (K_BB belongs to the fronts above) and the updates
/// of the separator's two children (extend-add), then partially factorised (LAPACK and BLAS):
///   F_SS = L_SS L_SS^T,  L_BS = F_BS L_SS^-T,  U = F_BB - L_BS L_BS^T,
/// U being this front's update of its own boundary. A forward solve takes r = [r_S; r_B] to
/// [L_SS^-1 r_S; r_B - L_BS L_SS^-1 r_S] (the second part goes up to the parent), a backward solve takes
/// y_S and the boundary's solution x_B to x_S = L_SS^-T (y_S - L_BS^T x_B).
/// Where F_SS is not positive definite (an indefinite matrix, or a child's LDL^T update), LAPACK's
/// Bunch-Kaufman LDL^T factorises it instead, F_SS = P L D L^T P^T (dsytrf), with
///   U = F_BB - F_BS F_SS^-1 F_BS^T,  forward: [F_SS^-1 r_S; r_B - F_BS F_SS^-1 r_S],
///   backward: x_S = y_S - F_SS^-1 F_BS^T x_B,
/// and negative() counts D's negative eigenvalues (1 x 1 and 2 x 2 blocks), F_SS's by Sylvester's law.
class DenseFront {
 public:
  /// The sizes of S and B, K's entries (index in K's value array, index in F's column-major storage of its
  /// lower triangle) and each child's map (the child's boundary rows' places in F).
  void set(int separator, int boundary, std::vector<std::pair<int, long>> entries,
           std::vector<std::vector<int>> child_maps);
  /// F from K's values, with the children's updates still to add.
  void assemble(const double* values);
  /// F += the lower triangle of child k's update `u` at its map's places.
  void add(int child, Eigen::Ref<const Eigen::MatrixXd> u);
  /// The partial factorisation, LL^T or else LDL^T; false where F_SS is singular.
  bool factorise();
  /// Whether the last factorisation is the LDL^T, and F_SS's negative eigenvalues (0 for LL^T).
  bool ldlt() const { return !pivots_.empty(); }
  int negative() const { return negative_; }
  /// U (after factorise()), the lower triangle.
  Eigen::Ref<const Eigen::MatrixXd> update() const { return f_.bottomRightCorner(b_, b_); }
  /// Keeps only what solves need (L_SS and L_BS), once the parent has added U.
  void drop_update();
  void release() { f_.resize(0, 0); }
  bool factored() const { return f_.size() > 0; }

  /// r (rows S, then B; m columns) as above.
  void forward(Eigen::MatrixXd& r) const;
  /// y (rows S) becomes x_S; x_b: the boundary's solution (rows B).
  void backward(Eigen::MatrixXd& y, const Eigen::MatrixXd& x_b) const;

  int separator() const { return s_; }
  int boundary() const { return b_; }
  const std::vector<int>& child_map(int k) const { return child_maps_[static_cast<std::size_t>(k)]; }
  /// Factor entries (the lower triangle of L_SS and L_BS) and the flops of a factorisation.
  long factor_entries() const;
  double flops() const;

 private:
  int s_ = 0, b_ = 0;
  std::vector<std::pair<int, long>> entries_;
  std::vector<std::vector<int>> child_maps_;
  Eigen::MatrixXd f_;
  std::vector<int> pivots_;  // dsytrf's IPIV where the LDL^T factorised F_SS, empty for the LL^T
  int negative_ = 0;
  bool factorise_ldlt(const Eigen::MatrixXd& f_ss);
  // x = F_SS^-1 x by dsytrs (rows S, m columns, leading dimension ld)
  void ldlt_solve(double* x, int m, int ld) const;
};

}  // namespace fibrane::solve
