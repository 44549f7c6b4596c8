#include "spline/refinement.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "spline/basis.hpp"

namespace fibrane::spline {

HomogeneousPoints to_homogeneous(const std::vector<Eigen::Vector3d>& points,
                                 const std::vector<double>& weights) {
  HomogeneousPoints hom(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    hom[i].head<3>() = weights[i] * points[i];
    hom[i][3] = weights[i];
  }
  return hom;
}

void from_homogeneous(const HomogeneousPoints& hom, std::vector<Eigen::Vector3d>& points,
                      std::vector<double>& weights) {
  points.resize(hom.size());
  weights.resize(hom.size());
  for (std::size_t i = 0; i < hom.size(); ++i) {
    weights[i] = hom[i][3];
    points[i] = hom[i].head<3>() / hom[i][3];
  }
}

namespace {

// One Boehm insertion of u into span k = find_span(u):
//   Q_i = P_i                                  i <= k - p
//   Q_i = a_i P_i + (1 - a_i) P_{i-1}          k - p + 1 <= i <= k,  a_i = (u - t_i)/(t_{i+p} - t_i)
//   Q_i = P_{i-1}                              i >= k + 1
// (for u equal to an existing knot the last alphas are 0 and reproduce P_{i-1}).
HomogeneousCurve insert_once(const HomogeneousCurve& curve, double u) {
  const KnotVector& kv = curve.knots;
  const int p = kv.degree();
  const std::vector<double>& t = kv.knots();
  const int k = kv.find_span(u);
  const int n = kv.num_basis();
  HomogeneousPoints q(n + 1);
  for (int i = 0; i <= k - p; ++i) q[i] = curve.points[i];
  for (int i = k - p + 1; i <= k; ++i) {
    const double a = (u - t[i]) / (t[i + p] - t[i]);
    q[i] = a * curve.points[i] + (1.0 - a) * curve.points[i - 1];
  }
  for (int i = k + 1; i <= n; ++i) q[i] = curve.points[i - 1];
  std::vector<double> knots = t;
  knots.insert(knots.begin() + k + 1, u);
  return {KnotVector(p, std::move(knots)), std::move(q)};
}

}  // namespace

HomogeneousCurve insert_knot(const HomogeneousCurve& curve, double u, int times) {
  const KnotVector& kv = curve.knots;
  if (times < 0) throw std::invalid_argument("insert_knot: times must be >= 0");
  const double tol = kv.tolerance();
  if (!(u > kv.front() + tol && u < kv.back() - tol)) {
    std::ostringstream msg;
    msg << "insert_knot: " << u << " is not strictly inside (" << kv.front() << ", " << kv.back() << ")";
    throw std::invalid_argument(msg.str());
  }
  for (double k : kv.knots())
    if (std::abs(k - u) <= tol) u = k;  // snap: keep equal knots bit-identical
  if (kv.multiplicity(u) + times > kv.degree()) {
    std::ostringstream msg;
    msg << "insert_knot: inserting " << u << " " << times << " times gives multiplicity "
        << kv.multiplicity(u) + times << " > degree " << kv.degree();
    throw std::invalid_argument(msg.str());
  }
  HomogeneousCurve result = curve;
  for (int r = 0; r < times; ++r) result = insert_once(result, u);
  return result;
}

std::vector<double> expand_insertions(const std::vector<std::pair<double, int>>& insertions) {
  std::vector<double> values;
  for (const auto& [u, times] : insertions)
    values.insert(values.end(), static_cast<std::size_t>(std::max(times, 0)), u);
  return values;
}

namespace {

// The values snapped onto the existing knots within the knot tolerance and sorted; throws
// std::invalid_argument for a value not strictly inside the domain or a multiplicity above the degree.
std::vector<double> checked_new_knots(const KnotVector& kv, std::vector<double> values) {
  const double tol = kv.tolerance();
  const std::vector<double>& t = kv.knots();
  for (double& u : values) {
    if (!(u > kv.front() + tol && u < kv.back() - tol)) {
      std::ostringstream msg;
      msg << "insert_knots: " << u << " is not strictly inside (" << kv.front() << ", " << kv.back() << ")";
      throw std::invalid_argument(msg.str());
    }
    const auto at = std::lower_bound(t.begin(), t.end(), u - tol);
    if (at != t.end() && std::abs(*at - u) <= tol) u = *at;  // keep equal knots bit-identical
  }
  std::sort(values.begin(), values.end());
  for (std::size_t i = 0; i < values.size();) {
    std::size_t j = i;
    while (j < values.size() && values[j] == values[i]) ++j;
    const int multiplicity = kv.multiplicity(values[i]) + static_cast<int>(j - i);
    if (multiplicity > kv.degree()) {
      std::ostringstream msg;
      msg << "insert_knots: inserting " << values[i] << " " << j - i << " times gives multiplicity " << multiplicity
          << " > degree " << kv.degree();
      throw std::invalid_argument(msg.str());
    }
    i = j;
  }
  return values;
}

}  // namespace

// Piegl & Tiller, The NURBS Book, algorithm A5.4 (RefineKnotVectCurve), in homogeneous coordinates: the
// points outside the spans [a, b] that receive new knots are copied; from the right end, each new knot x_j
// (largest first) shifts the old knots above it and forms p new points by the Boehm alphas on the knot
// vector built so far. Indices as in the book: P_0..P_n, U_0..U_m, X_0..X_r.
HomogeneousCurve insert_knots(const HomogeneousCurve& curve, const std::vector<double>& values) {
  const KnotVector& kv = curve.knots;
  if (values.empty()) return curve;
  const std::vector<double> x = checked_new_knots(kv, values);
  const int p = kv.degree();
  const std::vector<double>& u = kv.knots();
  const int n = kv.num_basis() - 1, m = n + p + 1, r = static_cast<int>(x.size()) - 1;
  const int a = kv.find_span(x.front()), b = kv.find_span(x.back()) + 1;
  HomogeneousPoints q(static_cast<std::size_t>(n + r + 2));
  std::vector<double> ubar(static_cast<std::size_t>(m + r + 2));
  for (int j = 0; j <= a - p; ++j) q[j] = curve.points[j];
  for (int j = b - 1; j <= n; ++j) q[j + r + 1] = curve.points[j];
  for (int j = 0; j <= a; ++j) ubar[j] = u[j];
  for (int j = b + p; j <= m; ++j) ubar[j + r + 1] = u[j];
  int i = b + p - 1, k = b + p + r;
  for (int j = r; j >= 0; --j) {
    while (x[j] <= u[i] && i > a) {
      q[k - p - 1] = curve.points[i - p - 1];
      ubar[k] = u[i];
      --k;
      --i;
    }
    q[k - p - 1] = q[k - p];
    for (int l = 1; l <= p; ++l) {
      const int ind = k - p + l;
      const double alpha = ubar[k + l] - x[j];
      if (alpha == 0.0) {
        q[ind - 1] = q[ind];
      } else {
        const double a_l = alpha / (ubar[k + l] - u[i - p + l]);
        q[ind - 1] = a_l * q[ind - 1] + (1.0 - a_l) * q[ind];
      }
    }
    ubar[k] = x[j];
    --k;
  }
  return {KnotVector(p, std::move(ubar)), std::move(q)};
}

HomogeneousCurve elevate_degree(const HomogeneousCurve& curve, int by) {
  if (by < 0) throw std::invalid_argument("elevate_degree: `by` must be >= 0");
  if (by == 0) return curve;
  const KnotVector& old_kv = curve.knots;
  const int p = old_kv.degree();
  const int new_p = p + by;
  std::vector<double> knots;
  for (double value : old_kv.unique_knots())
    knots.insert(knots.end(), old_kv.multiplicity(value) + by, value);
  KnotVector new_kv(new_p, std::move(knots));

  // Evaluate the old curve at the Greville abscissae xi_i = (t_{i+1} + ... + t_{i+p}) / p of the new
  // knots and solve N(xi) Q = C(xi).
  const int n = new_kv.num_basis();
  const std::vector<double>& t = new_kv.knots();
  Eigen::MatrixXd collocation = Eigen::MatrixXd::Zero(n, n);
  Eigen::MatrixXd rhs(n, 4);
  for (int i = 0; i < n; ++i) {
    double xi = 0.0;
    for (int m = 1; m <= new_p; ++m) xi += t[i + m];
    xi /= new_p;
    const int new_span = new_kv.find_span(xi);
    const Eigen::MatrixXd new_basis = bspline_basis_derivs(new_kv, new_span, xi, 0);
    for (int j = 0; j <= new_p; ++j) collocation(i, new_span - new_p + j) = new_basis(0, j);
    const int old_span = old_kv.find_span(xi);
    const Eigen::MatrixXd old_basis = bspline_basis_derivs(old_kv, old_span, xi, 0);
    Eigen::Vector4d value = Eigen::Vector4d::Zero();
    for (int j = 0; j <= p; ++j) value += old_basis(0, j) * curve.points[old_span - p + j];
    rhs.row(i) = value.transpose();
  }
  const Eigen::MatrixXd solution = collocation.partialPivLu().solve(rhs);
  HomogeneousPoints q(n);
  for (int i = 0; i < n; ++i) q[i] = solution.row(i).transpose();
  // The end points are interpolated exactly by both curves; copy them to avoid any round-off there.
  q.front() = curve.points.front();
  q.back() = curve.points.back();
  // A polynomial (all weights equal) stays polynomial: the constant weight function has constant
  // coefficients in any spline space, so set them exactly instead of keeping solver round-off.
  const double w0 = curve.points.front()[3];
  const bool constant_weight = std::all_of(curve.points.begin(), curve.points.end(),
                                           [&](const Eigen::Vector4d& h) { return h[3] == w0; });
  if (constant_weight)
    for (Eigen::Vector4d& h : q) h[3] = w0;
  return {std::move(new_kv), std::move(q)};
}

std::vector<std::pair<double, int>> uniform_insertions(const KnotVector& kv, int continuity,
                                                       int n_elements) {
  std::vector<double> grid;
  const double a = kv.front(), b = kv.back();
  for (int k = 1; k < n_elements; ++k) grid.push_back(a + (b - a) * k / n_elements);
  return grid_insertions(kv, continuity, grid);
}

std::vector<std::pair<double, int>> grid_insertions(const KnotVector& kv, int continuity,
                                                    const std::vector<double>& grid) {
  std::vector<std::pair<double, int>> insertions;
  const int target = kv.degree() - continuity;
  for (double u : grid) {
    const int missing = target - kv.multiplicity(u);
    if (missing > 0) insertions.emplace_back(u, missing);
  }
  return insertions;
}

std::vector<double> geometric_grid(double a, double b, int n_elements, double ratio) {
  if (!(ratio > 0.0) || !std::isfinite(ratio)) throw std::invalid_argument("geometric_grid: ratio must be > 0");
  if (n_elements < 1 || !(a < b)) throw std::invalid_argument("geometric_grid: need n_elements >= 1 and a < b");
  std::vector<double> grid;
  const double total = std::pow(ratio, n_elements) - 1.0;
  for (int k = 1; k < n_elements; ++k)
    grid.push_back(ratio == 1.0 ? a + (b - a) * k / n_elements : a + (b - a) * ((std::pow(ratio, k) - 1.0) / total));
  return grid;
}

void check_refine_request(int current_degree, int degree, int continuity, int n_elements) {
  if (degree < current_degree)
    throw std::invalid_argument("refine: degree " + std::to_string(degree) + " is below the current " +
                                std::to_string(current_degree) + " (degree reduction is not supported)");
  if (continuity < 0 || continuity >= degree)
    throw std::invalid_argument("refine: continuity must be in [0, degree-1], got " +
                                std::to_string(continuity));
  if (n_elements < 1) throw std::invalid_argument("refine: n_elements must be >= 1");
}

}  // namespace fibrane::spline
