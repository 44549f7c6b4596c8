// Monitors that mean what their names say. Reactions are the forces the supports exert: with the applied
// load they close the balance of forces (sum of all reactions + applied load = 0 per direction), checked on
// a clamped cantilever (its clamp ties a second row of control points), the pinched-cylinder octant (its
// load point is tied to its neighbours by two symmetry planes) and the peeling example (a coupled run with
// prescribed displacements only). Beam section monitors against pure torsion's exact solution.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "case_runner.hpp"

namespace fibrane::testing {
namespace {

// Newton converges to 1e-9 of the load level (the default), so a balance of forces closes to that times
// the load; 1e-7 relative leaves margin for the summation over the supports.
constexpr double kBalance = 1e-7;

std::string full_precision(double x) {
  std::ostringstream s;
  s.precision(17);
  s << x;
  return s.str();
}

TEST(Monitors, ClampedCantileverReactionBalancesTheTipLoad) {
  const auto r = run_yaml("monitor-cantilever",
                          example_text("bathe-bolourchi.yaml",
                                       {{"  - {name: root_force_z,",
                                         "  - {name: applied_z, type: applied_load, component: z}\n"
                                         "  - {name: root_named_z, type: reaction, constraint: root, component: z}\n"
                                         "  - {name: root_force_z,"},
                                        {"  - {body: bend, at: {end: start}, fix: [x, y, z, twist]}\n"
                                         "  - {body: bend, at: {end: start}, clamp: [x, y, z]}",
                                         "  - {name: root, body: bend, at: {end: start}, fix: [x, y, z, twist], "
                                         "clamp: [x, y, z]}"}}));
  ASSERT_TRUE(r.summary.result.completed()) << r.summary.result.message;
  const auto& h = r.history;
  for (std::size_t i = 1; i < h.at("t").size(); ++i) {
    const double applied = h.at("applied_z")[i];
    EXPECT_NEAR(applied, 600 * h.at("t")[i], 1e-9);
    // The site form (the end's control point and the row its clamp ties to it) and the named constraint
    // give the same support force, and it balances the tip load.
    EXPECT_NEAR(h.at("root_force_z")[i] + applied, 0.0, kBalance * 600) << "step " << i;
    EXPECT_NEAR(h.at("root_named_z")[i], h.at("root_force_z")[i], kBalance * 600) << "step " << i;
  }
}

// The octant (linear analysis): all support forces balance the quarter load. Then the same deflection
// prescribed at the load point instead of the load: the reaction there, which includes the neighbours
// that the two symmetry planes tie to the point, is the quarter load (the point's own DOF alone carries
// only part of it). Monitors of a linear analysis are evaluated with the model's (nonlinear) residual at
// the linear solution: balances close to the size of that residual (history's `residual`, ~3e-5 of the
// load here; the stiff shell's round-off floor is of the same order), times sqrt(n) at most for a sum.
TEST(Monitors, OctantCylinderReactionIsThePinchingLoad) {
  const auto loaded = run_yaml(
      "monitor-octant",
      example_text("pinched-cylinder.yaml",
                   {{"monitors:\n", "monitors:\n"
                                    "  - {name: supports_z, type: reaction, body: cylinder, at: {all: true}, component: z}\n"
                                    "  - {name: applied_z, type: applied_load, component: z}\n"}}));
  ASSERT_TRUE(loaded.summary.result.completed()) << loaded.summary.result.message;
  const double applied = loaded.history.at("applied_z").back(), w = loaded.history.at("w_load").back();
  EXPECT_NEAR(applied, -0.25, 1e-15);
  const double floor = 10 * loaded.history.at("residual").back();
  EXPECT_NEAR(loaded.history.at("supports_z").back() + applied, 0.0, floor);

  const auto driven = run_yaml(
      "monitor-octant-driven",
      example_text("pinched-cylinder.yaml",
                   {{"  - {body: cylinder, type: point_force, at: {corner: [1, 1]}, force: [0, 0, -0.25]}   # a quarter of P = 1\n", ""},
                    {"loads:\n", ""},
                    {"constraints:\n", "constraints:\n  - {name: pinch, body: cylinder, at: {corner: [1, 1]}, "
                                       "prescribe: {z: " + full_precision(w) + "}}\n"},
                    {"monitors:\n", "monitors:\n"
                                    "  - {name: pinch_z, type: reaction, body: cylinder, at: {corner: [1, 1]}, component: z}\n"
                                    "  - {name: pinch_named_z, type: reaction, constraint: pinch, component: z}\n"}}));
  ASSERT_TRUE(driven.summary.result.completed()) << driven.summary.result.message;
  // The support holds the point where the load pushed it: the same force; the point's DOF alone does not.
  EXPECT_NEAR(driven.history.at("pinch_z").back(), applied, floor);
  EXPECT_GT(floor, 0.0);
  EXPECT_LT(floor, 1e-3 * 0.25);
  EXPECT_NEAR(driven.history.at("pinch_named_z").back(), driven.history.at("pinch_z").back(), 1e-12);
}

TEST(Monitors, PeelingSupportForcesBalance) {
  const auto r = run_yaml("monitor-peeling",
                          example_text("peeling.yaml",
                                       {{"refine: {degree: 4, continuity: 1, elements: [20, 10]}",
                                         "refine: {degree: 3, continuity: 1, elements: [6, 3]}"},
                                        {"refine: {degree: 4, continuity: 1, elements: 100}",
                                         "refine: {degree: 3, continuity: 1, elements: 16}"},
                                        {"t_end: 0.3", "t_end: 0.004"},
                                        {"monitors:\n",
                                         "monitors:\n"
                                         "  - {name: membrane_z, type: reaction, body: membrane, at: {all: true}, "
                                         "component: z}\n"}}));
  ASSERT_TRUE(r.summary.result.completed()) << r.summary.result.message;
  const auto& h = r.history;
  ASSERT_GT(h.at("t").size(), 3u);
  for (std::size_t i = 1; i < h.at("t").size(); ++i) {
    // No applied load: what pulls the beam's ends holds the membrane down through the adhesion.
    // The example's Newton stops at |r| <= 1e-8 absolute: the balance closes to the sum of the residual's
    // components, at most sqrt(n) |r| (n ~ 500 unknowns here).
    const double pull = h.at("reaction_total_z")[i];
    EXPECT_NEAR(pull + h.at("membrane_z")[i], 0.0, 30 * h.at("residual")[i]) << "step " << i;
  }
}

// Pure torsion (examples/beam-torsion.yaml): uniform twist rate T / (G I_t), T = t T_1 with one full turn
// of the tip at t = 1. The twist angle integrates the twist rate, so it reaches 2 pi; the rotation vector
// of the tip section turns about x by 2 pi t (mod 2 pi, in [0, pi]); the torque is T everywhere.
TEST(Monitors, BeamSectionQuantitiesOfPureTorsion) {
  const std::string extra =
      "  - {name: tip_angle, type: twist_angle, body: rod, at: {end: end}}\n"
      "  - {name: mid_angle, type: twist_angle, body: rod, at: {xi: 0.3}}\n"
      "  - {name: tip_rotation_x, type: rotation, body: rod, at: {end: end}, component: x}\n"
      "  - {name: tip_rotation_axis, type: rotation, body: rod, at: {end: end}, axis: [2, 0, 0]}\n"
      "  - {name: mid_torque, type: section, body: rod, at: {xi: 0.37}, quantity: torque}\n"
      "  - {name: mid_bending, type: section, body: rod, at: {xi: 0.37}, quantity: bending2}\n"
      "  - {name: tip_a2_z, type: director2, body: rod, at: {end: end}, component: z}\n";
  const auto r = run_yaml("monitor-torsion", example_text("beam-torsion.yaml", {{"monitors:\n", "monitors:\n" + extra}}));
  ASSERT_TRUE(r.summary.result.completed()) << r.summary.result.message;
  const auto& h = r.history;
  const double torque = 616.850275068085, pi = std::numbers::pi;
  for (std::size_t i = 1; i < h.at("t").size(); ++i) {
    const double t = h.at("t")[i], angle = 2 * pi * t;
    // Quadratic elements represent the linear twist exactly; Newton's tolerance 1e-10 leaves ~1e-10.
    EXPECT_NEAR(h.at("tip_angle")[i], angle, 1e-8) << t;
    EXPECT_NEAR(h.at("mid_angle")[i], 0.3 * angle, 1e-8) << t;
    const double wrapped = std::abs(std::remainder(angle, 2 * pi));
    EXPECT_NEAR(std::abs(h.at("tip_rotation_x")[i]), wrapped, 1e-8) << t;
    EXPECT_NEAR(h.at("tip_rotation_axis")[i], h.at("tip_rotation_x")[i], 1e-12) << t;
    EXPECT_NEAR(h.at("mid_torque")[i], t * torque, 1e-6 * torque) << t;
    EXPECT_NEAR(h.at("mid_bending")[i], 0.0, 1e-6 * torque) << t;
    EXPECT_NEAR(std::abs(h.at("tip_a2_z")[i]), std::abs(std::cos(angle)), 1e-8) << t;
  }
}

}  // namespace
}  // namespace fibrane::testing
