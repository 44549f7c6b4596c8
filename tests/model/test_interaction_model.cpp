// The SBS coupling inside the whole model: a straight beam parallel to a flat plate (the case that the
// surrogate plate describes exactly, Sec. 4.3), and the global tangent of a coupled curved state.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <random>
#include <set>

#include "case_runner.hpp"
#include "model/coupling.hpp"
#include "laws/lennard_jones.hpp"

namespace fibrane::testing {
namespace {

// Beam of length 4 along x at height z above a clamped plate of thickness 0.5 over [-3, 3] x [-2, 2], at
// y = `y` (0 unless given); LJ with sigma = 0.05. The plate has 6 x `plate_rows` elements; the fiber is held
// by `fiber_constraints` (the default: in the plane y = 0, its start fixed in x).
struct ParallelOptions {
  double y = 0;
  int plate_rows = 4;
  std::string fiber_constraints = "  - {body: fiber, at: {all: true}, fix: [y, twist]}\n"
                                  "  - {body: fiber, at: {end: start}, fix: [x]}\n";
};
std::string parallel_case(double z_value, const std::string& formulation, int beam_elements = 8,
                          const ParallelOptions& o = {}) {
  const std::string z = fmt::format("{:.17g}", z_value), y = fmt::format("{:.17g}", o.y);
  return R"(
shells:
  - name: plate
    geometry: {rectangle: {origin: [-3, -2, 0], edge_u: [6, 0, 0], edge_v: [0, 4, 0]}}
    refine: {degree: 2, continuity: 1, elements: [6, )" + std::to_string(o.plate_rows) + R"(]}
    thickness: 0.5
    material: {young: 1000, poisson: 0.3}
beams:
  - name: fiber
    geometry: {line: {from: [-2, )" + y + ", " + z + R"(], to: [2, )" + y + ", " + z + R"(]}}
    refine: {degree: 3, continuity: 2, elements: )" + std::to_string(beam_elements) + R"(}
    material: {young: 1000, poisson: 0.3}
    section: {circle: {radius: 0.5}}
interactions:
  - {beam: fiber, shell: plate, formulation: )" + formulation + R"(, lennard_jones: {epsilon: 0.002, sigma: 0.05}}
constraints:
  - {body: plate, at: {all: true}, fix: [x, y, z]}
)" + o.fiber_constraints + R"(steps: {dt: 1, t_end: 1, tolerance: 1e-10, tolerance_absolute: 1e-11}
output: {vtk: false}
)";
}

laws::LennardJonesDiskPlate the_law() {
  laws::LennardJonesDiskPlate law;
  law.epsilon = 0.002;
  law.sigma = 0.05;
  law.disk_radius = 0.5;
  law.plate_thickness = 0.5;
  return law;
}

// On a flat plate every beam point sees the same distance and cos(alpha) = 1, so the SBS energy is the
// beam length times the law (the quadrature integrates a constant exactly): 1e-10 relative is round-off.
TEST(InteractionModel, ParallelBeamEnergyIsLengthTimesLaw) {
  const auto law = the_law();
  const double z = law.equilibrium_distance() * 1.02;
  for (const char* f : {"RF2", "RF1", "FF"}) {
    const auto dir = fresh_directory(std::string("parallel-energy-") + f);
    std::ofstream(dir / "case.yaml") << parallel_case(z, f);
    auto c = casefile::read_case((dir / "case.yaml").string());
    c.model->evaluate(c.model->initial_unknowns(), 0.0, false);
    const double expected = 4.0 * law.evaluate(z, 1.0).value;
    EXPECT_NEAR(c.model->interactions_of<model::Coupling>()[0]->energy(), expected, 1e-10 * std::abs(expected)) << f;
  }
}

// A beam released slightly above the plate settles where phi_d(d, 1) = 0 (every formulation: cos a = 1
// stays exact for a straight parallel beam). The interaction forces are ~1e-7 here while the beam's
// elastic residual has a round-off floor of ~1e-12, so Newton stops at an absolute 1e-11; one more
// quadratic step would change d by ~(1e-11 / phi_dd) ~ 1e-12, far below the 1e-8 relative asked for.
TEST(InteractionModel, FreeBeamSettlesAtTheEquilibriumDistance) {
  const auto law = the_law();
  const double d_eq = law.equilibrium_distance();
  for (const char* f : {"RF2", "RF1", "FF"}) {
    auto yaml = parallel_case(d_eq * 1.001, f);  // inside the convex well (the gap is ~5% of d)
    yaml.replace(yaml.find("constraints:"), 12,
                 "monitors:\n  - {name: z_mid, type: position, body: fiber, at: {xi: 0.5}, component: z}\nconstraints:");
    const auto r = run_yaml(std::string("settle-") + f, yaml);
    ASSERT_TRUE(r.summary.result.completed()) << f << ": " << r.summary.result.message;
    EXPECT_NEAR(r.history.at("z_mid").back(), d_eq, 1e-8 * d_eq) << f;
  }
}

}  // namespace
}  // namespace fibrane::testing

namespace fibrane::testing {
namespace {

// symmetry_share 0.5 (a fiber lying in a mirror plane of the model) halves everything the beam
// contributes: its strain energy, its interaction energy and its share of the residual. Both are
// evaluated at the same deformed state, so the ratio is exact up to round-off.
TEST(InteractionModel, SymmetryShareHalvesTheBeamsContributions) {
  const auto law = the_law();
  auto run = [&](const std::string& share) {
    auto yaml = parallel_case(law.equilibrium_distance() * 1.01, "RF2");
    const std::string section = "    section: {circle: {radius: 0.5}}";
    yaml.replace(yaml.find(section), section.size(), section + "\n    symmetry_share: " + share);
    const auto dir = fresh_directory("share-" + share);
    std::ofstream(dir / "case.yaml") << yaml;
    auto c = casefile::read_case((dir / "case.yaml").string());
    Eigen::VectorXd q = Eigen::VectorXd::LinSpaced(c.model->size(), 0.0, 0.002);
    c.model->evaluate(q, 1.0, false);
    return std::make_tuple(c.model->strain_energy(), c.model->interactions_of<model::Coupling>()[0]->energy(),
                           Eigen::VectorXd(c.model->residual()));
  };
  const auto [e_full, i_full, r_full] = run("1.0");
  const auto [e_half, i_half, r_half] = run("0.5");
  ASSERT_GT(e_full, 0.0);
  EXPECT_NEAR(e_half, 0.5 * e_full, 1e-12 * e_full);
  EXPECT_NEAR(i_half, 0.5 * i_full, 1e-12 * std::abs(i_full));
  // The plate is fully fixed, so every free unknown is a beam DOF: the whole residual halves.
  EXPECT_LT((r_half - 0.5 * r_full).norm(), 1e-12 * r_full.norm());
}

}  // namespace
}  // namespace fibrane::testing

namespace fibrane::testing {
namespace {

// A fiber at height 1.02 d_eq over the plate of parallel_case with 6 x 8 elements, each 1 x 0.5, at y = y0
// and free to move in y. Element rows (v) are 0.5 apart in y: row k holds -2 + 0.5 k <= y < -1.5 + 0.5 k.
std::string drifting_case(double y0) {
  return parallel_case(the_law().equilibrium_distance() * 1.02, "RF2", 4,
                       {.y = y0, .plate_rows = 8,
                        .fiber_constraints = "  - {body: fiber, at: {all: true}, fix: [x, z, twist]}\n"});
}

// The element rows (v) of the shell elements in the coupling's pattern.
std::set<int> pattern_rows(const model::Coupling& coupling, int elements_u) {
  std::set<int> rows;
  for (const auto& [beam_element, shell_element] : coupling.pattern_pairs()) rows.insert(shell_element / elements_u);
  return rows;
}

// The pattern holds a 3 x 3 block of shell elements around each beam point's closest one. When a point
// leaves its block, the new block reaches one element row further on the side toward which the closest
// points have moved since the last converged state (the next rows a drifting fiber reaches), and not on
// the other side. Without a converged state before (the first evaluation), the blocks are 3 x 3.
TEST(InteractionModel, PatternBlocksReachFurtherTowardTheDrift) {
  struct Drift { double y0, dy; std::set<int> before, after; };
  for (const Drift& d : {Drift{0.7, -1.0, {4, 5, 6}, {1, 2, 3, 4}}, Drift{-0.7, 1.0, {1, 2, 3}, {3, 4, 5, 6}}}) {
    const auto dir = fresh_directory(fmt::format("pattern-drift-{}", d.dy));
    std::ofstream(dir / "case.yaml") << drifting_case(d.y0);
    auto c = casefile::read_case((dir / "case.yaml").string());
    model::Model& m = *c.model;
    const model::Coupling& coupling = *m.interactions_of<model::Coupling>()[0];
    Eigen::VectorXd q = m.initial_unknowns();
    m.evaluate(q, 0.0, false);
    EXPECT_EQ(pattern_rows(coupling, 6), d.before) << d.dy;
    m.accept(q, 0.0);
    const int beam = coupling.beam().block;
    for (int k = 0; k < m.dofs.block_size(beam); ++k) {
      const int dof = m.dofs.block_offset(beam) + k;
      if (k % 4 == 1 && m.constraints.free_index(dof) >= 0) q[m.constraints.free_index(dof)] += d.dy;
    }
    const int version = m.pattern_version();
    m.evaluate(q, 1.0, false);
    EXPECT_GT(m.pattern_version(), version) << d.dy;
    EXPECT_EQ(pattern_rows(coupling, 6), d.after) << d.dy;
  }
}

}  // namespace
}  // namespace fibrane::testing
