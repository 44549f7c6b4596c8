// The snap-to-contact examples (examples/snap-to-contact.yaml, snap-to-contact-dynamic.yaml) on coarse
// meshes: the arc-length path passes the snap-in and the pull-off limit points with the adhesion
// hysteresis between them, and the dynamic jump into contact keeps its energy balance.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "case_runner.hpp"

namespace fibrane::testing {
namespace {

constexpr double kSigma = 0.05, kZ0 = 0.78216128295028686;  // the examples' LJ sigma and equilibrium distance

// 16 beam x 6 x 3 shell elements (the example: 50 x 10 x 5). Thresholds are qualitative features of the path
// with wide margins (the example's values in brackets): a wrong sign of the force, a path that turns back
// at a limit point or a solver that misses the inertia change breaks them.
TEST(SnapToContactExample, ArcLengthPathHasSnapInThenPullOffWithHysteresis) {
  const auto r = run_yaml("snap-coarse", example_text("snap-to-contact.yaml", {
      {"elements: [10, 5]", "elements: [6, 3]"},
      {"elements: 50", "elements: 16"},
      {"output: {directory: out/snap-to-contact, vtk_every: 5}", "output: {vtk: false}"}}), 1);
  ASSERT_TRUE(r.summary.result.completed()) << r.summary.result.message;
  const auto& t = r.history.at("t");
  const auto& end_z = r.history.at("end_z");
  const auto& force = r.history.at("reaction_z");
  const auto& negative = r.history.at("negative_eigenvalues");
  const auto& limit = r.history.at("limit_point");
  std::vector<std::size_t> flagged;
  for (std::size_t i = 0; i < t.size(); ++i)
    if (limit[i] > 0) flagged.push_back(i);
  ASSERT_EQ(flagged.size(), 2u) << "limit points";
  const std::size_t snap_in = flagged[0] - 1, pull_off = flagged[1] - 1;
  // Lowering: t rises to the snap-in (a maximum), falls along the unstable branch to the pull-off (a minimum).
  EXPECT_EQ(snap_in, static_cast<std::size_t>(std::max_element(t.begin(), t.begin() + pull_off) - t.begin()));
  EXPECT_EQ(pull_off, static_cast<std::size_t>(std::min_element(t.begin() + snap_in, t.end()) - t.begin()));
  // One negative eigenvalue strictly between the two limit points, none on the stable branches.
  for (std::size_t i = 1; i < t.size(); ++i) {
    const bool unstable = i > snap_in + 1 && i < pull_off;
    const bool stable = i < snap_in || i > pull_off + 1;
    if (unstable) {
      EXPECT_EQ(negative[i], 1.0) << "step " << i;
    }
    if (stable) {
      EXPECT_EQ(negative[i], 0.0) << "step " << i;
    }
  }
  // The hysteresis: the ends snap in lower than where they pull off (0.97 vs 1.28), and pull-off needs a
  // larger force than the free beam ever carries (1.11 vs 0.18).
  EXPECT_GT(end_z[pull_off] - end_z[snap_in], 4 * kSigma);
  EXPECT_GT(force[pull_off], 3 * force[snap_in]);
  // At the end (ends at z0) the beam adheres along its length.
  EXPECT_NEAR(r.history.at("mid_z").back(), kZ0, kSigma);
}

// The dynamic run on 12 beam x 4 x 2 shell elements: the beam jumps into contact (its middle falls from
// 5 sigma above z0 into the adhesive well) and the energy balance, which the trapezoidal rule and the
// trapezoidal work integrals keep up to the time-discretisation error, drifts by less than 1e-3 of the
// largest adhesion energy (the example's energy_tolerance 2e-6 per step gives 7e-4 here).
TEST(SnapToContactExample, DynamicJumpIntoContactKeepsItsEnergyBalance) {
  const auto r = run_yaml("snap-dynamic-coarse", example_text("snap-to-contact-dynamic.yaml", {
      {"elements: [10, 5]", "elements: [4, 2]"},
      {"elements: 50", "elements: 12"},
      {"output: {directory: out/snap-to-contact-dynamic, vtk_every: 10}", "output: {vtk: false}"}}), 1);
  ASSERT_TRUE(r.summary.result.completed()) << r.summary.result.message;
  const auto& mid = r.history.at("mid_z");
  const auto& interaction = r.history.at("interaction_energy");
  const auto& balance = r.history.at("energy_balance");
  EXPECT_GT(mid.front(), kZ0 + 4 * kSigma);
  EXPECT_LT(*std::min_element(mid.begin(), mid.end()), kZ0 + kSigma);
  double adhesion = 0, drift = 0;
  for (std::size_t i = 0; i < balance.size(); ++i) {
    adhesion = std::max(adhesion, std::abs(interaction[i]));
    drift = std::max(drift, std::abs(balance[i] - balance.front()));
  }
  EXPECT_LT(drift, 1e-3 * adhesion) << "drift " << drift << ", adhesion energy " << adhesion;
}

}  // namespace
}  // namespace fibrane::testing
