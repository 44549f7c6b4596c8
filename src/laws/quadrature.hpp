#pragma once
// Quadrature used by the reference
// integrators (adaptive Gauss-Kronrod). Header templates so that the integrands inline.
#include <cmath>
#include <stdexcept>
#include <vector>

#include "common/gauss_legendre.hpp"

namespace fibrane::laws {


namespace detail {
// Gauss-Kronrod 7/15 abscissae and weights on [-1, 1] (standard tabulated values).
inline constexpr double kKronrodNodes[8] = {
    0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
    0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
    0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
    0.207784955007898467600689403773245, 0.000000000000000000000000000000000};
inline constexpr double kKronrodWeights[8] = {
    0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
    0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
    0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
    0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
inline constexpr double kGaussWeights[4] = {
    0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
    0.381830050505118944950369775488975, 0.417959183673469387755102040816327};

// One G7/K15 panel; error is |K15 - G7|, abs_integral the panel integral of |f|.
template <class F>
double kronrod_segment(F& f, double a, double b, double& error, double* abs_integral = nullptr) {
  const double centre = 0.5 * (a + b), half = 0.5 * (b - a);
  const double fc = f(centre);
  double kronrod = kKronrodWeights[7] * fc, gauss = kGaussWeights[3] * fc;
  double magnitude = kKronrodWeights[7] * std::abs(fc);
  for (int i = 0; i < 7; ++i) {
    const double x = half * kKronrodNodes[i];
    const double left = f(centre - x), right = f(centre + x);
    kronrod += kKronrodWeights[i] * (left + right);
    magnitude += kKronrodWeights[i] * (std::abs(left) + std::abs(right));
    if (i % 2 == 1) gauss += kGaussWeights[i / 2] * (left + right);
  }
  error = std::abs((kronrod - gauss) * half);
  if (abs_integral) *abs_integral = magnitude * std::abs(half);
  return kronrod * half;
}

// Local criterion: a panel is accepted when its error is below rel_tol times its integral of |f|
// (so the total error is below rel_tol times the integral of |f|), or below its share of an
// absolute tolerance. A purely absolute, halving tolerance would recurse without end on integrands
// that carry the noise of an inner adaptive integral.
template <class F>
double adaptive_segment(F& f, double a, double b, double rel_tol, double tol, int depth, double& err,
                        long& panels_left) {
  double e = 0, magnitude = 0;
  const double value = kronrod_segment(f, a, b, e, &magnitude);
  if (e <= tol || e <= std::max(rel_tol, 1e-14) * magnitude || depth <= 0 || --panels_left <= 0 || std::abs(b - a) < 1e-15 * (std::abs(a) + std::abs(b))) {
    err += e;
    return value;
  }
  const double mid = 0.5 * (a + b);
  return adaptive_segment(f, a, mid, rel_tol, 0.5 * tol, depth - 1, err, panels_left) +
         adaptive_segment(f, mid, b, rel_tol, 0.5 * tol, depth - 1, err, panels_left);
}
}  // namespace detail

// Adaptive Gauss-Kronrod (7/15) integral of f over [a, b] to about rel_tol relative accuracy
// (absolute floor abs_tol). Bisection depth is limited to 30 levels and 4000 panels.
template <class F>
double integrate(F f, double a, double b, double rel_tol = 1e-12, double abs_tol = 0.0) {
  double err = 0;
  long panels_left = 4000;  // budget: integrands noisier than rel_tol must not recurse forever
  return detail::adaptive_segment(f, a, b, rel_tol, abs_tol, 30, err, panels_left);
}

// Integral over [a, infinity) by the map x = a + L t / (1 - t), t in [0, 1).
template <class F>
double integrate_to_infinity(F f, double a, double length_scale, double rel_tol = 1e-12) {
  auto mapped = [&](double t) {
    if (t >= 1.0) return 0.0;
    const double one_minus = 1.0 - t;
    return f(a + length_scale * t / one_minus) * length_scale / (one_minus * one_minus);
  };
  return integrate(mapped, 0.0, 1.0, rel_tol);
}

}  // namespace fibrane::laws
