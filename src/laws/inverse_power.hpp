#pragma once
// Sums of inverse-power laws through the disk-surrogate plate (paper Eqs. 1, 5, 56): for point-pair
// potentials k_m r^-m the beam-shell potential per unit length is
//   phi(d, c) = s beta_B beta_S sum_i k_i Pi^{m_i}_DPT(d, c),
// e.g. a single vdW term (m = 6, k < 0), a single steric term (m = 12, k > 0), or Lennard-Jones-like
// pairs with other exponents (9-3, 12-6, ...). Integer exponents 6..32 use the closed forms of
// laws/disk_plate.hpp, other m > 3 its quadrature.
#include <memory>
#include <vector>

#include "laws/disk_plate.hpp"
#include "laws/interaction_law.hpp"

namespace fibrane::laws {

// One point-pair term k r^-m of Eq. (1).
struct InversePowerTerm {
  double exponent = 6;     // m > 3
  double coefficient = 0;  // k_m (negative: attraction)
};

class InversePowerSum final : public InteractionLaw {
 public:
  // `factor` = s beta_B beta_S. Throws InputError on m <= 3, k = 0, non-positive geometry or factor.
  InversePowerSum(std::vector<InversePowerTerm> terms, LawGeometry geometry, double factor = 1.0);
  std::string name() const override { return "inverse_power_sum"; }
  LawValue evaluate(double d, double c) const override;
  LawGeometry geometry() const override { return geometry_; }
  // With an attractive and a repulsive term: the distance where the pair potential of the highest and the
  // lowest exponent balance, (|k_hi| / |k_lo|)^(1 / (m_hi - m_lo)) (sigma for 12-6); otherwise the
  // disk radius.
  double length_scale() const override;
  const std::vector<InversePowerTerm>& terms() const { return terms_; }

 private:
  std::vector<InversePowerTerm> terms_;
  LawGeometry geometry_;
  double factor_;
  std::vector<std::unique_ptr<DiskPlate>> general_;  // per term: null for the integer closed forms
};

}  // namespace fibrane::laws
