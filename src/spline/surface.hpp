#pragma once
// Tensor-product NURBS surfaces: S(u,v) = sum_{i,j} R_ij(u,v) P_ij,
//   R_ij = w_ij N_i(u) M_j(v) / sum_kl w_kl N_k(u) M_l(v).
// Direction 0 is u, direction 1 is v. Control points (and weights) are stored u fastest: the point
// (i, j) has global index i + n_u * j. Parameter domain: the knot ranges (generators use [0,1]^2).
#include <Eigen/Dense>
#include <string>
#include <vector>

#include "spline/knot_vector.hpp"

namespace fibrane::spline {

struct SurfaceBasis {
  // Global control-point indices of the (p+1)(q+1) non-zero functions, local index a = i + (p+1) j.
  std::vector<int> indices;
  // Rows: R, R_u, R_v, R_uu, R_uv, R_vv; column a matches indices[a].
  Eigen::Matrix<double, 6, Eigen::Dynamic> R;
};

struct SurfaceElement {
  int span_u, span_v;     // knot span indices (for basis_in)
  double u0, u1, v0, v1;  // parameter box [u0,u1] x [v0,v1]
};

class NurbsSurface {
 public:
  // control points ordered i + n_u * j (u fastest); weights empty => all 1. Throws
  // std::invalid_argument on a count mismatch or a weight that is not > 0.
  NurbsSurface(KnotVector u, KnotVector v, std::vector<Eigen::Vector3d> control_points,
               std::vector<double> weights = {});

  const KnotVector& knots(int dir) const;
  int degree(int dir) const { return knots(dir).degree(); }
  int num_control_points(int dir) const { return knots(dir).num_basis(); }
  int num_control_points() const { return static_cast<int>(points_.size()); }
  const std::vector<Eigen::Vector3d>& control_points() const { return points_; }
  const std::vector<double>& weights() const { return weights_; }
  bool is_rational() const;  // true unless all weights are equal
  int index(int i, int j) const { return i + num_control_points(0) * j; }

  SurfaceBasis basis(double u, double v) const;  // rational, with first and second derivatives
  // The same into `out`, with `nu` and `nv` holding the 1-D bases: no allocation once they have the size
  // (loops that evaluate surfaces on many threads keep them per thread).
  void basis(double u, double v, SurfaceBasis& out, Eigen::MatrixXd& nu, Eigen::MatrixXd& nv) const;
  // Same with the knot spans given (e.g. SurfaceElement::span_u/v), so that points on an element's
  // boundary are evaluated with that element's polynomial pieces.
  SurfaceBasis basis_in(int span_u, int span_v, double u, double v) const;
  // The same from the 1-D B-spline values and first and second derivatives of each direction at the point
  // (rows 0-2 of bspline_basis_derivs in the spans): element loops evaluate those once per element row and
  // column. Overwrites `out`, reusing its storage (no allocation once it has the size).
  void tensor_basis(int span_u, int span_v, const Eigen::MatrixXd& nu, const Eigen::MatrixXd& nv,
                    SurfaceBasis& out) const;
  Eigen::Vector3d point(double u, double v) const;
  std::vector<SurfaceElement> elements() const;  // non-empty knot spans, u fastest

  // Exact refinements, per direction (dir 0 = u, 1 = v); see NurbsCurve for the semantics.
  void insert_knot(int dir, double t, int times = 1);
  void insert_knots(int dir, const std::vector<double>& values);
  void elevate_degree(int dir, int by = 1);
  void refine(int dir, int degree, int continuity, int n_elements);
  void refine(int dir, int degree, int continuity, const std::vector<double>& grid);

  // Control-point indices along a boundary, in increasing order of the running index: "u0" (u = u_min,
  // i = row, j = 0..n_v-1), "u1" (i = n_u-1-row), "v0" (v = v_min, j = row, i = 0..n_u-1), "v1"
  // (j = n_v-1-row). row 0 is the boundary row itself, row 1 the next one inward (clamping / symmetry
  // of C1 splines). Throws std::invalid_argument for another edge name or a row out of range.
  std::vector<int> edge_indices(const std::string& edge, int row = 0) const;

 private:
  // Apply a curve operation to every row of control points along `dir`.
  template <typename Op>
  void refine_rows(int dir, Op op);

  KnotVector knots_u_, knots_v_;
  std::vector<Eigen::Vector3d> points_;
  std::vector<double> weights_;
};

}  // namespace fibrane::spline
