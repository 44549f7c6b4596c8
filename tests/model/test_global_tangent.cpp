// The assembled, constraint-reduced tangent of whole models against central finite differences of the
// reduced residual, at random deformed states. This covers what the point-kernel tests cannot: the
// scatter through the constraint elimination (fixes, clamps, symmetry ties, parametric-point MPCs) and the
// configuration-dependent loads (shell edge moment, beam point moment).
#include <gtest/gtest.h>

#include <algorithm>

#include "case_runner.hpp"
#include "linalg/skew_correction.hpp"
#include "linalg/symmetry_probe.hpp"
#include "path/nonlinear.hpp"

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
  auto c = read_yaml("global-tangent", curved_shell_and_beam);
  auto& m = *c.model;
  const Eigen::VectorXd q = random_unknowns(m.size(), 7);
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

// The rows the model names for its tangent's skew part hold all of it: the point moment's load stiffness
// (Eq. (54)) at a random deformed state is unsymmetric, the probe of those rows alone finds what the
// whole probe finds, and the symmetric part written into the skew rows' block leaves a symmetric matrix.
TEST(GlobalTangent, SkewCandidatesHoldTheSkewPart) {
  auto c = read_yaml("global-tangent-skew", curved_shell_and_beam);
  auto& m = *c.model;
  m.evaluate(random_unknowns(m.size(), 11), 0.7, true);
  const Eigen::SparseMatrix<double>& k = m.tangent();
  const auto candidates = m.skew_candidates();
  ASSERT_TRUE(candidates.has_value());
  EXPECT_FALSE(candidates->empty());
  EXPECT_LT(4 * candidates->size(), static_cast<std::size_t>(k.rows()));  // the probe keeps to the rows
  solve::SymmetryProbe whole, rows;
  whole.build(k);
  rows.build(k, *candidates);
  const std::vector<int> support = whole.skew_support(k);
  ASSERT_FALSE(support.empty());
  EXPECT_TRUE(std::includes(candidates->begin(), candidates->end(), support.begin(), support.end()));
  EXPECT_EQ(rows.skew_support(k), support);
  // S, symmetric in the skew rows' block alone, is symmetric everywhere to the whole probe's tolerance: the
  // rest of k differs from its transpose by the round-off of sums of symmetric element matrices only.
  Eigen::SparseMatrix<double> s = k;
  solve::SkewCorrection correction;
  ASSERT_TRUE(correction.symmetrize(s, support));
  EXPECT_TRUE(whole.symmetric(s));
}

// Newton's analyses pass the system's skew candidates to the solver, once per pattern.
TEST(GlobalTangent, AnalysesTellTheSolverTheSkewCandidates) {
  struct Recording final : solve::LinearSolver {
    void analyze(const Eigen::SparseMatrix<double>&) override { ++analyses; }
    bool factorize_numeric(const Eigen::SparseMatrix<double>&) override { return true; }
    Eigen::VectorXd solve(const Eigen::VectorXd& b) const override { return b; }
    std::string name() const override { return "recording"; }
    long factor_nonzeros() const override { return 0; }
    void set_skew_candidates(std::optional<std::vector<int>> r) override { rows = std::move(r), ++told; }
    std::optional<std::vector<int>> rows;
    int analyses = 0, told = 0;
  };
  auto c = read_yaml("global-tangent-told", curved_shell_and_beam);
  auto& m = *c.model;
  m.evaluate(Eigen::VectorXd::Zero(m.size()), 0.5, true);
  Recording solver;
  EXPECT_TRUE(solve::analyze_if_needed(solver, m, m.tangent()));
  EXPECT_FALSE(solve::analyze_if_needed(solver, m, m.tangent()));
  EXPECT_EQ(solver.analyses, 1);
  EXPECT_EQ(solver.told, 1);
  EXPECT_EQ(solver.rows, m.skew_candidates());
}

}  // namespace
}  // namespace fibrane::testing
