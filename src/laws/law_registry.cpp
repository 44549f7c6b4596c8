#include "laws/law_registry.hpp"

#include "laws/inverse_power.hpp"
#include "laws/lennard_jones.hpp"

namespace fibrane::laws {
namespace {

// The particle densities beta_B, beta_S and the strength factor s of Eq. (5) and Sec. 6.1.
double density_factor(const Parameters& p) {
  return p.positive_or("strength", 1.0) * p.positive_or("density_beam", 1.0) * p.positive_or("density_shell", 1.0);
}

std::shared_ptr<const InteractionLaw> make_lennard_jones(const Parameters& p, const LawGeometry& g) {
  p.reject_unknown({"epsilon", "sigma", "density_beam", "density_shell", "strength"});
  auto law = std::make_shared<LennardJonesDiskPlate>(p.positive("epsilon"), p.positive("sigma"), g.disk_radius,
                                                     g.plate_thickness, p.positive_or("density_beam", 1.0),
                                                     p.positive_or("density_shell", 1.0),
                                                     p.positive_or("strength", 1.0));
  law->validate();
  return law;
}

InversePowerTerm read_term(const Parameters& p) {
  p.reject_unknown({"exponent", "coefficient"});
  InversePowerTerm t{p.number("exponent"), p.number("coefficient")};
  if (!(t.exponent > 3)) p.fail("exponent", "an exponent m > 3");
  if (t.coefficient == 0) p.fail("coefficient", "a non-zero coefficient k_m");
  return t;
}

std::shared_ptr<const InteractionLaw> make_inverse_power(const Parameters& p, const LawGeometry& g) {
  p.reject_unknown({"exponent", "coefficient", "density_beam", "density_shell", "strength"});
  const double m = p.number("exponent"), k = p.number("coefficient");
  if (!(m > 3)) p.fail("exponent", "an exponent m > 3");
  if (k == 0) p.fail("coefficient", "a non-zero coefficient k_m");
  return std::make_shared<InversePowerSum>(std::vector<InversePowerTerm>{{m, k}}, g, density_factor(p));
}

std::shared_ptr<const InteractionLaw> make_inverse_power_sum(const Parameters& p, const LawGeometry& g) {
  p.reject_unknown({"terms", "density_beam", "density_shell", "strength"});
  std::vector<InversePowerTerm> terms;
  for (const auto& term : p.list("terms")) terms.push_back(read_term(*term));
  return std::make_shared<InversePowerSum>(std::move(terms), g, density_factor(p));
}

LawRegistry build() {
  LawRegistry r;
  r.add("lennard_jones", "Lennard-Jones disk-plate law, Eq. (6): epsilon, sigma", make_lennard_jones);
  r.add("inverse_power", "one inverse-power term k r^-m, Eq. (1): exponent, coefficient", make_inverse_power);
  r.add("inverse_power_sum", "a sum of inverse-power terms: terms: [{exponent, coefficient}, ...]",
        make_inverse_power_sum);
  return r;
}

}  // namespace

LawRegistry& law_registry() {
  static LawRegistry registry = build();
  return registry;
}

}  // namespace fibrane::laws
