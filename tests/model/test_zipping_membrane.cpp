// examples/zipping-membrane.yaml on a coarser mesh (membrane 6 x 3, fibers 8 elements): two fibers lying
// on a membrane in a V zip into a bundle under damped dynamics while their weight presses the membrane
// down.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "case_runner.hpp"

namespace fibrane::testing {
namespace {

// Measured on this mesh: zip_contact_length 0.069 at t = 0 (the points at the vertex), 1.18 at t = 0.3
// (the largest 1.32 at t = 0.05, overshooting); membrane_mid_z -0.032 at the end. At the end the force
// balances below hold to 0.05 % (supports), 0.04 % (adhesion) and 0.16 % (pin) of the force.
TEST(ZippingMembrane, FibersZipWhileTheMembraneDeforms) {
  const CaseRun r = run_yaml("zipping-membrane",
                             example_text("zipping-membrane.yaml", {{"elements: [10, 5]", "elements: [6, 3]"},
                                                                    {"elements: 12", "elements: 8"},
                                                                    {"elements: 12", "elements: 8"},
                                                                    {"vtk_every: 10", "vtk: false"}}));
  ASSERT_TRUE(r.summary.result.completed()) << r.summary.result.message;
  const auto& h = r.history;
  const auto& t = h.at("t");
  ASSERT_GT(t.size(), 100u);
  EXPECT_NEAR(t.back(), 0.3, 1e-12);
  for (const char* c : {"zip_contact_length", "zip_energy", "left_adhesion_energy", "right_adhesion_energy",
                        "membrane_mid_z", "kinetic_energy", "interaction_energy"})
    ASSERT_TRUE(h.count(c)) << c;

  // The fibers zip: the contact length grows from the vertex's few points to more than half the fibers.
  const auto& length = h.at("zip_contact_length");
  EXPECT_LT(length.front(), 0.1);
  EXPECT_GT(length.back(), 1.0);
  EXPECT_GT(length.back(), length.front() + 0.9);
  // ... by the fibers' attraction: the fiber-fiber energy falls to several times its start.
  EXPECT_LT(h.at("zip_energy").back(), 5 * h.at("zip_energy").front());
  // ... and they come to rest, adhering to the membrane (no point lost).
  EXPECT_LT(h.at("kinetic_energy").back(), 1e-6 * std::abs(h.at("interaction_energy").back()));
  for (const char* c : {"left_adhesion_lost_points", "right_adhesion_lost_points"})
    EXPECT_EQ(*std::max_element(h.at(c).begin(), h.at(c).end()), 0.0) << c;
  EXPECT_LT(h.at("left_adhesion_energy").back(), 0.0);

  // The membrane deflects under the bundle: down by about a third of the fiber radius.
  EXPECT_LT(h.at("membrane_mid_z").back(), -0.02);

  // Forces. Action = reaction between the fibers, at every step (the residual is the energy's gradient).
  for (std::size_t i = 0; i < t.size(); ++i)
    for (const char* c : {"x", "y", "z"}) {
      const double left = h.at(std::string("zip_force_left_") + c)[i];
      const double right = h.at(std::string("zip_force_right_") + c)[i];
      EXPECT_NEAR(left + right, 0.0, 1e-10 * std::max(1.0, std::abs(left))) << "step " << i << " " << c;
    }
  // At rest (the reactions then hold no inertia and damping forces): the membrane's supports carry the
  // weight of the fibers (2 x length 2 x 2 per length), each fiber's adhesion force carries its weight,
  // and the left fiber's pin holds the pull of the other fiber and the membrane's sideways push.
  const std::size_t e = t.size() - 1;
  EXPECT_NEAR(h.at("edges_z")[e], 8.0, 0.01 * 8.0);
  EXPECT_NEAR(h.at("left_adhesion_force_z")[e] + h.at("zip_force_left_z")[e], 4.0, 0.01 * 4.0);
  const double pull = h.at("zip_force_left_y")[e];
  EXPECT_GT(pull, 1.0);
  EXPECT_NEAR(h.at("left_pin_y")[e] + pull + h.at("left_adhesion_force_y")[e], 0.0, 0.01 * pull);
}

}  // namespace
}  // namespace fibrane::testing
