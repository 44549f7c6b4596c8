// The coupled, reduced tangent of a beam over a curved shell (pairs crossing element boundaries, clamped
// shell edge) against central differences of the reduced residual, for every formulation. FF uses its
// exact tangent; RF1's tangent is exact for its own (non-variational) residual.
#include <gtest/gtest.h>

#include <random>

#include "case_runner.hpp"

namespace fibrane::testing {
namespace {

TEST(CoupledModel, TangentMatchesFiniteDifferencesForEveryFormulation) {
  for (const std::string f : {"RF2", "RF1", "FF"}) {
    const auto dir = fresh_directory("coupled-tangent-" + f);
    std::ofstream(dir / "case.yaml") << beam_over_panel_case(", formulation: " + f);
    auto c = model::read_case((dir / "case.yaml").string());
    auto& m = *c.model;
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-0.01, 0.01);
    Eigen::VectorXd q(m.size());
    for (int i = 0; i < q.size(); ++i) q[i] = u(rng);
    m.evaluate(q, 1.0, true);
    int active = 0;
    for (const auto& p : m.couplings[0].points()) active += p.active;
    ASSERT_GT(active, 10) << "the beam must interact with the panel";
    const Eigen::MatrixXd K = Eigen::MatrixXd(m.tangent());
    // h = 1e-7 on O(1e-2) perturbations of O(1) geometry: truncation ~ h^2 |r'''| ~ 1e-12 relative,
    // round-off ~ 1e-16 |r| / h ~ 1e-9 relative; 1e-6 has margin and still catches a missing term.
    const Eigen::MatrixXd Kfd = finite_difference_tangent(m, q, 1.0, 1e-7);
    Eigen::Index bi, bj;
    const double worst = (K - Kfd).cwiseAbs().maxCoeff(&bi, &bj);
    EXPECT_LT(worst / K.cwiseAbs().maxCoeff(), 1e-6) << f << ": entry (" << bi << ", " << bj << ")";
  }
}

}  // namespace
}  // namespace fibrane::testing
