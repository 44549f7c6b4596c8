// examples/zipping.yaml, shortened: two fibers attracted into contact zip together under implicit dynamics
// without damping, and the trapezoidal rule keeps their energy.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "case_runner.hpp"

namespace fibrane::testing {
namespace {

// No external force does work on the fibers, so energy_balance (kinetic + strain + interaction energy) is
// constant but for the time-discretisation error. Drift measured as |balance(T) - balance(0)| / T over the
// run, relative to the interaction energy at t = 0 (its smallest magnitude in the run): below 1e-6 per
// unit time. With energy_tolerance 1e-10 per step, starting
// with dt = 1e-5 (the first steps from rest are short).
TEST(BeamBeamCase, ZippingKeepsEnergy) {
  const CaseRun r = run_yaml("beam-beam-zipping",
                             example_text("zipping.yaml", {{"t_end: 0.2", "t_end: 0.05"},
                                                           {"energy_tolerance: 3.0e-10", "energy_tolerance: 1.0e-10"},
                                                           {"dt: 0.01", "dt: 1.0e-5"},
                                                           {"vtk_every: 200", "vtk_every: 100000"}}));
  ASSERT_TRUE(r.summary.result.completed()) << r.summary.result.message;
  const auto& h = r.history;
  const auto& t = h.at("t");
  const auto& balance = h.at("energy_balance");
  const auto& interaction = h.at("interaction_energy");
  ASSERT_GT(t.size(), 100u);
  EXPECT_NEAR(t.back(), 0.05, 1e-12);
  // The fibers zip: the contact spreads along them, the interaction energy falls and they move.
  EXPECT_LT(interaction.back(), 1.2 * interaction.front());
  EXPECT_GT(*std::max_element(h.at("kinetic_energy").begin(), h.at("kinetic_energy").end()),
            0.05 * std::abs(interaction.front()));
  const double drift = std::abs(balance.back() - balance.front()) / t.back();
  EXPECT_LT(drift, 1e-6 * std::abs(interaction.front())) << "drift per unit time " << drift;
  for (std::size_t i = 0; i < t.size(); ++i)
    EXPECT_NEAR(balance[i], balance.front(), 1e-6 * std::abs(interaction.front())) << "step " << i;
}

}  // namespace
}  // namespace fibrane::testing
