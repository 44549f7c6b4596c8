#pragma once
// Point-half-space and disk-half-space laws for the pair potential r^-m (k_m = 1, unit densities),
// paper Sec. 4.1, Eq. (55), generalised to any exponent m > 3.
#include "laws/law_value.hpp"

namespace fibrane::laws {

// Value and first two derivatives of a function of one distance.
struct ScalarJet {
  double value = 0, d1 = 0, d2 = 0;
};

// Point at distance z > 0 from a half-space: 2 pi / ((m-2)(m-3)) z^(3-m).
ScalarJet point_halfspace(double m, double z);

// Disk of radius R whose centre is at distance d from the surface of a half-space, the disk plane
// making the angle alpha with the surface normal (c = cos alpha = 1: disk perpendicular to the
// surface, as for a beam lying on a shell). Requires d > c R (positive gap g = d - c R).
//
// Integrating the point law over the disk gives (derivation in docs/laws.md)
//   Pi^m = 2 pi^2 R^2 / ((m-2)(m-3)) d^-n 2F1(n/2, (n+1)/2; 2; z),  n = m - 3, z = (c R / d)^2,
// and by Euler's transformation 2F1 = (1-z)^(3/2-n) 2F1(2-n/2, (3-n)/2; 2; z), whose series
// terminates for every integer m >= 6 (m = 6 gives Eq. (55), m = 12 a cubic). Other m use a
// spectrally convergent trapezoidal rule for the Euler integral of 2F1 and its z-derivatives.
class DiskHalfSpace {
 public:
  DiskHalfSpace(double m, double radius);

  DistanceSquaredCosJet jet(double d, double c) const;
  LawValue evaluate(double d, double c) const { return jet(d, c).to_law_value(c); }

  double exponent() const { return m_; }
  double radius() const { return radius_; }
  bool is_closed_form() const { return terminating_degree_ >= 0; }

 private:
  void hypergeometric(double z, double w, double& f, double& f1, double& f2) const;

  double m_, n_, radius_, prefactor_;
  int terminating_degree_ = -1;  // degree of the terminating polynomial, -1: quadrature
  double coefficients_[16] = {};
};

// Fast closed form for integer m in [6, 33] (the path used by the Lennard-Jones law).
DistanceSquaredCosJet disk_halfspace_integer_jet(int m, double radius, double d, double c);

}  // namespace fibrane::laws
