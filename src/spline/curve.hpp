#pragma once
// NURBS curves in 3D: C(u) = sum_i R_i(u) P_i, R_i = w_i N_i / sum_j w_j N_j.
// Parameter domain: [knots().front(), knots().back()] (generators in shapes.hpp use [0, 1]).
#include <Eigen/Dense>
#include <vector>

#include "spline/knot_vector.hpp"

namespace fibrane::spline {

struct CurveBasis {
  int first;          // global index of the first non-zero function (= span - p)
  Eigen::MatrixXd R;  // (n_deriv+1) x (p+1): R(k, j) = d^k R_{first+j} / du^k
};

class NurbsCurve {
 public:
  // weights empty => all 1 (a plain B-spline). Throws std::invalid_argument if the number of control
  // points or weights differs from kv.num_basis(), or a weight is not > 0.
  NurbsCurve(KnotVector kv, std::vector<Eigen::Vector3d> control_points, std::vector<double> weights = {});

  const KnotVector& knots() const { return knots_; }
  int degree() const { return knots_.degree(); }
  int num_control_points() const { return static_cast<int>(points_.size()); }
  const std::vector<Eigen::Vector3d>& control_points() const { return points_; }
  const std::vector<double>& weights() const { return weights_; }
  bool is_rational() const;  // true unless all weights are equal

  // Rational basis functions and their first n_deriv derivatives at u.
  CurveBasis basis(double u, int n_deriv = 2) const;
  Eigen::Vector3d point(double u) const;
  Eigen::Vector3d derivative(double u, int order) const;  // d^order C / du^order, order >= 1

  // Exact refinements (the geometry and parameterisation do not change).
  void insert_knot(double u, int times = 1);
  // All `values` in one pass (spline::insert_knots); refine() inserts its knots this way.
  void insert_knots(const std::vector<double>& values);
  void elevate_degree(int by = 1);
  // Uniform h-refinement: elevate to `degree` (>= current), then insert knots at the uniform parameter
  // grid a + (b-a) k / n_elements, k = 1..n-1, each to multiplicity degree - continuity (counting the
  // existing multiplicity; knots already of lower continuity are left alone). Interior knots the
  // geometry already has off that grid (e.g. C0 joints of arcs) remain, so the element count is
  // n_elements plus those extra knots.
  void refine(int degree, int continuity, int n_elements);
  // The same on the interior parameter values `grid` (increasing, strictly inside the domain) instead of
  // the uniform grid, e.g. spline::geometric_grid.
  void refine(int degree, int continuity, const std::vector<double>& grid);

 private:
  KnotVector knots_;
  std::vector<Eigen::Vector3d> points_;
  std::vector<double> weights_;
};

// Rational basis from B-spline derivatives: A = w_j N_j^(k), W^(k) = sum_j A_j^(k),
//   R^(k) = (A^(k) - sum_{i=1..k} C(k,i) W^(i) R^(k-i)) / W.
// `basis` is (n+1) x (p+1) as from bspline_basis_derivs and becomes R in place (no allocation up to the
// 7th derivative); `weights` are those of the p+1 functions.
void rationalize_curve_basis(Eigen::MatrixXd& basis, const double* weights);

// Arc length of the curve from xi0 to xi by 10-point Gauss-Legendre: exact to round-off for the output
// coordinates along one element of a smooth axis (xi0 and xi in one knot span).
double arc_length(const NurbsCurve& c, double xi0, double xi);

}  // namespace fibrane::spline
