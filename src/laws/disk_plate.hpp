#pragma once
// Disk-infinite plate law, paper Eq. (56): Pi_DPT(d) = Pi_DHS(d - h/2) - Pi_DHS(d + h/2), d the
// distance from the disk centre to the plate mid-plane, h the plate thickness.
#include "laws/disk_halfspace.hpp"
#include "laws/quadrature.hpp"

namespace fibrane::laws {

// Far from the plate (h small against d - c R) the difference of Eq. (56) cancels. There the law
// is evaluated instead as the thickness integral of the disk-layer law,
//   Pi_DPT = (m-1) int_{-h/2}^{h/2} Pi_DHS^{m+1}(d + t) dt       (-d/dz Pi^m_DHS = (m-1) Pi^{m+1}_DHS),
// with a 3-point Gauss-Legendre rule, which converges geometrically because the nearest
// singularity (d + t = c R) lies at least kThicknessQuadratureRatio half-thicknesses away.
// The switch is placed where both forms are good to ~1e-14: the difference loses about
// log10(rho / m) digits (rho = (d - cR)/(h/2)): 1e-16 * 2000 / 12 ~ 2e-14 at the switch, while the
// 3-point rule's error ~ C(m) rho^-6 is ~1e-16 there; evaluations below the switch (every distance that
// matters for adhesion) use the cheaper difference form.
inline constexpr double kThicknessQuadratureRatio = 2000.0;
inline constexpr int kThicknessQuadraturePoints = 3;

class DiskPlate {
 public:
  DiskPlate(double m, double radius, double thickness);

  DistanceSquaredCosJet jet(double d, double c) const;
  LawValue evaluate(double d, double c) const { return jet(d, c).to_law_value(c); }

  double exponent() const { return half_space_.exponent(); }
  double radius() const { return half_space_.radius(); }
  double thickness() const { return thickness_; }

 private:
  DiskHalfSpace half_space_, layer_;  // exponents m and m + 1
  double thickness_;
  QuadratureRule rule_;
};

// Fast closed form for integer m in [6, 32], used by the Lennard-Jones law.
DistanceSquaredCosJet disk_plate_integer_jet(int m, double radius, double thickness, double d,
                                             double c);

}  // namespace fibrane::laws
