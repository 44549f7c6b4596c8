#pragma once
// The gap law of the section-beam interaction potential (SBIP, after Grill, Wall, Meier, arXiv 2208.03149)
// for two fibers at small separations: fiber A's circular cross section (radius R_A) against an infinite
// straight cylinder (radius R_B), the surrogate of fiber B. The point-pair law is the sum of inverse powers
// k_m r^-m of the paper's Eq. (1) with the particle densities of Eq. (3).
//
// Small-separation form. Near the section's point closest to the cylinder the gap is, to second order,
// h = g + a x^2 + b y (x along the section's rim, y from the rim into the section; a and b come from the
// geometry, interaction/section_beam.hpp). Each area element of the section sees the cylinder as a
// half-space at gap h (the point-half-space potential 2 pi rho_B k_m h^(3-m) / ((m-2)(m-3))); integrating
// y over [0, inf) and x over R gives, per unit length of fiber A,
//   pi(g, a, b) = F(g) / (b sqrt(a)),                                                       (S1)
//   F(g) = s rho_A rho_B sum_m k_m C_m g^(4.5-m),
//   C_m = 2 pi sqrt(pi) Gamma(m - 4.5) / ((m-2)(m-3)(m-4) Gamma(m - 4)),    m > 4.5.        (S2)
// The kernel uses (S1) with the slope b replaced by b + G(g) / (2 R_A) (S4'): for m = 6 against a flat
// surface (a = b / (2 R_A)) (S1) is then exactly the paper's disk-half-space law, Eq. (55),
// pi^2 R^2 / (6 (g (g + 2 R c))^(3/2)) with c = b, which keeps the section's finite size where b is small
// (sections far from a crossing, which would otherwise see an infinite half-plane at a grazing angle).
// This class evaluates F, G and their first two derivatives in g. Along two parallel fibers (S1) tends
// to the Derjaguin limit per unit length, and integrated along crossed fibers to the crossed-cylinder
// Derjaguin energy (docs/verification.md; Israelachvili, ch. 13).
//
// Regularization (as 4C's SBIP option `linear`): below the gap g_r, F is continued by its second-order
// Taylor polynomial at g_r, so the force law is linearly extrapolated and F is C2 and finite for every g,
// overlaps included. Cut-off: above g_c - w the law is multiplied by the C2 taper
// 1 - (10 x^3 - 15 x^4 + 6 x^5), x = (g - g_c + w) / w, and it vanishes from g_c on.
#include <limits>
#include <vector>

#include "laws/inverse_power.hpp"

namespace fibrane::laws {

// F(g) and its derivatives, see (S1).
struct GapValue {
  double f = 0, f_g = 0, f_gg = 0;
};

// Section-cylinder gap law: a sum of inverse-power point-pair terms, densities, radii, regularization and
// cut-off; see the file comment.
class SectionCylinderLaw {
 public:
  // `factor` = s rho_A rho_B. `regularization_gap` 0: none (then F throws std::domain_error for g <= 0).
  // `cutoff_gap` infinite: no cut-off; `taper` its width w (0: half the cut-off gap).
  // Throws InputError on an exponent m <= 4.5, a zero coefficient, non-positive radii or factor, a negative
  // regularization gap, a cut-off below the regularization gap or a taper wider than the cut-off.
  SectionCylinderLaw(std::vector<InversePowerTerm> terms, double radius_a, double radius_b, double factor = 1.0,
                     double regularization_gap = 0.0,
                     double cutoff_gap = std::numeric_limits<double>::infinity(), double taper = 0.0);

  // Lennard-Jones point pairs 4 eps [(sigma/r)^12 - (sigma/r)^6] (paper Eq. 6).
  static SectionCylinderLaw lennard_jones(double epsilon, double sigma, double radius_a, double radius_b,
                                          double factor = 1.0, double regularization_gap = 0.0,
                                          double cutoff_gap = std::numeric_limits<double>::infinity());

  GapValue evaluate(double g) const;
  // G(g) of the slope correction (S4'): g, continued below the regularization gap g_r by
  // g_r / (1 - x + x^2), x = (g - g_r) / g_r (C2 at g_r and positive for every g).
  GapValue slope_gap(double g) const;
  // F without regularization and cut-off (the law of (S2) itself); throws std::domain_error for g <= 0.
  GapValue raw(double g) const;
  // C_m of (S2).
  static double coefficient(double m);
  // The equilibrium gap g_0 of the law: the gap of the smallest F of (S2) itself (F_g(g_0) = 0 with F
  // falling below and rising above it; without regularization, cut-off and the slope correction), sought
  // over 1e-15 <= g <= 1e15. NaN if F has no such minimum (a single term, or only attractive terms).
  // Lennard-Jones: g_0 = (5 C_12 / C_6)^(1/6) sigma = 0.6417 sigma.
  double equilibrium_gap() const;

  double radius_a() const { return radius_a_; }
  double radius_b() const { return radius_b_; }
  double factor() const { return factor_; }
  double regularization_gap() const { return regularization_gap_; }
  double cutoff_gap() const { return cutoff_gap_; }
  const std::vector<InversePowerTerm>& terms() const { return terms_; }
  // The same law with the roles of the two fibers exchanged (the second half pass).
  SectionCylinderLaw swapped() const;

 private:
  std::vector<InversePowerTerm> terms_;
  double radius_a_, radius_b_, factor_, regularization_gap_, cutoff_gap_, taper_;
  GapValue at_regularization_;  // raw(regularization_gap_) when it is positive
};

}  // namespace fibrane::laws
