#pragma once
// The fiber-fiber laws (laws/section_cylinder.hpp) by name, for a case file's fiber-fiber interaction
// (`law: {model: NAME, ...}`), with the same point-pair models as the beam-shell registry
// (laws/law_registry.hpp) and the keys of the section-beam potential:
//   lennard_jones: epsilon, sigma; inverse_power: exponent, coefficient; inverse_power_sum: terms;
//   every model: strength, density_a, density_b (s rho_A rho_B, default 1), regularization (g_r, default 0:
//   none), cutoff (g_c, default none), taper (default cutoff / 2).
// Adding a law: one line in section_law_registry.cpp.
#include <memory>

#include "common/registry.hpp"
#include "laws/section_cylinder.hpp"

namespace fibrane::laws {

// The two fibers' circular section radii (R_A, R_B).
struct SectionGeometry {
  double radius_a = 0, radius_b = 0;
};

using SectionLawRegistry = Registry<std::shared_ptr<const SectionCylinderLaw>, const SectionGeometry&>;

// The registry of fiber-fiber laws; mutable so that programs and tests may add their own.
SectionLawRegistry& section_law_registry();

}  // namespace fibrane::laws
