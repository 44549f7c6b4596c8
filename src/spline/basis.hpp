#pragma once
// B-spline basis functions and their derivatives (Cox-de Boor recursion).
#include <Eigen/Dense>

#include "spline/knot_vector.hpp"

namespace fibrane::spline {

// Derivatives of the p+1 basis functions that are non-zero on knot span `span` (as returned by
// kv.find_span(u)), evaluated at u:
//   result(k, j) = d^k N_{span-p+j, p}(u) / du^k,   k = 0..n_deriv, j = 0..p.
// Rows k > p are zero (a degree-p polynomial piece). n_deriv >= 0.
Eigen::MatrixXd bspline_basis_derivs(const KnotVector& kv, int span, double u, int n_deriv);
// The same into `out`, whose storage is kept where it has the size (no allocation in loops that call it
// on many threads).
void bspline_basis_derivs(const KnotVector& kv, int span, double u, int n_deriv, Eigen::MatrixXd& out);

}  // namespace fibrane::spline
