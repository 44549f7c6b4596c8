#pragma once
// Lennard-Jones disk-surrogate plate potential per unit beam length (paper Sec. 2.3, Eq. 6, and
// Sec. 5): phi(d, c) = s beta_B beta_S (k6 Pi^6_DPT + k12 Pi^12_DPT), k6 = -4 eps sigma^6,
// k12 = 4 eps sigma^12, d the distance of the disk centre from the plate mid-plane, c = cos alpha.
#include "laws/interaction_law.hpp"

namespace fibrane::laws {

class LennardJonesDiskPlate final : public InteractionLaw {
 public:
  double epsilon = 1, sigma = 1, disk_radius = 1, plate_thickness = 1, density_beam = 1, density_shell = 1,
         strength = 1;

  LennardJonesDiskPlate() = default;
  LennardJonesDiskPlate(double epsilon, double sigma, double disk_radius, double plate_thickness,
                        double density_beam = 1, double density_shell = 1, double strength = 1);

  std::string name() const override { return "lennard_jones"; }
  // Value, all first and second derivatives in (d, c) and the reduced forms of Eqs. (75), (E2).
  // Precondition: positive gap, d - h/2 > c R (throws std::domain_error otherwise).
  LawValue evaluate(double d, double c) const override;
  LawGeometry geometry() const override { return {disk_radius, plate_thickness}; }
  double length_scale() const override { return sigma; }

  // Throws fibrane::InputError naming the first invalid parameter.
  void validate() const;
};

}  // namespace fibrane::laws
