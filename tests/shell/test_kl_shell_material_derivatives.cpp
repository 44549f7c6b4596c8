// The point kernel with every material on random curved, deformed NURBS states: residual = d energy / du
// and tangent = d residual / du by central differences, and a symmetric tangent. This checks the kernel's
// use of the four material blocks, the membrane-bending coupling blocks of the neo-Hookean materials
// included.
#include <gtest/gtest.h>

#include <string>

#include "shell/bezier_patch.hpp"
#include "shell/material_states.hpp"

namespace fibrane::shell {
namespace {

using testing::evaluate;
using testing::shifted;

// Central differences with step 1e-5 on coordinates of size O(1), as in test_kl_shell_derivatives.cpp:
// truncation ~1e-10 and round-off ~1e-11 relative, far below the 1e-6 tolerance on the max-norm relative
// error. The thickness 0.4 makes the bending and coupling terms 1e-2..1 of the membrane terms here, so a
// wrong or missing coupling term shows at >= 1e-3.
constexpr double kStep = 1e-5;
constexpr double kFdTolerance = 1e-6;
constexpr double kThickness = 0.4;

struct Case {
  int p, q;
  bool rational;
  double u, v;
};

struct PatchState {
  BasisDerivs R;
  Eigen::Matrix3Xd X, x;
};

// A random doubly curved reference and a random deformed state (stretch, bend and jitter of 0.08).
PatchState make_state(const Case& c, unsigned seed) {
  std::mt19937 rng(seed);
  const int nen = (c.p + 1) * (c.q + 1);
  const auto w = c.rational ? testing::random_weights(nen, rng) : std::vector<double>{};
  PatchState s{testing::bezier_basis(c.p, c.q, c.u, c.v, w), testing::random_curved_patch(c.p, c.q, rng), {}};
  s.x = testing::random_deformation(s.X, 0.08, rng);
  return s;
}

double max_rel_error(const Eigen::MatrixXd& approx, const Eigen::MatrixXd& exact) {
  return (approx - exact).cwiseAbs().maxCoeff() / exact.cwiseAbs().maxCoeff();
}

class ShellKernelMaterials : public ::testing::TestWithParam<Case> {};

TEST_P(ShellKernelMaterials, ResidualMatchesEnergyDifferences) {
  const PatchState d = make_state(GetParam(), 31);
  for (const auto& [name, material] : testing::all_materials()) {
    const ShellSection section{kThickness, material};
    const auto exact = evaluate(section, d.R, d.X, d.x);
    ASSERT_TRUE(std::isfinite(exact.energy)) << name;
    Eigen::VectorXd fd(exact.residual.size());
    for (Eigen::Index k = 0; k < fd.size(); ++k)
      fd[k] = (evaluate(section, d.R, d.X, shifted(d.x, k, kStep)).energy -
               evaluate(section, d.R, d.X, shifted(d.x, k, -kStep)).energy) / (2.0 * kStep);
    EXPECT_LT(max_rel_error(fd, exact.residual), kFdTolerance) << name;
  }
}

TEST_P(ShellKernelMaterials, TangentMatchesResidualDifferences) {
  const PatchState d = make_state(GetParam(), 32);
  for (const auto& [name, material] : testing::all_materials()) {
    const ShellSection section{kThickness, material};
    const auto exact = evaluate(section, d.R, d.X, d.x);
    Eigen::MatrixXd fd(exact.tangent.rows(), exact.tangent.cols());
    for (Eigen::Index k = 0; k < fd.cols(); ++k)
      fd.col(k) = (evaluate(section, d.R, d.X, shifted(d.x, k, kStep)).residual -
                   evaluate(section, d.R, d.X, shifted(d.x, k, -kStep)).residual) / (2.0 * kStep);
    EXPECT_LT(max_rel_error(fd, exact.tangent), kFdTolerance) << name;
    // Symmetry is built in by mirroring blocks; 1e-13 relative allows for nothing but round-off.
    EXPECT_LT((exact.tangent - exact.tangent.transpose()).cwiseAbs().maxCoeff(),
              1e-13 * exact.tangent.cwiseAbs().maxCoeff()) << name;
  }
}

INSTANTIATE_TEST_SUITE_P(Patches, ShellKernelMaterials,
                         ::testing::Values(Case{2, 2, true, 0.3, 0.6}, Case{3, 2, false, 0.7, 0.2},
                                           Case{3, 3, true, 0.45, 0.55}),
                         [](const ::testing::TestParamInfo<Case>& info) {
                           const Case& c = info.param;
                           std::string name = "p";  // appended, not "p" + ...: GCC 12 -Wrestrict false positive
                           name += std::to_string(c.p) + "q" + std::to_string(c.q);
                           return name + (c.rational ? "_rational" : "_polynomial");
                         });

}  // namespace
}  // namespace fibrane::shell
