#pragma once
// Lennard-Jones disk-surrogate plate potential per unit beam length (paper Sec. 2.3, Eq. 6, and
// Sec. 5): phi(d, c) = s beta_B beta_S (k6 Pi^6_DPT + k12 Pi^12_DPT), k6 = -4 eps sigma^6,
// k12 = 4 eps sigma^12, d the distance of the disk centre from the plate mid-plane, c = cos alpha.
#include "laws/law_value.hpp"

namespace fibrane::laws {

struct LennardJonesDiskPlate {
  double epsilon, sigma, disk_radius, plate_thickness, density_beam = 1, density_shell = 1,
                                                         strength = 1;

  // Value, all first and second derivatives in (d, c) and the reduced forms of Eqs. (75), (E2).
  // Precondition: positive gap, d - h/2 > c R (throws std::domain_error otherwise).
  LawValue evaluate(double d, double c) const;

  // Root of phi_{,d}(d, c): the equilibrium distance (RF2 uses c = 1). Throws std::runtime_error
  // when no equilibrium exists.
  double equilibrium_distance(double c = 1.0) const;

  // Throws fibrane::InputError naming the first invalid parameter.
  void validate() const;
};

}  // namespace fibrane::laws
