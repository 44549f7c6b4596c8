// Consistency of the shell point kernel: residual = d energy / du and tangent = d residual / du by central
// finite differences, tangent symmetry, and invariance under rigid-body motion.
#include <gtest/gtest.h>

#include <string>

#include "shell/bezier_patch.hpp"

namespace fibrane::shell {
namespace {

using testing::bezier_basis;
using testing::evaluate;
using testing::shifted;

// Central differences with step 1e-5 on coordinates of size O(1): the truncation error is
// O(step^2 * third derivative) ~ 1e-10 relative and the round-off error O(eps * |f| / step) ~ 1e-11
// relative, both far below the 1e-6 tolerance on the max-norm relative error, while a wrong term
// (even a small one such as a Christoffel-symbol correction) shows up at the 1e-3..1 level.
constexpr double kStep = 1e-5;
constexpr double kFdTolerance = 1e-6;

struct Case {
  int p, q;
  bool rational;
  double u, v;
};

// Element data at one point: random doubly curved reference, random deformed state.
struct PatchState {
  BasisDerivs R;
  Eigen::Matrix3Xd X, x;
};
PatchState make_setup(const Case& c, unsigned seed) {
  std::mt19937 rng(seed);
  const int nen = (c.p + 1) * (c.q + 1);
  const auto w = c.rational ? testing::random_weights(nen, rng) : std::vector<double>{};
  PatchState s{bezier_basis(c.p, c.q, c.u, c.v, w), testing::random_curved_patch(c.p, c.q, rng), {}};
  s.x = testing::random_deformation(s.X, 0.08, rng);
  return s;
}

double max_rel_error(const Eigen::MatrixXd& approx, const Eigen::MatrixXd& exact) {
  return (approx - exact).cwiseAbs().maxCoeff() / exact.cwiseAbs().maxCoeff();
}

// Energy/residual/tangent of the membrane-only or bending-only part: with Pi(h) = h m + h^3 b,
// m h = (8 Pi(h) - Pi(2h)) / 6 and b h^3 = (Pi(2h) - 2 Pi(h)) / 6. Checking each part on its own keeps
// the small bending terms from hiding behind the membrane terms in a common norm.
enum class Part { total, membrane, bending };
testing::PointResult evaluate_part(Part part, const ShellSection& s, const PatchState& d, const Eigen::Matrix3Xd& x) {
  if (part == Part::total) return evaluate(s, d.R, d.X, x);
  ShellSection thick = s;
  thick.thickness *= 2.0;
  const auto a = evaluate(s, d.R, d.X, x), b = evaluate(thick, d.R, d.X, x);
  const double ca = part == Part::membrane ? 8.0 / 6.0 : -2.0 / 6.0;
  const double cb = part == Part::membrane ? -1.0 / 6.0 : 1.0 / 6.0;
  return {ca * a.energy + cb * b.energy, ca * a.residual + cb * b.residual, ca * a.tangent + cb * b.tangent};
}

class ShellKernelDerivatives : public ::testing::TestWithParam<Case> {};

TEST_P(ShellKernelDerivatives, ResidualMatchesEnergyDifferences) {
  const ShellSection section = ShellSection::svk(1000.0, 0.3, 0.8);
  const PatchState d = make_setup(GetParam(), 11);
  for (Part part : {Part::total, Part::membrane, Part::bending}) {
    const auto exact = evaluate_part(part, section, d, d.x);
    Eigen::VectorXd fd(exact.residual.size());
    for (Eigen::Index k = 0; k < fd.size(); ++k)
      fd[k] = (evaluate_part(part, section, d, shifted(d.x, k, kStep)).energy -
               evaluate_part(part, section, d, shifted(d.x, k, -kStep)).energy) / (2.0 * kStep);
    EXPECT_GT(exact.residual.norm(), 0.0);
    EXPECT_LT(max_rel_error(fd, exact.residual), kFdTolerance) << "part " << int(part);
  }
}

TEST_P(ShellKernelDerivatives, TangentMatchesResidualDifferences) {
  const ShellSection section = ShellSection::svk(1000.0, 0.3, 0.8);
  const PatchState d = make_setup(GetParam(), 12);
  for (Part part : {Part::total, Part::membrane, Part::bending}) {
    const auto exact = evaluate_part(part, section, d, d.x);
    Eigen::MatrixXd fd(exact.tangent.rows(), exact.tangent.cols());
    for (Eigen::Index k = 0; k < fd.cols(); ++k)
      fd.col(k) = (evaluate_part(part, section, d, shifted(d.x, k, kStep)).residual -
                   evaluate_part(part, section, d, shifted(d.x, k, -kStep)).residual) / (2.0 * kStep);
    EXPECT_LT(max_rel_error(fd, exact.tangent), kFdTolerance) << "part " << int(part);
  }
}

TEST_P(ShellKernelDerivatives, TangentIsSymmetric) {
  const PatchState d = make_setup(GetParam(), 13);
  const auto r = evaluate(ShellSection::svk(1000.0, 0.3, 0.5), d.R, d.X, d.x);
  // Symmetry is built in by mirroring blocks; 1e-13 relative allows for nothing but round-off.
  EXPECT_LT((r.tangent - r.tangent.transpose()).cwiseAbs().maxCoeff(), 1e-13 * r.tangent.cwiseAbs().maxCoeff());
}

TEST_P(ShellKernelDerivatives, RigidBodyMotionIsStressFree) {
  const ShellSection section = ShellSection::svk(1000.0, 0.3, 0.5);
  const PatchState d = make_setup(GetParam(), 14);
  std::mt19937 rng(15);
  const Eigen::Matrix3d Q = testing::random_rotation(rng);
  const Eigen::Vector3d t(0.3, -1.2, 2.5);
  const Eigen::Matrix3Xd moved = (Q * d.X).colwise() + t;
  const auto rigid = evaluate(section, d.R, d.X, moved);
  const auto deformed = evaluate(section, d.R, d.X, d.x);
  // Strains of a rigid motion are round-off (~1e-16 of the O(1) metric), so energy and residual must
  // vanish relative to a deformed state's values by many orders of magnitude.
  EXPECT_LT(std::abs(rigid.energy), 1e-20 * deformed.energy);
  EXPECT_LT(rigid.residual.cwiseAbs().maxCoeff(), 1e-12 * deformed.residual.cwiseAbs().maxCoeff());

  // Linearized rigid modes lie in the tangent's kernel: translations at any state (the energy does not
  // see them), infinitesimal rotations omega x x_A at the stress-free rotated state.
  const double scale = deformed.tangent.cwiseAbs().maxCoeff();
  const Eigen::Index n = d.R.cols();
  for (int c = 0; c < 3; ++c) {
    Eigen::VectorXd translation = Eigen::VectorXd::Zero(3 * n);
    for (Eigen::Index A = 0; A < n; ++A) translation[3 * A + c] = 1.0;
    EXPECT_LT((deformed.tangent * translation).cwiseAbs().maxCoeff(), 1e-12 * scale);
    Eigen::VectorXd rotation(3 * n);
    for (Eigen::Index A = 0; A < n; ++A)
      rotation.segment<3>(3 * A) = Eigen::Vector3d::Unit(c).cross(moved.col(A));
    EXPECT_LT((rigid.tangent * rotation).cwiseAbs().maxCoeff(), 1e-12 * scale);
  }
}

INSTANTIATE_TEST_SUITE_P(Patches, ShellKernelDerivatives,
                         ::testing::Values(Case{2, 2, false, 0.3, 0.6}, Case{2, 3, true, 0.7, 0.2},
                                           Case{4, 4, false, 0.45, 0.8}, Case{4, 4, true, 0.15, 0.35}),
                         [](const ::testing::TestParamInfo<Case>& info) {
                           const Case& c = info.param;
                           return "p" + std::to_string(c.p) + "q" + std::to_string(c.q) +
                                  (c.rational ? "_rational" : "_polynomial");
                         });

TEST(ShellKernel, AccumulatesWithWeightAndOnlyIntoRequestedOutputs) {
  const PatchState d = make_setup({2, 2, false, 0.4, 0.4}, 16);
  const ShellSection section = ShellSection::svk(1000.0, 0.3, 0.5);
  const auto once = evaluate(section, d.R, d.X, d.x, 1.0);
  // Two calls with weights 0.25 and 0.5 must add up to 0.75 times one call with weight 1.
  double energy = 1.0;
  Eigen::VectorXd r = Eigen::VectorXd::Zero(3 * d.R.cols());
  add_shell_point(section, d.R, d.X, d.x, 0.25, &energy, &r);
  add_shell_point(section, d.R, d.X, d.x, 0.5, &energy, &r);
  EXPECT_NEAR(energy, 1.0 + 0.75 * once.energy, 1e-14 * (1.0 + once.energy));
  EXPECT_LT((r - 0.75 * once.residual).cwiseAbs().maxCoeff(), 1e-13 * once.residual.cwiseAbs().maxCoeff());

  Eigen::MatrixXd wrong_size = Eigen::MatrixXd::Zero(3, 3);
  EXPECT_THROW(add_shell_point(section, d.R, d.X, d.x, 1.0, nullptr, nullptr, &wrong_size), std::invalid_argument);
  EXPECT_THROW(add_shell_point(section, d.R, d.X.leftCols(4), d.x, 1.0, &energy, nullptr),
               std::invalid_argument);
}

}  // namespace
}  // namespace fibrane::shell
