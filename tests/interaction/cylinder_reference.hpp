#pragma once
// Reference energies of two straight solid cylinders interacting by the point-pair law k r^-m (paper
// Eq. 1, unit densities), by direct numerical integration over both volumes, reduced analytically only
// where exact:
//   - along an infinite axis: int (rho^2 + z^2)^(-m/2) dz = c_m rho^(1-m), c_m = sqrt(pi) G((m-1)/2) / G(m/2);
//   - over a disk of radius R for a point at distance s > R from its centre, radially in polar coordinates
//     about the point: I(s) = int (r_1^(3-m) - r_2^(3-m)) / (m-3) dtheta, r_1 = (s^2 - R^2) / r_2,
//     r_2 = s cos theta + R cos phi, sin theta = (R / s) sin phi (substitution that removes the end-point
//     square roots).
// The remaining integrals (phi; the other section; the crossed fiber's length) are composite
// Gauss-Legendre rules on panels graded geometrically towards the near-contact point, `points` per panel.
#include <algorithm>
#include <cmath>
#include <functional>

#include "common/gauss_legendre.hpp"

namespace fibrane::interaction::test {

// int_a^b f over panels [a, a + L q^k] graded towards a (ratio 1/2, down to L * 1e-9), `points` each.
inline double graded_integral(const std::function<double(double)>& f, double a, double b, int points) {
  const auto rule = gauss_legendre(points);
  double sum = 0, hi = b - a;
  while (hi > (b - a) * 1e-9) {
    const double lo = 0.5 * hi, mid = a + 0.5 * (lo + hi), half = 0.5 * (hi - lo);
    for (std::size_t i = 0; i < rule.points.size(); ++i) sum += rule.weights[i] * half * f(mid + half * rule.points[i]);
    hi = lo;
  }
  const double half = 0.5 * hi;  // the last panel [a, a + hi]
  for (std::size_t i = 0; i < rule.points.size(); ++i) sum += rule.weights[i] * half * f(a + half * (1 + rule.points[i]));
  return sum;
}

// c_m.
inline double line_factor(double m) { return std::sqrt(M_PI) * std::tgamma(0.5 * (m - 1)) / std::tgamma(0.5 * m); }

// I(s) * c_m: the potential of a unit point at distance s from the axis of an infinite cylinder of radius R.
inline double point_cylinder(double m, double radius, double s, int points) {
  auto integrand = [&](double phi) {
    const double sin_theta = radius / s * std::sin(phi), cos_theta = std::sqrt(1 - sin_theta * sin_theta);
    const double r2 = s * cos_theta + radius * std::cos(phi), r1 = (s * s - radius * radius) / r2;
    const double dtheta = radius / s * std::cos(phi) / cos_theta;
    return (std::pow(r1, 3 - m) - std::pow(r2, 3 - m)) / (m - 3) * dtheta;
  };
  return 2 * line_factor(m) * graded_integral(integrand, 0.0, 0.5 * M_PI, points);
}

// Energy per unit length of two parallel cylinders (radii ra, rb) with axes at distance d.
inline double parallel_cylinders(double m, double ra, double rb, double d, int points) {
  // Over section A by the distance s from B's axis: arc of half-angle psi(s) inside A, s = d - ra + 2 ra u^2.
  auto integrand = [&](double u) {
    const double s = d - ra + 2 * ra * u * u, ds = 4 * ra * u;
    const double cos_psi = std::clamp((s * s + d * d - ra * ra) / (2 * s * d), -1.0, 1.0);
    return point_cylinder(m, rb, s, points) * 2 * s * std::acos(cos_psi) * ds;
  };
  return graded_integral(integrand, 0.0, 1.0, points);
}

// Energy of two infinite cylinders crossed at right angles, axes at distance d (A along x at height d,
// B along y).
inline double crossed_cylinders(double m, double ra, double rb, double d, int points) {
  // The length of A is cut at |x| = 40 (ra + rb), where the rest is below 1e-8 of the energy.
  auto over_x = [&](double z) {  // int over x in R of the point-cylinder potential at height d + z
    auto f = [&](double x) { return point_cylinder(m, rb, std::hypot(x, d + z), points); };
    return 2 * graded_integral(f, 0.0, 40 * (ra + rb), points);
  };
  // z = -ra + 2 ra u^2 (chord 2 sqrt(ra^2 - z^2) of section A at height z).
  auto integrand = [&](double u) {
    const double z = -ra + 2 * ra * u * u, dz = 4 * ra * u;
    return 2 * std::sqrt(std::max(0.0, ra * ra - z * z)) * over_x(z) * dz;
  };
  return graded_integral(integrand, 0.0, 1.0, points);
}

}  // namespace fibrane::interaction::test
