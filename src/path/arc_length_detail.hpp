#pragma once
// Small numerical helpers shared by the files of the arc-length method (arc_length*.cpp).
#include <cmath>

namespace fibrane::solve::arc_length_detail {

inline int sign_of(double x) { return x > 0 ? 1 : (x < 0 ? -1 : 0); }

// The two roots of a x^2 + b x + c = 0 (a > 0) without cancellation; false if they are complex.
inline bool quadratic_roots(double a, double b, double c, double& x1, double& x2) {
  const double discriminant = b * b - 4 * a * c;
  if (!(discriminant >= 0)) return false;
  const double q = -0.5 * (b + (b >= 0 ? 1 : -1) * std::sqrt(discriminant));
  x1 = q / a;
  x2 = q != 0 ? c / q : x1;
  return true;
}

}  // namespace fibrane::solve::arc_length_detail
