// Basis functions: partition of unity, derivatives vs central finite differences, known values.
//
// Finite-difference step: the central difference (f(u+h) - f(u-h)) / 2h has truncation error
// h^2 |f'''| / 6 and round-off error ~ eps |f| / h. On these O(1) domains with O(1)-O(100) derivatives,
// h = 1e-5 balances them at ~1e-10..1e-8 absolute, safely below the 1e-7 relative tolerance (relative to
// max(1, |derivative|)). Sample points are kept 1e-3 away from knots so u +- h stays on one piece.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "spline/basis.hpp"
#include "spline/curve.hpp"
#include "spline/surface.hpp"
#include "test_helpers.hpp"

namespace fibrane::spline {
namespace {

using testing::param_away_from_knots;
constexpr double kStep = 1e-5;
constexpr double kRelTol = 1e-7;
void expect_fd_close(double analytic, double fd, const char* what) {
  EXPECT_LE(std::abs(analytic - fd), kRelTol * std::max(1.0, std::abs(analytic)))
      << what << ": analytic " << analytic << " vs FD " << fd;
}

TEST(Basis, MatchesQuadraticBernsteinPolynomials) {
  // On one Bezier element the B-splines are Bernstein polynomials: (1-u)^2, 2u(1-u), u^2.
  const KnotVector kv(2, {0, 0, 0, 1, 1, 1});
  const double u = 0.3;
  const Eigen::MatrixXd n = bspline_basis_derivs(kv, kv.find_span(u), u, 3);
  EXPECT_NEAR(n(0, 0), 0.49, 1e-15);
  EXPECT_NEAR(n(0, 1), 0.42, 1e-15);
  EXPECT_NEAR(n(0, 2), 0.09, 1e-15);
  EXPECT_NEAR(n(1, 0), -1.4, 1e-14);
  EXPECT_NEAR(n(1, 1), 0.8, 1e-14);
  EXPECT_NEAR(n(1, 2), 0.6, 1e-14);
  EXPECT_NEAR(n(2, 0), 2.0, 1e-14);
  EXPECT_NEAR(n(2, 1), -4.0, 1e-14);
  EXPECT_NEAR(n(2, 2), 2.0, 1e-14);
  EXPECT_EQ(n.row(3).norm(), 0.0);  // beyond the degree
}

// High degrees: the recursion's tables sit on the stack up to degree 21 and on the heap above; both give
// the Bernstein polynomials C(p, j) u^j (1 - u)^(p - j) and their first derivatives (to 1e-12 relative:
// binomial coefficients up to ~3e6 at degree 24, round-off growing with the degree).
TEST(Basis, HighDegreesMatchBernsteinPolynomials) {
  for (const int p : {20, 21, 22, 24}) {
    std::vector<double> knots(static_cast<std::size_t>(p + 1), 0.0);
    knots.resize(static_cast<std::size_t>(2 * p + 2), 1.0);
    const KnotVector kv(p, knots);
    const double u = 0.37;
    const Eigen::MatrixXd n = bspline_basis_derivs(kv, kv.find_span(u), u, 1);
    double binomial = 1.0;
    for (int j = 0; j <= p; ++j) {
      const double value = binomial * std::pow(u, j) * std::pow(1 - u, p - j);
      const double slope = binomial * ((j > 0 ? j * std::pow(u, j - 1) * std::pow(1 - u, p - j) : 0.0) -
                                       (j < p ? (p - j) * std::pow(u, j) * std::pow(1 - u, p - j - 1) : 0.0));
      EXPECT_NEAR(n(0, j), value, 1e-12 * std::max(1.0, std::abs(value))) << "degree " << p << ", j " << j;
      EXPECT_NEAR(n(1, j), slope, 1e-12 * std::max(1.0, std::abs(slope)) * p) << "degree " << p << ", j " << j;
      binomial = binomial * (p - j) / (j + 1);
    }
  }
}

TEST(Basis, BSplinePartitionOfUnityAndDerivativesSumToZero) {
  std::mt19937 rng(1);
  for (const KnotVector& kv : {testing::sample_knots_cubic(), testing::sample_knots_quadratic(),
                               KnotVector::open_uniform(5, 7, 2)}) {
    std::uniform_real_distribution<double> dist(kv.front(), kv.back());
    for (int s = 0; s < 200; ++s) {
      const double u = s == 0 ? kv.front() : s == 1 ? kv.back() : dist(rng);
      const Eigen::MatrixXd n = bspline_basis_derivs(kv, kv.find_span(u), u, 2);
      EXPECT_NEAR(n.row(0).sum(), 1.0, 1e-13);
      EXPECT_GE(n.row(0).minCoeff(), 0.0);
      // Derivative sums vanish; their size scales with (p / knot spacing)^k ~ 1e2, hence 1e-11.
      EXPECT_NEAR(n.row(1).sum(), 0.0, 1e-11);
      EXPECT_NEAR(n.row(2).sum(), 0.0, 1e-10);
    }
  }
}

TEST(Basis, BSplineDerivativesMatchFiniteDifferences) {
  std::mt19937 rng(2);
  const KnotVector kv = testing::sample_knots_cubic();
  for (int s = 0; s < 50; ++s) {
    const double u = param_away_from_knots(rng, kv, 1e-3);
    const int span = kv.find_span(u);
    const Eigen::MatrixXd n = bspline_basis_derivs(kv, span, u, 3);
    const Eigen::MatrixXd plus = bspline_basis_derivs(kv, span, u + kStep, 3);
    const Eigen::MatrixXd minus = bspline_basis_derivs(kv, span, u - kStep, 3);
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j <= 3; ++j) expect_fd_close(n(k + 1, j), (plus(k, j) - minus(k, j)) / (2 * kStep), "dN");
  }
}

TEST(Basis, RationalCurveBasis) {
  std::mt19937 rng(3);
  const NurbsCurve curve = testing::random_curve(rng, true);
  ASSERT_TRUE(curve.is_rational());
  for (int s = 0; s < 100; ++s) {
    const double u = param_away_from_knots(rng, curve.knots(), 1e-3);
    const CurveBasis b = curve.basis(u, 2);
    EXPECT_NEAR(b.R.row(0).sum(), 1.0, 1e-13);
    const CurveBasis plus = curve.basis(u + kStep, 2), minus = curve.basis(u - kStep, 2);
    ASSERT_EQ(plus.first, b.first);
    for (int j = 0; j < b.R.cols(); ++j) {
      expect_fd_close(b.R(1, j), (plus.R(0, j) - minus.R(0, j)) / (2 * kStep), "R_u");
      expect_fd_close(b.R(2, j), (plus.R(1, j) - minus.R(1, j)) / (2 * kStep), "R_uu");
    }
    // Curve derivatives are the basis derivatives applied to the control points.
    const Eigen::Vector3d d1 = (curve.point(u + kStep) - curve.point(u - kStep)) / (2 * kStep);
    const Eigen::Vector3d d2 = (curve.derivative(u + kStep, 1) - curve.derivative(u - kStep, 1)) / (2 * kStep);
    EXPECT_LE((curve.derivative(u, 1) - d1).norm(), kRelTol * std::max(1.0, d1.norm()));
    EXPECT_LE((curve.derivative(u, 2) - d2).norm(), kRelTol * std::max(1.0, d2.norm()));
  }
}

// Derivatives beyond the 7th (rationalize_curve_basis's arrays then on the heap): a rational curve raised
// to degree 10 keeps the partition of unity in every derivative (the rows k >= 1 sum to zero, to round-off
// of the row's magnitude grown by the quotient rule's k terms: 1e-9 of it), and the 9th derivative is the
// central difference of the 8th (truncation h^2 R^(11) / 6 with h = 1e-5, round-off 1e-16 |R^(8)| / h:
// both far below 1e-5 of the row's largest entry). A wrong row on the heap path breaks either.
TEST(Basis, RationalCurveBasisOfHighDerivatives) {
  std::mt19937 rng(8);
  NurbsCurve curve = testing::random_curve(rng, true);
  curve.elevate_degree(10 - curve.degree());
  ASSERT_EQ(curve.degree(), 10);
  for (int s = 0; s < 20; ++s) {
    const double u = param_away_from_knots(rng, curve.knots(), 1e-2);
    const CurveBasis b = curve.basis(u, 10);
    ASSERT_EQ(b.R.rows(), 11);
    EXPECT_NEAR(b.R.row(0).sum(), 1.0, 1e-13);
    for (int k = 1; k <= 10; ++k) EXPECT_NEAR(b.R.row(k).sum(), 0.0, 1e-9 * b.R.row(k).cwiseAbs().sum()) << k;
    const double h = 1e-5;
    const CurveBasis plus = curve.basis(u + h, 10), minus = curve.basis(u - h, 10);
    for (int j = 0; j < b.R.cols(); ++j) {
      const double fd = (plus.R(8, j) - minus.R(8, j)) / (2 * h);
      EXPECT_NEAR(b.R(9, j), fd, 1e-5 * b.R.row(9).cwiseAbs().maxCoeff()) << j;
    }
  }
}

// The basis into kept storage is the value-returning basis, bit for bit.
TEST(Basis, SurfaceBasisIntoKeptStorageIsTheSameBits) {
  std::mt19937 rng(9);
  const NurbsSurface surface = testing::random_surface(rng, true);
  SurfaceBasis kept;
  Eigen::MatrixXd nu, nv;
  for (int s = 0; s < 20; ++s) {
    const double u = param_away_from_knots(rng, surface.knots(0), 1e-3);
    const double v = param_away_from_knots(rng, surface.knots(1), 1e-3);
    surface.basis(u, v, kept, nu, nv);
    const SurfaceBasis b = surface.basis(u, v);
    EXPECT_EQ(kept.indices, b.indices);
    EXPECT_EQ((kept.R - b.R).cwiseAbs().maxCoeff(), 0.0);
  }
}

TEST(Basis, RationalSurfaceBasis) {
  std::mt19937 rng(4);
  const NurbsSurface surface = testing::random_surface(rng, true);
  ASSERT_TRUE(surface.is_rational());
  for (int s = 0; s < 60; ++s) {
    const double u = param_away_from_knots(rng, surface.knots(0), 1e-3);
    const double v = param_away_from_knots(rng, surface.knots(1), 1e-3);
    const SurfaceBasis b = surface.basis(u, v);
    EXPECT_NEAR(b.R.row(0).sum(), 1.0, 1e-13);
    const SurfaceBasis up = surface.basis(u + kStep, v), um = surface.basis(u - kStep, v);
    const SurfaceBasis vp = surface.basis(u, v + kStep), vm = surface.basis(u, v - kStep);
    ASSERT_EQ(up.indices, b.indices);
    ASSERT_EQ(vm.indices, b.indices);
    for (int a = 0; a < b.R.cols(); ++a) {
      expect_fd_close(b.R(1, a), (up.R(0, a) - um.R(0, a)) / (2 * kStep), "R_u");
      expect_fd_close(b.R(2, a), (vp.R(0, a) - vm.R(0, a)) / (2 * kStep), "R_v");
      expect_fd_close(b.R(3, a), (up.R(1, a) - um.R(1, a)) / (2 * kStep), "R_uu");
      expect_fd_close(b.R(4, a), (vp.R(1, a) - vm.R(1, a)) / (2 * kStep), "R_uv");
      expect_fd_close(b.R(4, a), (up.R(2, a) - um.R(2, a)) / (2 * kStep), "R_vu");
      expect_fd_close(b.R(5, a), (vp.R(2, a) - vm.R(2, a)) / (2 * kStep), "R_vv");
    }
  }
}

TEST(Basis, NonRationalSurfaceIsTensorProduct) {
  std::mt19937 rng(5);
  const NurbsSurface surface = testing::random_surface(rng, false);
  const double u = 0.41, v = 0.77;
  const SurfaceBasis b = surface.basis(u, v);
  const Eigen::MatrixXd nu = bspline_basis_derivs(surface.knots(0), surface.knots(0).find_span(u), u, 2);
  const Eigen::MatrixXd nv = bspline_basis_derivs(surface.knots(1), surface.knots(1).find_span(v), v, 2);
  const int p = surface.degree(0);
  for (int a = 0; a < b.R.cols(); ++a) {
    const int i = a % (p + 1), j = a / (p + 1);
    EXPECT_NEAR(b.R(0, a), nu(0, i) * nv(0, j), 1e-15);
    EXPECT_NEAR(b.R(4, a), nu(1, i) * nv(1, j), 1e-12);
  }
}

TEST(Basis, BasisInUsesTheGivenSpanAtElementBoundaries) {
  std::mt19937 rng(6);
  const NurbsSurface surface = testing::random_surface(rng, true);
  // u = 0.7 is a double knot of the quadratic u-direction (C0): the left element's pieces differ.
  const SurfaceElement left = surface.elements()[1];
  ASSERT_DOUBLE_EQ(left.u1, 0.7);
  const SurfaceBasis at_edge = surface.basis_in(left.span_u, left.span_v, 0.7, left.v0);
  const SurfaceBasis inside = surface.basis_in(left.span_u, left.span_v, 0.7 - 1e-9, left.v0);
  EXPECT_EQ(at_edge.indices, inside.indices);
  EXPECT_LE((at_edge.R.row(1) - inside.R.row(1)).norm(), 1e-6 * at_edge.R.row(1).norm());
}

}  // namespace
}  // namespace fibrane::spline
