// The registry of shell materials: names, parameters, defaults and located errors.
#include <gtest/gtest.h>

#include "common/error.hpp"
#include "shell/material_states.hpp"

namespace fibrane::shell {
namespace {

using Map = std::map<std::string, double>;

std::shared_ptr<const ShellMaterial> make(const std::string& model, Map values) {
  return material_registry().make(model, MapParameters("material", std::move(values)));
}

std::string error_of(const std::string& model, Map values) {
  try {
    make(model, std::move(values));
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ShellMaterialRegistry, BuildsEveryMaterialFromItsParameters) {
  EXPECT_EQ(material_registry().names_text(), "svk, neo_hookean, neo_hookean_incompressible");
  const auto svk = std::dynamic_pointer_cast<const SvkMaterial>(make("svk", {{"young", 7.0}, {"poisson", 0.2}}));
  ASSERT_TRUE(svk);
  EXPECT_EQ(svk->young(), 7.0);
  EXPECT_EQ(svk->poisson(), 0.2);

  const auto nh = std::dynamic_pointer_cast<const NeoHookeanMaterial>(
      make("neo_hookean", {{"young", 1300.0}, {"poisson", 0.3}, {"thickness_points", 6}}));
  ASSERT_TRUE(nh);
  EXPECT_DOUBLE_EQ(nh->mu(), 500.0);          // E / (2 (1 + nu))
  EXPECT_DOUBLE_EQ(nh->lambda(), 750.0);      // E nu / ((1 + nu)(1 - 2 nu))
  EXPECT_EQ(nh->thickness_points(), 6);

  const auto by_mu = std::dynamic_pointer_cast<const IncompressibleNeoHookeanMaterial>(
      make("neo_hookean_incompressible", {{"shear_modulus", 2.5}}));
  ASSERT_TRUE(by_mu);
  EXPECT_EQ(by_mu->mu(), 2.5);
  EXPECT_EQ(by_mu->thickness_points(), kDefaultThicknessPoints);
  const auto by_young = std::dynamic_pointer_cast<const IncompressibleNeoHookeanMaterial>(
      make("neo_hookean_incompressible", {{"young", 9.0}}));
  ASSERT_TRUE(by_young);
  EXPECT_DOUBLE_EQ(by_young->mu(), 3.0);  // nu = 1/2: mu = E / 3
}

TEST(ShellMaterialRegistry, RejectsInvalidParametersWithTheKey) {
  EXPECT_EQ(error_of("svk", {{"young", 1.0}, {"poisson", 0.3}, {"thickness_points", 3}}),
            "material: unknown parameter 'thickness_points'");
  EXPECT_EQ(error_of("svk", {{"young", 1.0}, {"poisson", 0.5}}),
            "material: poisson: expected a number in (-1, 0.5), got 0.5");
  EXPECT_EQ(error_of("neo_hookean", {{"young", 1.0}, {"poisson", -0.1}}),
            "material: poisson: expected a number in [0, 0.5), got -0.1");
  EXPECT_EQ(error_of("neo_hookean", {{"young", 1.0}, {"poisson", 0.3}, {"thickness_points", 2.5}}),
            "material: thickness_points: expected an integer from 1 to 20, got 2.5");
  EXPECT_EQ(error_of("neo_hookean_incompressible", {{"young", 1.0}, {"shear_modulus", 1.0}}),
            "material: young: expected either shear_modulus or young (mu = young / 3), not both, got 1");
  EXPECT_EQ(error_of("neo_hookean_incompressible", {}), "material: shear_modulus: expected a number, got nothing");
  EXPECT_EQ(error_of("mooney", {}),
            "material: expected one of svk, neo_hookean, neo_hookean_incompressible (got 'mooney'), got nothing");
}

}  // namespace
}  // namespace fibrane::shell
