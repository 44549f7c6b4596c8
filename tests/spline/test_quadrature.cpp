#include <gtest/gtest.h>

#include <cmath>

#include "spline/quadrature.hpp"

namespace fibrane::spline {
namespace {

// int_{-1}^{1} x^k dx = 2/(k+1) for even k, 0 for odd k.
double monomial_integral(int k) { return k % 2 == 0 ? 2.0 / (k + 1) : 0.0; }

TEST(GaussLegendre, IntegratesDegree2nMinus1Exactly) {
  for (int n = 1; n <= 10; ++n) {
    const QuadratureRule rule = gauss_legendre(n);
    ASSERT_EQ(rule.points.size(), static_cast<std::size_t>(n));
    for (int k = 0; k <= 2 * n - 1; ++k) {
      double sum = 0.0;
      for (int i = 0; i < n; ++i) sum += rule.weights[i] * std::pow(rule.points[i], k);
      // Sum of n terms of size <= 2 with nodes/weights at machine precision: 1e-14 is ~50 ulps.
      EXPECT_NEAR(sum, monomial_integral(k), 1e-14) << "n=" << n << " k=" << k;
    }
    // Degree 2n is not integrated exactly: the rule is the Gauss rule, not something of higher order.
    double sum = 0.0;
    for (int i = 0; i < n; ++i) sum += rule.weights[i] * std::pow(rule.points[i], 2 * n);
    EXPECT_GT(std::abs(sum - monomial_integral(2 * n)), 1e-6) << "n=" << n;
    for (int i = 1; i < n; ++i) EXPECT_LT(rule.points[i - 1], rule.points[i]);
  }
}

TEST(GaussLegendre, KnownNodesAndLargeN) {
  const QuadratureRule two = gauss_legendre(2);
  EXPECT_NEAR(two.points[1], 1.0 / std::sqrt(3.0), 2.3e-16);  // 2 ulps
  EXPECT_NEAR(two.weights[0], 1.0, 1e-15);
  const QuadratureRule many = gauss_legendre(40);
  double sum = 0.0, integral = 0.0;
  for (int i = 0; i < 40; ++i) {
    sum += many.weights[i];
    integral += many.weights[i] * std::exp(many.points[i]);
  }
  EXPECT_NEAR(sum, 2.0, 1e-13);
  EXPECT_NEAR(integral, std::exp(1.0) - std::exp(-1.0), 1e-13);  // smooth: converged to round-off
  EXPECT_THROW(gauss_legendre(0), std::invalid_argument);
}

}  // namespace
}  // namespace fibrane::spline
