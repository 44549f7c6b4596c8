#include "laws/section_law_registry.hpp"

#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace fibrane::laws {
namespace {

// The keys every model shares, read into a law with the given point-pair terms.
std::shared_ptr<const SectionCylinderLaw> with_common_keys(const Parameters& p, const SectionGeometry& g,
                                                           std::vector<InversePowerTerm> terms) {
  const double factor =
      p.positive_or("strength", 1.0) * p.positive_or("density_a", 1.0) * p.positive_or("density_b", 1.0);
  const double regularization = p.has("regularization") ? p.positive("regularization") : 0.0;
  const double cutoff = p.has("cutoff") ? p.positive("cutoff") : std::numeric_limits<double>::infinity();
  if (!(cutoff > regularization)) p.fail("cutoff", "a cut-off gap above the regularization gap");
  const double taper = p.has("taper") ? p.positive("taper") : 0.0;
  if (taper > cutoff - regularization) p.fail("taper", "a taper no wider than cutoff - regularization");
  return std::make_shared<SectionCylinderLaw>(std::move(terms), g.radius_a, g.radius_b, factor, regularization,
                                              cutoff, taper);
}

InversePowerTerm read_term(const Parameters& p) {
  const double m = p.number("exponent"), k = p.number("coefficient");
  if (!(m > 4.5)) p.fail("exponent", "an exponent m > 4.5 (the section-beam integral diverges otherwise)");
  if (k == 0 || !std::isfinite(k)) p.fail("coefficient", "a finite, non-zero coefficient k_m");
  return {m, k};
}

std::shared_ptr<const SectionCylinderLaw> make_lennard_jones(const Parameters& p, const SectionGeometry& g) {
  p.reject_unknown({"epsilon", "sigma", "strength", "density_a", "density_b", "regularization", "cutoff", "taper"});
  const double epsilon = p.positive("epsilon"), s6 = std::pow(p.positive("sigma"), 6);
  return with_common_keys(p, g, {{6, -4 * epsilon * s6}, {12, 4 * epsilon * s6 * s6}});
}

std::shared_ptr<const SectionCylinderLaw> make_inverse_power(const Parameters& p, const SectionGeometry& g) {
  p.reject_unknown({"exponent", "coefficient", "strength", "density_a", "density_b", "regularization", "cutoff",
                    "taper"});
  return with_common_keys(p, g, {read_term(p)});
}

std::shared_ptr<const SectionCylinderLaw> make_inverse_power_sum(const Parameters& p, const SectionGeometry& g) {
  p.reject_unknown({"terms", "strength", "density_a", "density_b", "regularization", "cutoff", "taper"});
  std::vector<InversePowerTerm> terms;
  for (const auto& term : p.list("terms")) {
    term->reject_unknown({"exponent", "coefficient"});
    terms.push_back(read_term(*term));
  }
  if (terms.empty()) p.fail("terms", "at least one term {exponent, coefficient}");
  return with_common_keys(p, g, std::move(terms));
}

SectionLawRegistry build() {
  SectionLawRegistry r;
  r.add("lennard_jones", "Lennard-Jones point pairs, Eq. (6): epsilon, sigma", make_lennard_jones);
  r.add("inverse_power", "one inverse-power term k r^-m, m > 4.5: exponent, coefficient", make_inverse_power);
  r.add("inverse_power_sum", "a sum of inverse-power terms: terms: [{exponent, coefficient}, ...]",
        make_inverse_power_sum);
  return r;
}

}  // namespace

SectionLawRegistry& section_law_registry() {
  static SectionLawRegistry registry = build();
  return registry;
}

}  // namespace fibrane::laws
