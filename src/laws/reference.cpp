#include "laws/reference.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "laws/disk_halfspace.hpp"
#include "laws/disk_plate.hpp"
#include "laws/disk_sphere.hpp"
#include "laws/quadrature.hpp"

namespace fibrane::laws::reference {
namespace {
constexpr double kPi = std::numbers::pi;

// int over a disk of radius R of f(distance to a point at distance d in the disk plane), by the
// cosine rule; the half-disk is doubled by symmetry.
template <class F>
double disk_cubature_around_point(F f, double radius, double d, double tol) {
  return 2.0 * integrate(
                   [&](double r) {
                     return r * integrate(
                                    [&](double beta) {
                                      const double half_sine = std::sin(0.5 * beta);  // cancellation-free cosine rule
                                      return f(std::sqrt((d - r) * (d - r) + 4 * d * r * half_sine * half_sine));
                                    },
                                    0.0, kPi, 0.1 * tol);
                   },
                   0.0, radius, tol);
}
}  // namespace

double disk_halfspace(double m, double radius, double d, double c, double tol) {
  const double k = 2 * kPi / ((m - 2) * (m - 3));
  return 2.0 * integrate(
                   [&](double r) {
                     return r * integrate(
                                    [&](double t) { return k * std::pow(d + c * r * std::cos(t), 3 - m); },
                                    0.0, kPi, 0.1 * tol);
                   },
                   0.0, radius, tol);
}

double disk_plate(double m, double radius, double thickness, double d, double c, double tol) {
  const double k = 2 * kPi / ((m - 2) * (m - 3)), half = 0.5 * thickness;
  return 2.0 * integrate(
                   [&](double r) {
                     return r * integrate(
                                    [&](double t) {
                                      const double z = d + c * r * std::cos(t);
                                      return k * (std::pow(z - half, 3 - m) - std::pow(z + half, 3 - m));
                                    },
                                    0.0, kPi, 0.1 * tol);
                   },
                   0.0, radius, tol);
}

double point_sphere(double sphere_radius, double t, double tol) {
  return integrate(
      [&](double r) {
        return 2 * kPi * r * r * integrate(
                                     [&](double theta) {
                                       const double half_sine = std::sin(0.5 * theta);
                                       const double s2 = (t - r) * (t - r) + 4 * t * r * half_sine * half_sine;
                                       return std::sin(theta) / (s2 * s2 * s2);
                                     },
                                     0.0, kPi, 0.1 * tol);
      },
      0.0, sphere_radius, tol);
}

double disk_sphere(double disk_radius, double sphere_radius, double d, double tol) {
  return disk_cubature_around_point(
      [&](double t) { return laws::point_sphere(sphere_radius, t).value; }, disk_radius, d, tol);
}

// Complete elliptic integrals K and E from the complementary modulus k' by the arithmetic-
// geometric mean; passing k' (not k) keeps full accuracy as k -> 1, where 1 - k^2 would cancel.
static void elliptic_from_complement(double k_complement, double& big_k, double& big_e) {
  double a = 1.0, b = k_complement, c2 = 1.0 - k_complement * k_complement;
  double sum = 0.5 * c2, power = 0.5;
  for (int i = 0; i < 40 && c2 > 1e-34; ++i) {
    const double c = 0.5 * (a - b);
    const double next_b = std::sqrt(a * b);
    a = 0.5 * (a + b);
    b = next_b;
    c2 = c * c;
    power *= 2.0;
    sum += power * c2;
  }
  big_k = kPi / (2.0 * a);
  big_e = big_k * (1.0 - sum);
}

double angular_integral_five_halves(double a, double b) {
  if (b == 0.0) return kPi * std::pow(a, -2.5);
  // I_{3/2} = 2 E(k) / ((A-B) sqrt(A+B)), k^2 = 2B/(A+B), and I_{5/2} = -(2/3) dI_{3/2}/dA with
  // dE/dA = (K - E) / (2 (A+B)); k'^2 = (A-B)/(A+B).
  const double sum = a + b, difference = a - b;
  double big_k, big_e;
  elliptic_from_complement(std::sqrt(difference / sum), big_k, big_e);
  const double root = std::sqrt(sum);
  const double derivative =
      2 * ((big_k - big_e) / (2 * sum) / (difference * root) -
           big_e * (1 / (difference * difference * root) + 0.5 / (difference * sum * root)));
  return -2.0 / 3.0 * derivative;
}

// I_{5/2}(rho^2 + r^2, 2 rho r) with A - B = (rho - r)^2 formed exactly.
static double angular_integral_five_halves_split(double rho, double r) {
  const double sum = (rho + r) * (rho + r), difference = (rho - r) * (rho - r);
  double big_k, big_e;
  elliptic_from_complement(std::abs(rho - r) / (rho + r), big_k, big_e);
  const double root = rho + r;
  const double derivative =
      2 * ((big_k - big_e) / (2 * sum) / (difference * root) -
           big_e * (1 / (difference * difference * root) + 0.5 / (difference * sum * root)));
  return -2.0 / 3.0 * derivative;
}

double point_cylindrical_shell(double shell_radius, double thickness, double rho, double tol) {
  const double inner = shell_radius - 0.5 * thickness, outer = shell_radius + 0.5 * thickness;
  return 3 * kPi / 8 * 2 *
         integrate([&](double r) { return r * angular_integral_five_halves_split(rho, r); },
                   inner, outer, tol);
}

double disk_cylindrical_shell_parallel(double disk_radius, double shell_radius, double thickness,
                                       double d, double tol) {
  // The point law depends only on the in-plane distance rho from the axis point, so the disk
  // integral collapses to int P(rho) 2 rho acos((rho^2 + d^2 - R^2) / (2 rho d)) drho; the map
  // rho = d - R cos(psi) removes the square-root behaviour of the arc length at both ends.
  return integrate(
      [&](double psi) {
        const double rho = d - disk_radius * std::cos(psi);
        // Half-angle of the arc of radius rho inside the disk: 1 - cos(phi) = R^2 sin^2(psi) / (2 rho d),
        // written through asin so that nothing cancels near the ends.
        const double phi = 2 * std::asin(std::min(1.0, disk_radius * std::sin(psi) / (2 * std::sqrt(rho * d))));
        return 2 * rho * phi * disk_radius * std::sin(psi) *
               point_cylindrical_shell(shell_radius, thickness, rho, tol * 0.1);
      },
      0.0, kPi, tol);
}

double disk_cylindrical_shell_perpendicular(double disk_radius, double shell_radius,
                                            double thickness, double d, double tol) {
  // The disk plane contains the axis: a disk point's distance from the axis is d + v, v the
  // coordinate along the disk diameter through the axis; the chord at v has length 2 sqrt(R^2-v^2).
  return integrate(
      [&](double angle) {  // v = -R cos(angle) removes the square-root end singularities
        const double v = -disk_radius * std::cos(angle), chord = 2 * disk_radius * std::sin(angle);
        return chord * disk_radius * std::sin(angle) *
               point_cylindrical_shell(shell_radius, thickness, d + v, tol * 0.1);
      },
      0.0, kPi, 0.1 * tol);
}

double cylinder_spherical_shell_force(double cylinder_radius, double shell_radius, double thickness,
                                      double gap, double tol) {
  // Cylinder = stack of disks along xi; the disk at xi sees the shell centre at axial offset xi and
  // in-plane distance D0 = R_SS + h/2 + g0 + R_C from the axis. With the corrected point-sphere law
  // (F1) the angular integral is elementary: int_0^2pi (A - B cos)^-3 = pi (2A^2+B^2)/(A^2-B^2)^5/2.
  const double d0 = shell_radius + 0.5 * thickness + gap + cylinder_radius;
  const double radii[2] = {shell_radius + 0.5 * thickness, shell_radius - 0.5 * thickness};
  auto integrand = [&](double xi, double r) {  // -dPi/dD0 density at (xi, r)
    double total = 0;
    for (int i = 0; i < 2; ++i) {
      const double rs = radii[i];
      const double a = xi * xi + d0 * d0 + r * r - rs * rs, b = 2 * d0 * r;
      const double a_minus_b = xi * xi + (d0 - r - rs) * (d0 - r + rs);
      const double s = a_minus_b * (a + b), q = 2 * a * a + b * b;
      const double s52 = std::pow(s, -2.5), s72 = s52 / s;
      const double j_a = kPi * (4 * a * s52 - 5 * a * q * s72);
      const double j_b = kPi * (2 * b * s52 + 5 * b * q * s72);
      const double dj = j_a * 2 * d0 + j_b * 2 * r;
      total += (i == 0 ? 1.0 : -1.0) * 4 * kPi * rs * rs * rs / 3 * dj;
    }
    return -r * total;
  };
  const double length = std::sqrt(gap * (shell_radius + cylinder_radius)) + gap;
  return 2 * integrate_to_infinity(
                 [&](double xi) {
                   return integrate([&](double r) { return integrand(xi, r); }, 0.0, cylinder_radius,
                                    0.1 * tol);
                 },
                 0.0, length, tol);
}

double cylinder_spherical_shell_sbs_force(double cylinder_radius, double shell_radius,
                                          double thickness, double gap, bool exact_orientation,
                                          double tol) {
  const DiskPlate plate(6, cylinder_radius, thickness);
  const double d0 = shell_radius + 0.5 * thickness + gap + cylinder_radius;
  auto integrand = [&](double xi) {
    // Closest point of the section centre on the mid-surface: distance d = rho - R_SS along the
    // line of centres; the section normal is the axis, so cos alpha = sqrt(1 - t_n^2) = D0 / rho.
    const double rho = std::hypot(d0, xi), d = rho - shell_radius;
    const double c = exact_orientation ? d0 / rho : 1.0;
    const LawValue v = plate.evaluate(d, c);
    double dpi = v.d_d * d0 / rho;
    if (exact_orientation) dpi += v.d_c * xi * xi / (rho * rho * rho);
    return -dpi;
  };
  const double length = std::sqrt(gap * (shell_radius + cylinder_radius)) + gap;
  return 2 * integrate_to_infinity(integrand, 0.0, length, tol);
}

}  // namespace fibrane::laws::reference
