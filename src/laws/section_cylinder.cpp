#include "laws/section_cylinder.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "common/error.hpp"
#include "common/format.hpp"

namespace fibrane::laws {

SectionCylinderLaw::SectionCylinderLaw(std::vector<InversePowerTerm> terms, double radius_a, double radius_b,
                                       double factor, double regularization_gap, double cutoff_gap, double taper)
    : terms_(std::move(terms)), radius_a_(radius_a), radius_b_(radius_b), factor_(factor),
      regularization_gap_(regularization_gap), cutoff_gap_(cutoff_gap), taper_(taper) {
  if (terms_.empty()) throw InputError("section-cylinder law: at least one term is needed");
  for (const auto& t : terms_) {
    if (!(t.exponent > 4.5) || !std::isfinite(t.exponent))
      throw InputError("section-cylinder law: exponent " + format_number(t.exponent) +
                       " must exceed 4.5 (the small-separation integral (S2) diverges otherwise)");
    if (t.coefficient == 0 || !std::isfinite(t.coefficient))
      throw InputError("section-cylinder law: coefficients must be finite and non-zero");
  }
  if (!(radius_a_ > 0) || !(radius_b_ > 0) || !std::isfinite(radius_a_) || !std::isfinite(radius_b_))
    throw InputError("section-cylinder law: both fiber radii must be positive");
  if (!(factor_ > 0) || !std::isfinite(factor_))
    throw InputError("section-cylinder law: strength x densities must be positive");
  if (!(regularization_gap_ >= 0) || !std::isfinite(regularization_gap_))
    throw InputError("section-cylinder law: the regularization gap must be zero (none) or positive");
  if (!(cutoff_gap_ > regularization_gap_))
    throw InputError("section-cylinder law: the cut-off gap must exceed the regularization gap");
  if (std::isfinite(cutoff_gap_)) {
    if (taper_ == 0) taper_ = 0.5 * cutoff_gap_;
    if (!(taper_ > 0) || taper_ > cutoff_gap_ - regularization_gap_)
      throw InputError("section-cylinder law: the taper must be positive and end above the regularization gap");
  }
  if (regularization_gap_ > 0) at_regularization_ = raw(regularization_gap_);
}

SectionCylinderLaw SectionCylinderLaw::lennard_jones(double epsilon, double sigma, double radius_a, double radius_b,
                                                     double factor, double regularization_gap, double cutoff_gap) {
  const double s6 = std::pow(sigma, 6);
  return SectionCylinderLaw({{6, -4 * epsilon * s6}, {12, 4 * epsilon * s6 * s6}}, radius_a, radius_b, factor,
                            regularization_gap, cutoff_gap);
}

SectionCylinderLaw SectionCylinderLaw::swapped() const {
  SectionCylinderLaw s = *this;
  std::swap(s.radius_a_, s.radius_b_);
  return s;
}

double SectionCylinderLaw::coefficient(double m) {
  // (S2): the point-half-space potential integrated over y in [0, inf) and x in R.
  const double pi = 3.14159265358979323846;
  return 2 * pi * std::sqrt(pi) * std::tgamma(m - 4.5) / ((m - 2) * (m - 3) * (m - 4) * std::tgamma(m - 4));
}

GapValue SectionCylinderLaw::raw(double g) const {
  if (!(g > 0)) throw std::domain_error("section-cylinder law: gap " + format_number(g) + " is not positive");
  GapValue v;
  for (const auto& t : terms_) {
    const double p = 4.5 - t.exponent;  // F ~ g^p, (S1)
    const double c = factor_ * t.coefficient * coefficient(t.exponent) * std::pow(g, p);
    v.f += c;
    v.f_g += c * p / g;
    v.f_gg += c * p * (p - 1) / (g * g);
  }
  return v;
}

double SectionCylinderLaw::equilibrium_gap() const {
  // The sign of F_g is that of h(g) = sum_m k_m C_m (4.5 - m) g^(m_max - m) (F_g times g^(m_max - 3.5) / s
  // rho_A rho_B > 0), which neither overflows nor underflows where the terms balance. Its sign changes from
  // - to + are the minima of F; the deepest one is g_0.
  double m_max = 0;
  for (const auto& t : terms_) m_max = std::max(m_max, t.exponent);
  auto h = [&](double g) {
    double v = 0;
    for (const auto& t : terms_)
      v += t.coefficient * coefficient(t.exponent) * (4.5 - t.exponent) * std::pow(g, m_max - t.exponent);
    return v;
  };
  double best = std::numeric_limits<double>::quiet_NaN(), best_f = 0;
  constexpr int per_decade = 40;
  double lo = 1e-15, h_lo = h(lo);
  for (int k = 1; k <= 30 * per_decade; ++k) {
    const double hi = std::pow(10.0, -15.0 + static_cast<double>(k) / per_decade), h_hi = h(hi);
    if (std::isfinite(h_lo) && std::isfinite(h_hi) && h_lo < 0 && h_hi >= 0) {
      double a = lo, b = hi;  // bisection: h(a) < 0 <= h(b)
      for (int it = 0; it < 200 && b - a > 1e-15 * b; ++it) {
        const double mid = 0.5 * (a + b);
        (h(mid) < 0 ? a : b) = mid;
      }
      const double g = 0.5 * (a + b), f = raw(g).f;
      if (std::isnan(best) || f < best_f) {
        best = g;
        best_f = f;
      }
    }
    lo = hi;
    h_lo = h_hi;
  }
  return best;
}

GapValue SectionCylinderLaw::slope_gap(double g) const {
  if (!(regularization_gap_ > 0) || g >= regularization_gap_) return {g, 1, 0};
  const double r = regularization_gap_, x = (g - r) / r, u = 1 - x + x * x, u_x = 2 * x - 1;
  // d/dx 1/u = -u_x / u^2, d2/dx2 1/u = (2 u_x^2 - 2 u) / u^3
  return {r / u, -u_x / (u * u), (2 * u_x * u_x - 2 * u) / (u * u * u) / r};
}

GapValue SectionCylinderLaw::evaluate(double g) const {
  if (g >= cutoff_gap_) return {};
  GapValue v;
  if (regularization_gap_ > 0 && g < regularization_gap_) {
    // Linear extrapolation of the force law: the second-order Taylor polynomial of F at g_r.
    const GapValue& r = at_regularization_;
    const double x = g - regularization_gap_;
    v = {r.f + r.f_g * x + 0.5 * r.f_gg * x * x, r.f_g + r.f_gg * x, r.f_gg};
  } else {
    v = raw(g);
  }
  const double start = cutoff_gap_ - taper_;
  if (g > start) {  // C2 taper to zero at the cut-off
    const double x = (g - start) / taper_;
    const double t = 1 - x * x * x * (10 - 15 * x + 6 * x * x);
    const double t_x = -30 * x * x * (1 - x) * (1 - x);
    const double t_xx = -60 * x * (1 - x) * (1 - 2 * x);
    const double t_g = t_x / taper_, t_gg = t_xx / (taper_ * taper_);
    v = {v.f * t, v.f_g * t + v.f * t_g, v.f_gg * t + 2 * v.f_g * t_g + v.f * t_gg};
  }
  return v;
}

}  // namespace fibrane::laws
