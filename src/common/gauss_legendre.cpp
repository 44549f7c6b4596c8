#include "common/gauss_legendre.hpp"

#include <cmath>
#include <numbers>
#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

namespace fibrane {
namespace {

// P_n(x) and P_n'(x) by the three-term recurrence (k+1) P_{k+1} = (2k+1) x P_k - k P_{k-1}.
std::pair<double, double> legendre_and_derivative(int n, double x) {
  double p_prev = 1.0, p = x;
  for (int k = 1; k < n; ++k) {
    const double p_next = ((2.0 * k + 1.0) * x * p - k * p_prev) / (k + 1.0);
    p_prev = p;
    p = p_next;
  }
  // P_n' = n (x P_n - P_{n-1}) / (x^2 - 1); x is never +-1 at the interior roots.
  const double dp = n * (x * p - p_prev) / (x * x - 1.0);
  return {p, dp};
}

}  // namespace

QuadratureRule gauss_legendre(int n) {
  if (n < 1) throw std::invalid_argument("gauss_legendre: need n >= 1, got " + std::to_string(n));
  QuadratureRule rule;
  rule.points.resize(n);
  rule.weights.resize(n);
  if (n == 1) {
    rule.points[0] = 0.0;
    rule.weights[0] = 2.0;
    return rule;
  }
  for (int i = 0; i < (n + 1) / 2; ++i) {
    // Root i (descending from +1) lies close to cos(pi (i + 3/4) / (n + 1/2)).
    double x = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5));
    double dp = 0.0;
    for (int iter = 0; iter < 100; ++iter) {
      const auto [p, dpx] = legendre_and_derivative(n, x);
      dp = dpx;
      const double step = p / dp;
      x -= step;
      if (std::abs(step) <= 1e-16 * std::max(1.0, std::abs(x))) break;
    }
    dp = legendre_and_derivative(n, x).second;
    const double w = 2.0 / ((1.0 - x * x) * dp * dp);
    // Symmetric pair: -x at index i, +x at index n-1-i (points increasing).
    rule.points[i] = -x;
    rule.points[n - 1 - i] = x;
    rule.weights[i] = rule.weights[n - 1 - i] = w;
  }
  if (n % 2 == 1) rule.points[n / 2] = 0.0;  // exact middle node
  return rule;
}

}  // namespace fibrane
