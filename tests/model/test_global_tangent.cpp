// The assembled, constraint-reduced tangent of whole models against central finite differences of the
// reduced residual, at random deformed states. This covers what the point-kernel tests cannot: the
// scatter through the constraint elimination (fixes, clamps, symmetry ties, parametric-point MPCs) and the
// configuration-dependent loads (shell edge moment, beam point moment).
#include <gtest/gtest.h>

#include <random>

#include "case_runner.hpp"

namespace fibrane::testing {
namespace {

const char* const curved_shell_and_beam = R"(
shells:
  - name: panel
    geometry:
      cylinder: {radius: 3, length: 2, angles: [60, 120]}
    refine: {degree: 3, continuity: 2, elements: [3, 2]}
    thickness: 0.1
    material: {young: 1000, poisson: 0.3}
beams:
  - name: rod
    geometry:
      arc: {center: [0, 0, 0], e1: [1, 0, 0], e2: [0, 1, 0], radius: 2, angles: [0, 60]}
    refine: {degree: 3, continuity: 2, elements: 3}
    material: {young: 1000, poisson: 0.3}
    section: {circle: {radius: 0.1}}
constraints:
  - {body: panel, at: {edge: v0}, fix: [x, y, z]}
  - {body: panel, at: {edge: v1}, symmetry: x}
  - {body: panel, at: {point: [0.5, 0.5]}, prescribe: {z: 0.01}}
  - {body: rod, at: {end: start}, fix: [x, y, z, twist]}
  - {body: rod, at: {end: start}, clamp: [x, y, z]}
loads:
  - {body: panel, type: line_moment, at: {edge: u1}, moment: [0, 0.3, 0.1]}
  - {body: rod, type: point_moment, at: {end: end}, moment: [0.01, 0.02, 0.03]}
  - {body: rod, type: line_load, force: [0, 0, -0.01]}
steps: {dt: 1}
)";

TEST(GlobalTangent, MatchesFiniteDifferencesOfReducedResidual) {
  const auto dir = fresh_directory("global-tangent");
  std::ofstream(dir / "case.yaml") << curved_shell_and_beam;
  auto c = casefile::read_case((dir / "case.yaml").string());
  auto& m = *c.model;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  Eigen::VectorXd q(m.size());
  for (int i = 0; i < q.size(); ++i) q[i] = u(rng);
  const double t = 0.7;
  m.evaluate(q, t, true);
  const Eigen::MatrixXd K = Eigen::MatrixXd(m.tangent());
  // Central differences with h = 1e-6 on O(0.1) displacements: truncation ~h^2 * |r'''| ~ 1e-12 relative,
  // round-off ~1e-16 * |r| / h ~ 1e-10 relative; 1e-6 leaves a wide margin and still catches a missing term.
  const Eigen::MatrixXd Kfd = finite_difference_tangent(m, q, t, 1e-6);
  const double scale = K.cwiseAbs().maxCoeff();
  Eigen::Index bi, bj;
  const double worst = (K - Kfd).cwiseAbs().maxCoeff(&bi, &bj);
  EXPECT_LT(worst / scale, 1e-6) << "worst entry (" << bi << ", " << bj << ") = full DOFs ("
                                 << m.constraints.free_dof(static_cast<int>(bi)) << ", "
                                 << m.constraints.free_dof(static_cast<int>(bj)) << "): K = " << K(bi, bj)
                                 << ", finite differences " << Kfd(bi, bj) << "; shell DOFs end at "
                                 << m.dofs.block_size(0);
}

}  // namespace
}  // namespace fibrane::testing
