// The model's exact d r / d t (NonlinearSystem::load_derivative, the load vector of arc-length
// continuation) against central differences in t at fixed q: prescribed values (through the element
// matrices, K dg/dt), nodal loads, a point moment and an edge moment, each on its own load function, one of
// them a table (piecewise slope).
#include <gtest/gtest.h>

#include "case_runner.hpp"

namespace fibrane::testing {
namespace {

const char* const loaded_panel_and_rod = R"(
functions:
  slow: {linear: 0.5}
  steps: {table: [[0, 0], [0.5, 0.2], [1, 1.5]]}
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
  - {body: panel, at: {point: [0.5, 0.5]}, prescribe: {z: 0.01}}
  - {body: panel, at: {edge: v1}, prescribe: {x: 0.02}, function: steps}
  - {body: rod, at: {end: start}, fix: [x, y, twist]}
  - {body: rod, at: {end: start}, prescribe: {z: -0.03}, function: slow}
loads:
  - {body: panel, type: line_moment, at: {edge: u1}, moment: [0, 0.3, 0.1], function: steps}
  - {body: panel, type: pressure, value: 0.2, function: slow}
  - {body: rod, type: point_moment, at: {end: end}, moment: [0.01, 0.02, 0.03]}
  - {body: rod, type: line_load, force: [0, 0, -0.01], function: steps}
)";

TEST(LoadDerivative, MatchesCentralDifferencesInT) {
  auto c = read_yaml("load-derivative", loaded_panel_and_rod);
  auto& m = *c.model;
  const Eigen::VectorXd q = random_unknowns(m.size(), 11);
  // t = 0.7 lies inside the table's second segment, so the differences see one slope.
  const double t = 0.7, h = 1e-6;
  m.evaluate(q, t, true);
  const Eigen::VectorXd exact = m.load_derivative();
  ASSERT_EQ(exact.size(), m.size());
  m.evaluate(q, t + h, false);
  const Eigen::VectorXd rp = m.residual();
  m.evaluate(q, t - h, false);
  const Eigen::VectorXd fd = (rp - m.residual()) / (2 * h);
  // r is smooth in t here (quadratic at most through the prescribed values): truncation is ~h^2 |r'''|,
  // round-off ~1e-16 |r| / h ~ 1e-10 relative to r_t's scale; 1e-6 is the acceptance bound and still far
  // above both, while a missing term (any one of the five sources) is O(1) relative.
  EXPECT_LT((exact - fd).cwiseAbs().maxCoeff() / exact.cwiseAbs().maxCoeff(), 1e-6);
  // Each source is present: without the prescribed values' part the derivative would be the loads' alone.
  EXPECT_GT(exact.norm(), 0.0);
}

TEST(LoadDerivative, ComesOnlyWithTheTangent) {
  auto c = read_yaml("load-derivative-residual-only", loaded_panel_and_rod);
  auto& m = *c.model;
  m.evaluate(Eigen::VectorXd::Zero(m.size()), 0.3, false);
  EXPECT_EQ(m.load_derivative().size(), 0);
}

}  // namespace
}  // namespace fibrane::testing
