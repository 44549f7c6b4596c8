#pragma once
#include "common/gauss_legendre.hpp"
// Test-only geometry for the beam kernels: B-spline basis with derivatives on an open knot vector
// (Cox-de Boor recursion), Gauss-Legendre rules and random curved/deformed beam states. Independent
// of src/spline on purpose, so the kernel tests do not depend on a module written in parallel.
#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <vector>

#include "beam/beam.hpp"

namespace fibrane::beam::testing {

// Open uniform knot vector with `elements` spans on [0, 1].
inline std::vector<double> open_knots(int degree, int elements) {
  std::vector<double> u(degree, 0.0);
  for (int e = 0; e <= elements; ++e) u.push_back(static_cast<double>(e) / elements);
  u.insert(u.end(), degree, 1.0);
  return u;
}

// d-th derivative of N_{i,k} at xi (0/0 := 0); `span` is the knot span containing xi.
inline double basis_derivative(const std::vector<double>& u, int i, int k, int d, double xi, int span) {
  if (d > k) return 0.0;
  if (k == 0) return i == span ? 1.0 : 0.0;
  auto ratio = [](double num, double den) { return den > 0 ? num / den : 0.0; };
  if (d == 0)
    return ratio(xi - u[i], u[i + k] - u[i]) * basis_derivative(u, i, k - 1, 0, xi, span) +
           ratio(u[i + k + 1] - xi, u[i + k + 1] - u[i + 1]) * basis_derivative(u, i + 1, k - 1, 0, xi, span);
  return k * (ratio(basis_derivative(u, i, k - 1, d - 1, xi, span), u[i + k] - u[i]) -
              ratio(basis_derivative(u, i + 1, k - 1, d - 1, xi, span), u[i + k + 1] - u[i + 1]));
}

// Basis (rows R, R_xi, R_xixi) of the degree+1 functions that are non-zero at xi; `first` receives
// the index of the first one.
inline BasisDerivs bspline_basis(const std::vector<double>& u, int degree, double xi, int* first) {
  int span = degree;
  while (span + 1 < static_cast<int>(u.size()) - degree - 1 && xi >= u[span + 1]) ++span;
  BasisDerivs R(3, degree + 1);
  for (int j = 0; j <= degree; ++j)
    for (int d = 0; d < 3; ++d) R(d, j) = basis_derivative(u, span - degree + j, degree, d, xi, span);
  if (first) *first = span - degree;
  return R;
}

// Single Bezier element of the given degree on [0, 1].
inline BasisDerivs bezier_basis(int degree, double xi) {
  return bspline_basis(open_knots(degree, 1), degree, xi, nullptr);
}

// Gauss-Legendre points and weights on [0, 1] (the project's rule mapped from [-1, 1]).
inline void gauss_legendre(int n, std::vector<double>& points, std::vector<double>& weights) {
  const auto rule = ::fibrane::gauss_legendre(n);
  points.resize(n);
  weights.resize(n);
  for (int i = 0; i < n; ++i) {
    points[i] = 0.5 * (rule.points[i] + 1.0);
    weights[i] = 0.5 * rule.weights[i];
  }
}

inline Eigen::Matrix3d random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> normal;
  Eigen::Quaterniond qr(normal(rng), normal(rng), normal(rng), normal(rng));
  return qr.normalized().toRotationMatrix();
}

// Curved reference axis: control points along x with random transverse offsets, randomly rotated.
inline Eigen::Matrix3Xd random_reference(std::mt19937& rng, int n_cp, double length = 1.0) {
  std::uniform_real_distribution<double> offset(-0.25, 0.25);
  Eigen::Matrix3Xd X(3, n_cp);
  for (int j = 0; j < n_cp; ++j)
    X.col(j) = Eigen::Vector3d(length * j / (n_cp - 1.0), offset(rng), offset(rng));
  return random_rotation(rng) * X;
}

// Bent, stretched and twisted current state: X plus random displacements and twist angles.
inline BeamDofs random_current(std::mt19937& rng, const Eigen::Matrix3Xd& X, double size = 0.15,
                               double twist = 0.6) {
  std::uniform_real_distribution<double> disp(-size, size), angle(-twist, twist);
  BeamDofs q(4, X.cols());
  for (Eigen::Index j = 0; j < X.cols(); ++j) {
    q.col(j).head<3>() = X.col(j) + Eigen::Vector3d(disp(rng), disp(rng), disp(rng));
    q(3, j) = angle(rng);
  }
  return q;
}

inline BeamDofs reference_dofs(const Eigen::Matrix3Xd& X) {
  BeamDofs q = BeamDofs::Zero(4, X.cols());
  q.topRows<3>() = X;
  return q;
}

// Section with O(1) stiffnesses of distinct sizes, so every strain term is visible in the checks.
inline BeamSection test_section() { return BeamSection::general(1.0, 0.25, 1.0, 0.3, 0.5, 0.7); }

}  // namespace fibrane::beam::testing
