#include "laws/disk_halfspace.hpp"

#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "common/error.hpp"
#include "common/format.hpp"

namespace fibrane::laws {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kMaxIntegerExponent = 33;

// Coefficients of the terminating series 2F1(2-n/2, (3-n)/2; 2; z), n = m - 3. One of the two upper
// parameters is a non-positive integer for every integer n >= 3, so the series is a polynomial.
int terminating_coefficients(int n, double* out, int capacity) {
  const double a = 2.0 - 0.5 * n, b = 0.5 * (3.0 - n);
  out[0] = 1.0;
  for (int j = 0; j + 1 < capacity; ++j) {
    const double factor = (a + j) * (b + j) / ((2.0 + j) * (j + 1.0));
    if (factor == 0.0) return j;
    out[j + 1] = out[j] * factor;
  }
  return -1;
}

struct IntegerLawTable {
  std::array<std::array<double, 16>, kMaxIntegerExponent + 1> coefficients{};
  std::array<int, kMaxIntegerExponent + 1> degree{};
  IntegerLawTable() {
    for (int m = 6; m <= kMaxIntegerExponent; ++m)
      degree[m] = terminating_coefficients(m - 3, coefficients[m].data(), 16);
  }
};

const IntegerLawTable& integer_table() {
  static const IntegerLawTable table;
  return table;
}

double integer_power(double x, int k) {
  double result = 1.0;
  for (; k > 0; --k) result *= x;
  return result;
}

// F(z) = (1-z)^(-p) Q(z), p = n - 3/2, and its first two z-derivatives; w = 1 - z is passed in
// separately because the caller computes it without cancellation.
void closed_form_hypergeometric(int n, const double* q, int degree, double z, double w, double& f,
                                double& f1, double& f2) {
  double poly = 0, poly1 = 0, poly2 = 0;
  for (int j = degree; j >= 0; --j) {  // Horner for Q, Q', Q''
    poly2 = poly2 * z + 2.0 * poly1;
    poly1 = poly1 * z + poly;
    poly = poly * z + q[j];
  }
  const double p = n - 1.5;
  const double w_minus_p = 1.0 / (integer_power(w, n - 2) * std::sqrt(w));
  const double inv_w = 1.0 / w;
  f = w_minus_p * poly;
  f1 = w_minus_p * (p * inv_w * poly + poly1);
  f2 = w_minus_p * (p * (p + 1.0) * inv_w * inv_w * poly + 2.0 * p * inv_w * poly1 + poly2);
}

// Pi = C d^-n F(z), z = s R^2 / d^2, differentiated in (d, s) by the chain rule.
DistanceSquaredCosJet assemble(double n, double prefactor, double radius, double d, double z,
                               double f, double f1, double f2, double d_minus_n) {
  const double inv_d = 1.0 / d, r2 = radius * radius;
  const double g = prefactor * d_minus_n;
  const double g1 = -n * g * inv_d, g2 = n * (n + 1.0) * g * inv_d * inv_d;
  const double z_d = -2.0 * z * inv_d, z_dd = 6.0 * z * inv_d * inv_d;
  const double z_s = r2 * inv_d * inv_d, z_ds = -2.0 * z_s * inv_d;
  DistanceSquaredCosJet out;
  out.value = g * f;
  out.d = g1 * f + g * f1 * z_d;
  out.dd = g2 * f + 2.0 * g1 * f1 * z_d + g * (f2 * z_d * z_d + f1 * z_dd);
  out.s = g * f1 * z_s;
  out.ss = g * f2 * z_s * z_s;
  out.ds = g1 * f1 * z_s + g * (f2 * z_d * z_s + f1 * z_ds);
  return out;
}

void require_positive_gap(double radius, double d, double c) {
  if (!(d - c * radius > 0.0))
    throw std::domain_error("disk-half-space law: the disk touches or penetrates the surface (d = " +
                            format_number(d) + ", c R = " + format_number(c * radius) + ")");
}

// I_lambda(N) = int_0^pi sin^(2 lambda) t (1 + k cos t)^-N dt for lambda = 1, 2, 3 at once. The
// integrand is smooth and periodic, so the trapezoidal rule converges geometrically; the number of
// points is doubled until the last doubling changed nothing at 1e-15.
void trapezoid_moments(double k, double n, double out[3]) {
  const double exponents[3] = {n, n + 2.0, n + 4.0};
  auto sample = [&](double t, double acc[3]) {
    const double s2 = std::sin(t) * std::sin(t), base = 1.0 + k * std::cos(t);
    double weight = s2;
    for (int i = 0; i < 3; ++i, weight *= s2) acc[i] += weight * std::pow(base, -exponents[i]);
  };
  double sums[3] = {0, 0, 0};
  int intervals = 16;
  for (int j = 1; j < intervals; ++j) sample(kPi * j / intervals, sums);  // end points vanish
  double previous[3] = {sums[0] / intervals, sums[1] / intervals, sums[2] / intervals};
  for (int level = 0; level < 20; ++level) {
    for (int j = 1; j < 2 * intervals; j += 2) sample(kPi * j / (2 * intervals), sums);
    intervals *= 2;
    bool converged = true;
    for (int i = 0; i < 3; ++i) {
      const double current = sums[i] / intervals;
      if (std::abs(current - previous[i]) > 1e-15 * std::abs(current)) converged = false;
      previous[i] = current;
    }
    if (converged) break;
  }
  for (int i = 0; i < 3; ++i) out[i] = kPi * previous[i];
}

}  // namespace

ScalarJet point_halfspace(double m, double z) {
  if (!(m > 3.0)) throw InputError("point-half-space law needs an exponent m > 3");
  if (!(z > 0.0)) throw std::domain_error("point-half-space law: the point must lie outside");
  const double value = 2.0 * kPi / ((m - 2.0) * (m - 3.0)) * std::pow(z, 3.0 - m);
  return {value, -(m - 3.0) * value / z, (m - 3.0) * (m - 2.0) * value / (z * z)};
}

DiskHalfSpace::DiskHalfSpace(double m, double radius)
    : m_(m), n_(m - 3.0), radius_(radius),
      prefactor_(2.0 * kPi * kPi * radius * radius / ((m - 2.0) * (m - 3.0))) {
  if (!(m > 3.0)) throw InputError("disk law needs an exponent m > 3, got " + std::to_string(m));
  if (!(radius > 0.0)) throw InputError("disk radius must be positive");
  const double rounded = std::round(m);
  if (rounded == m && m >= 6 && m <= kMaxIntegerExponent)
    terminating_degree_ = terminating_coefficients(static_cast<int>(m) - 3, coefficients_, 16);
}

void DiskHalfSpace::hypergeometric(double z, double w, double& f, double& f1, double& f2) const {
  if (terminating_degree_ >= 0) {
    closed_form_hypergeometric(static_cast<int>(n_), coefficients_, terminating_degree_, z, w, f,
                               f1, f2);
    return;
  }
  // Euler integrals: int_{-1}^{1} (1-x^2)^(lambda-1/2) (1+kx)^-N dx = B(1/2, lambda+1/2)
  // 2F1(N/2, (N+1)/2; lambda+1; k^2); the z-derivatives of F raise lambda and N together.
  double moments[3];
  trapezoid_moments(std::sqrt(z), n_, moments);
  const double n = n_;
  f = 2.0 / kPi * moments[0];
  f1 = n * (n + 1.0) / (3.0 * kPi) * moments[1];
  f2 = (0.5 * n) * (0.5 * n + 1.0) * (0.5 * (n + 1.0)) * (0.5 * (n + 3.0)) / 6.0 *
       (16.0 / (5.0 * kPi)) * moments[2];
}

DistanceSquaredCosJet DiskHalfSpace::jet(double d, double c) const {
  require_positive_gap(radius_, d, c);
  const double cr = c * radius_;
  const double z = (cr / d) * (cr / d), w = (d - cr) * (d + cr) / (d * d);
  double f, f1, f2;
  hypergeometric(z, w, f, f1, f2);
  return assemble(n_, prefactor_, radius_, d, z, f, f1, f2, std::pow(d, -n_));
}

DistanceSquaredCosJet disk_halfspace_integer_jet(int m, double radius, double d, double c) {
  if (m < 6 || m > kMaxIntegerExponent)
    throw std::invalid_argument("disk_halfspace_integer_jet: m outside [6, 33]");
  require_positive_gap(radius, d, c);
  const IntegerLawTable& table = integer_table();
  const int n = m - 3;
  const double cr = c * radius;
  const double z = (cr / d) * (cr / d), w = (d - cr) * (d + cr) / (d * d);
  double f, f1, f2;
  closed_form_hypergeometric(n, table.coefficients[m].data(), table.degree[m], z, w, f, f1, f2);
  const double prefactor = 2.0 * kPi * kPi * radius * radius / ((m - 2.0) * (m - 3.0));
  return assemble(n, prefactor, radius, d, z, f, f1, f2, 1.0 / integer_power(d, n));
}

}  // namespace fibrane::laws
