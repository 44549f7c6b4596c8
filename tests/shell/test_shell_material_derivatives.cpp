// Consistency of every shell material on its own, at random large strains on a skewed curved reference:
// N and M are the derivatives of the energy density, the four tangent blocks the derivatives of N and M
// (central differences in the Voigt strains e and k), and the cross blocks vanish when `coupled` says so.
#include <gtest/gtest.h>

#include "shell/material_states.hpp"

namespace fibrane::shell {
namespace {

using testing::all_materials;
using testing::strained;

// Central differences with step 1e-6 on strains of size 0.1-0.5: the truncation error is
// O(step^2 * third derivative) ~ 1e-12 relative and the round-off error O(eps * Psi / step) ~ 1e-10
// relative to N, M; 1e-6 relative to each block's largest entry is far above both and far below what a
// wrong term gives (the smallest physical terms checked, the coupling blocks, are ~1e-2 of dN/de here).
constexpr double kStep = 1e-6;
constexpr double kTolerance = 1e-6;
constexpr double kThickness = 0.4;

double rel_error(const Eigen::MatrixXd& approx, const Eigen::MatrixXd& exact) {
  return (approx - exact).cwiseAbs().maxCoeff() / exact.cwiseAbs().maxCoeff();
}

struct StrainState {
  SurfaceMetric ref;
  Eigen::Vector3d e, k;
};

StrainState random_state(unsigned seed) {
  std::mt19937 rng(seed);
  // |E(zeta)| <= 0.1 + 0.2 * 0.5: large strains, C_ab positive definite through the thickness.
  return {testing::random_reference(rng), testing::random_voigt(0.1, rng), testing::random_voigt(0.5, rng)};
}

SectionResponse respond(const ShellMaterial& m, const StrainState& s, const Eigen::Vector3d& e,
                        const Eigen::Vector3d& k, bool tangent) {
  return m.respond(s.ref, strained(s.ref, e, k), kThickness, tangent);
}

TEST(ShellMaterial, SectionForcesAreEnergyDerivatives) {
  for (const auto& [name, material] : all_materials())
    for (unsigned seed : {1u, 2u, 3u}) {
      const StrainState s = random_state(seed);
      const SectionResponse exact = respond(*material, s, s.e, s.k, false);
      Eigen::Vector3d dN, dM;
      for (int i = 0; i < 3; ++i) {
        const Eigen::Vector3d d = kStep * Eigen::Vector3d::Unit(i);
        dN[i] = (respond(*material, s, s.e + d, s.k, false).energy - respond(*material, s, s.e - d, s.k, false).energy) /
                (2.0 * kStep);
        dM[i] = (respond(*material, s, s.e, s.k + d, false).energy - respond(*material, s, s.e, s.k - d, false).energy) /
                (2.0 * kStep);
      }
      EXPECT_LT(rel_error(dN, exact.N), kTolerance) << name << " seed " << seed;
      EXPECT_LT(rel_error(dM, exact.M), kTolerance) << name << " seed " << seed;
    }
}

TEST(ShellMaterial, TangentBlocksAreSectionForceDerivatives) {
  for (const auto& [name, material] : all_materials())
    for (unsigned seed : {4u, 5u, 6u}) {
      const StrainState s = random_state(seed);
      const SectionResponse exact = respond(*material, s, s.e, s.k, true);
      Eigen::Matrix3d dN_de, dN_dk, dM_de, dM_dk;  // column j: derivative by strain j
      for (int j = 0; j < 3; ++j) {
        const Eigen::Vector3d d = kStep * Eigen::Vector3d::Unit(j);
        const SectionResponse ep = respond(*material, s, s.e + d, s.k, false);
        const SectionResponse em = respond(*material, s, s.e - d, s.k, false);
        const SectionResponse kp = respond(*material, s, s.e, s.k + d, false);
        const SectionResponse km = respond(*material, s, s.e, s.k - d, false);
        dN_de.col(j) = (ep.N - em.N) / (2.0 * kStep);
        dM_de.col(j) = (ep.M - em.M) / (2.0 * kStep);
        dN_dk.col(j) = (kp.N - km.N) / (2.0 * kStep);
        dM_dk.col(j) = (kp.M - km.M) / (2.0 * kStep);
      }
      EXPECT_LT(rel_error(dN_de, exact.dN_de), kTolerance) << name << " seed " << seed;
      EXPECT_LT(rel_error(dM_dk, exact.dM_dk), kTolerance) << name << " seed " << seed;
      if (exact.coupled) {
        EXPECT_LT(rel_error(dN_dk, exact.dN_dk), kTolerance) << name << " seed " << seed;
        EXPECT_LT(rel_error(dM_de, exact.dM_de), kTolerance) << name << " seed " << seed;
        // The coupling must be large enough here for the check above to mean something.
        EXPECT_GT(exact.dN_dk.cwiseAbs().maxCoeff(), 1e-3 * exact.dN_de.cwiseAbs().maxCoeff()) << name;
      } else {
        // `coupled == false` promises vanishing cross blocks: only difference noise (~1e-10) may remain.
        const double scale = exact.dN_de.cwiseAbs().maxCoeff();
        EXPECT_LT(dN_dk.cwiseAbs().maxCoeff(), 1e-8 * scale) << name;
        EXPECT_LT(dM_de.cwiseAbs().maxCoeff(), 1e-8 * scale) << name;
      }
    }
}

// The tangent must not change N, M or the energy: the same numbers with and without it.
TEST(ShellMaterial, TangentRequestDoesNotChangeTheResponse) {
  for (const auto& [name, material] : all_materials()) {
    const StrainState s = random_state(7);
    const SectionResponse a = respond(*material, s, s.e, s.k, false);
    const SectionResponse b = respond(*material, s, s.e, s.k, true);
    EXPECT_EQ(a.energy, b.energy) << name;
    EXPECT_EQ(a.N, b.N) << name;
    EXPECT_EQ(a.M, b.M) << name;
  }
}

}  // namespace
}  // namespace fibrane::shell
