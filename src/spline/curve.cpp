#include "spline/curve.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>
#include <vector>

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

void rationalize_curve_basis(Eigen::MatrixXd& basis, const double* weights) {
  const auto rows = static_cast<int>(basis.rows()), cols = static_cast<int>(basis.cols());
  for (int j = 0; j < cols; ++j)
    for (int k = 0; k < rows; ++k) basis(k, j) *= weights[j];  // A
  // W^(k) by Eigen's row sums (their order of additions), on the stack up to the 7th derivative
  constexpr int kOnStack = 8;
  Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kOnStack, 1> w_on_stack;
  Eigen::VectorXd w_on_heap;
  const double* w_derivs = nullptr;
  if (rows <= kOnStack) {
    w_on_stack = basis.rowwise().sum();
    w_derivs = w_on_stack.data();
  } else {
    w_on_heap = basis.rowwise().sum();
    w_derivs = w_on_heap.data();
  }
  // Row k needs only itself and the rows above it, which are rational by then.
  std::array<double, kOnStack> factor_on_stack{};
  std::vector<double> factor_on_heap(rows > kOnStack ? static_cast<std::size_t>(rows) : 0);
  double* factor = rows > kOnStack ? factor_on_heap.data() : factor_on_stack.data();  // C(k, i) W^(i)
  for (int k = 0; k < rows; ++k) {
    double binomial = 1.0;  // C(k, i), updated incrementally
    for (int i = 1; i <= k; ++i) {
      binomial = binomial * (k - i + 1) / i;
      factor[i] = binomial * w_derivs[i];
    }
    for (int j = 0; j < cols; ++j) {
      double a = basis(k, j);
      for (int i = 1; i <= k; ++i) a -= factor[i] * basis(k - i, j);
      basis(k, j) = a / w_derivs[0];
    }
  }
}

CurveBasis NurbsCurve::basis(double u, int n_deriv) const {
  const int p = degree();
  const int span = knots_.find_span(u);
  CurveBasis b{span - p, bspline_basis_derivs(knots_, span, u, n_deriv)};
  rationalize_curve_basis(b.R, weights_.data() + (span - p));
  return b;
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
