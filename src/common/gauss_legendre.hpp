#pragma once
// Gauss-Legendre quadrature on the reference interval [-1, 1], shared by the element loops (src/spline,
// src/model) and the laws (thickness integrals in src/laws).
#include <vector>

namespace fibrane {

struct QuadratureRule {
  std::vector<double> points, weights;  // points increasing, on [-1, 1]; weights sum to 2
};

// n-point rule, exact for polynomials of degree 2n - 1. Any n >= 1 (throws std::invalid_argument
// otherwise). Nodes are the roots of P_n found by Newton's method from Chebyshev-like initial guesses,
// weights w_i = 2 / ((1 - x_i^2) P_n'(x_i)^2), both to machine precision.
QuadratureRule gauss_legendre(int n);

}  // namespace fibrane
