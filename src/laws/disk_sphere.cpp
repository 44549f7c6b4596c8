#include "laws/disk_sphere.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "common/error.hpp"

namespace fibrane::laws {
namespace {

constexpr double kPi = std::numbers::pi;

// Second-order forward-mode jet in one variable: differentiating the cancellation-free form of
// Eq. (F4) keeps the derivatives free of the cancellation as well.
struct Jet {
  double v, d, dd;
};
Jet operator+(Jet a, Jet b) { return {a.v + b.v, a.d + b.d, a.dd + b.dd}; }
Jet operator-(Jet a, Jet b) { return {a.v - b.v, a.d - b.d, a.dd - b.dd}; }
Jet operator*(Jet a, Jet b) { return {a.v * b.v, a.d * b.v + a.v * b.d, a.dd * b.v + 2 * a.d * b.d + a.v * b.dd}; }
Jet operator*(double s, Jet a) { return {s * a.v, s * a.d, s * a.dd}; }
Jet operator+(Jet a, double s) { return {a.v + s, a.d, a.dd}; }
Jet reciprocal(Jet a) {
  const double r = 1.0 / a.v;
  return {r, -a.d * r * r, (2 * a.d * a.d * r - a.dd) * r * r};
}
Jet operator/(Jet a, Jet b) { return a * reciprocal(b); }
Jet power_three_halves(Jet a) {  // a^(3/2)
  const double root = std::sqrt(a.v);
  return {a.v * root, 1.5 * root * a.d, 1.5 * root * a.dd + 0.75 / root * a.d * a.d};
}

}  // namespace

ScalarJet point_sphere(double sphere_radius, double t) {
  if (!(sphere_radius > 0.0)) throw InputError("sphere radius must be positive");
  if (!(t > sphere_radius)) throw std::domain_error("point-sphere law: the point must lie outside");
  const double r3 = sphere_radius * sphere_radius * sphere_radius;
  const double a = t * t - sphere_radius * sphere_radius;
  const double value = 4.0 * kPi * r3 / (3.0 * a * a * a);
  // d/dt a^-3 = -6 t a^-4, d2/dt2 a^-3 = -6 a^-4 + 48 t^2 a^-5
  return {value, -6.0 * t * value / a, value * (-6.0 / a + 48.0 * t * t / (a * a))};
}

ScalarJet disk_sphere(double disk_radius, double sphere_radius, double d) {
  if (!(disk_radius > 0.0) || !(sphere_radius > 0.0))
    throw InputError("disk-sphere law: radii must be positive");
  if (!(d > disk_radius + sphere_radius))
    throw std::domain_error("disk-sphere law: the disk touches or penetrates the sphere");
  const double rd2 = disk_radius * disk_radius, rs2 = sphere_radius * sphere_radius;
  const Jet x{d * d, 2 * d, 2};  // x = d^2
  const double sum2 = (disk_radius + sphere_radius) * (disk_radius + sphere_radius);
  const double diff2 = (disk_radius - sphere_radius) * (disk_radius - sphere_radius);
  const Jet q = (x + (-sum2)) * (x + (-diff2));
  const Jet x_minus_rd2 = x + (-rd2);
  const Jet numerator = (-3.0 * rs2 * rs2) * x + (3.0 * rs2) * (x * x) +
                        (-1.0) * (x_minus_rd2 * x_minus_rd2 * x_minus_rd2) +
                        (rs2 * rs2 * rs2 + rd2 * rs2 * rs2 - 3.0 * rs2 * rd2 * rd2);
  const Jet q32 = power_three_halves(q);
  Jet value;
  if (numerator.v < 0) {
    // 1 + N/Q^(3/2) = (Q^3 - N^2) / (Q^(3/2) (Q^(3/2) - N)) with Q^3 - N^2 = 4 R_D^2 R_S^4 P, P
    // below; both factors of the denominator are positive, so nothing cancels at large d.
    const Jet x_minus_rs2 = x + (-rs2);
    const Jet p = 2.0 * (x_minus_rs2 * x_minus_rs2 * x_minus_rs2) + (-3.0 * rd2) * (x * x) +
                  (-6.0 * rd2 * rs2) * x +
                  (5.0 * rd2 * rs2 * rs2 - 4.0 * rd2 * rd2 * rs2 + rd2 * rd2 * rd2);
    value = (4.0 * kPi * kPi * rd2 * rs2 * sphere_radius / 3.0) * (p / (q32 * (q32 - numerator)));
  } else {
    value = (kPi * kPi / (3.0 * sphere_radius)) * ((numerator / q32) + 1.0);
  }
  return {value.v, value.d, value.dd};
}

ScalarJet disk_spherical_shell(double disk_radius, double shell_radius, double thickness,
                               double d) {
  if (!(thickness > 0.0) || !(thickness < 2.0 * shell_radius))
    throw InputError("spherical shell: thickness must lie in (0, 2 R_SS)");
  const ScalarJet outer = disk_sphere(disk_radius, shell_radius + 0.5 * thickness, d);
  const ScalarJet inner = disk_sphere(disk_radius, shell_radius - 0.5 * thickness, d);
  return {outer.value - inner.value, outer.d1 - inner.d1, outer.d2 - inner.d2};
}

}  // namespace fibrane::laws
