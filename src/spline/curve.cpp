#include "spline/curve.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "common/gauss_legendre.hpp"
#include "spline/basis.hpp"
#include "spline/refinement.hpp"

namespace fibrane::spline {

NurbsCurve::NurbsCurve(KnotVector kv, std::vector<Eigen::Vector3d> control_points,
                       std::vector<double> weights)
    : knots_(std::move(kv)), points_(std::move(control_points)), weights_(std::move(weights)) {
  const std::size_t n = static_cast<std::size_t>(knots_.num_basis());
  if (points_.size() != n)
    throw std::invalid_argument("NurbsCurve: " + std::to_string(points_.size()) +
                                " control points given, the knot vector needs " + std::to_string(n));
  if (weights_.empty()) weights_.assign(n, 1.0);
  if (weights_.size() != n)
    throw std::invalid_argument("NurbsCurve: " + std::to_string(weights_.size()) + " weights given, " +
                                std::to_string(n) + " control points");
  for (std::size_t i = 0; i < n; ++i)
    if (!(weights_[i] > 0.0))
      throw std::invalid_argument("NurbsCurve: weight " + std::to_string(i) + " is not positive");
}

bool NurbsCurve::is_rational() const {
  return std::any_of(weights_.begin(), weights_.end(), [&](double w) { return w != weights_.front(); });
}

Eigen::MatrixXd rationalize_curve_basis(const Eigen::MatrixXd& bspline, const Eigen::VectorXd& weights) {
  const int n_deriv = static_cast<int>(bspline.rows()) - 1;
  const Eigen::MatrixXd weighted = bspline * weights.asDiagonal();
  const Eigen::VectorXd w_derivs = weighted.rowwise().sum();  // W^(k)
  Eigen::MatrixXd rational(bspline.rows(), bspline.cols());
  for (int k = 0; k <= n_deriv; ++k) {
    Eigen::RowVectorXd row = weighted.row(k);
    double binomial = 1.0;  // C(k, i), updated incrementally
    for (int i = 1; i <= k; ++i) {
      binomial = binomial * (k - i + 1) / i;
      row -= binomial * w_derivs[i] * rational.row(k - i);
    }
    rational.row(k) = row / w_derivs[0];
  }
  return rational;
}

CurveBasis NurbsCurve::basis(double u, int n_deriv) const {
  const int p = degree();
  const int span = knots_.find_span(u);
  const Eigen::MatrixXd bspline = bspline_basis_derivs(knots_, span, u, n_deriv);
  Eigen::VectorXd local_weights(p + 1);
  for (int j = 0; j <= p; ++j) local_weights[j] = weights_[span - p + j];
  return {span - p, rationalize_curve_basis(bspline, local_weights)};
}

Eigen::Vector3d NurbsCurve::point(double u) const { return derivative(u, 0); }

Eigen::Vector3d NurbsCurve::derivative(double u, int order) const {
  if (order < 0) throw std::invalid_argument("NurbsCurve::derivative: order must be >= 0");
  const CurveBasis b = basis(u, order);
  Eigen::Vector3d result = Eigen::Vector3d::Zero();
  for (int j = 0; j < b.R.cols(); ++j) result += b.R(order, j) * points_[b.first + j];
  return result;
}

void NurbsCurve::insert_knot(double u, int times) {
  HomogeneousCurve refined = spline::insert_knot({knots_, to_homogeneous(points_, weights_)}, u, times);
  knots_ = std::move(refined.knots);
  from_homogeneous(refined.points, points_, weights_);
}

void NurbsCurve::insert_knots(const std::vector<double>& values) {
  if (values.empty()) return;
  HomogeneousCurve refined = spline::insert_knots({knots_, to_homogeneous(points_, weights_)}, values);
  knots_ = std::move(refined.knots);
  from_homogeneous(refined.points, points_, weights_);
}

void NurbsCurve::elevate_degree(int by) {
  HomogeneousCurve elevated = spline::elevate_degree({knots_, to_homogeneous(points_, weights_)}, by);
  knots_ = std::move(elevated.knots);
  from_homogeneous(elevated.points, points_, weights_);
}

void NurbsCurve::refine(int degree, int continuity, int n_elements) {
  check_refine_request(this->degree(), degree, continuity, n_elements);
  elevate_degree(degree - this->degree());
  insert_knots(expand_insertions(uniform_insertions(knots_, continuity, n_elements)));
}

void NurbsCurve::refine(int degree, int continuity, const std::vector<double>& grid) {
  check_refine_request(this->degree(), degree, continuity, static_cast<int>(grid.size()) + 1);
  elevate_degree(degree - this->degree());
  insert_knots(expand_insertions(grid_insertions(knots_, continuity, grid)));
}

double arc_length(const NurbsCurve& c, double xi0, double xi) {
  static const auto g = gauss_legendre(10);
  double s = 0;
  const double j = 0.5 * (xi - xi0);
  for (std::size_t q = 0; q < g.points.size(); ++q)
    s += g.weights[q] * j * c.derivative(xi0 + (g.points[q] + 1.0) * j, 1).norm();
  return s;
}

}  // namespace fibrane::spline
