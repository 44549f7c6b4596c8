// Beam benchmarks through the whole chain (case file -> model -> solver -> history.csv): roll-up under an
// end moment, the Bathe-Bolourchi 45-degree bend, pure torsion, objectivity with respect to a rigid
// rotation of the reference configuration, and the quadratic rate of Newton's method on a curved case.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <iostream>
#include <numbers>
#include <random>
#include <sstream>
#include <tuple>

#include "case_runner.hpp"
#include "common/error.hpp"
#include "model/model.hpp"
#include "path/load_stepping.hpp"
#include "linalg/linear_solver.hpp"

namespace fibrane::testing {
namespace {

std::size_t index_of_time(const History& h, double t) {
  const auto& ts = h.at("t");
  for (std::size_t i = 0; i < ts.size(); ++i)
    if (std::abs(ts[i] - t) < 1e-9) return i;
  ADD_FAILURE() << "the run has no step at t = " << t;
  return ts.size() - 1;
}

// A cantilever of length L = 10 under the end moment 2 pi E I / L closes into a circle: the tip returns
// to the root within 0.5% of L; at M/2 it is a half circle with the tip at height 2L/pi on the root's
// vertical. The example (16 cubic elements) is about 100 times more accurate than that (see
// docs/verification.md), so the test keeps the tolerance and has ample margin.
TEST(BeamBenchmarks, RollUpClosesIntoCircle) {
  const auto r = run_yaml("beam-rollup", example_text("beam-rollup.yaml"));
  ASSERT_TRUE(r.summary.result.completed()) << r.summary.result.message;
  const double L = 10.0, tol = 0.005 * L;
  const auto& h = r.history;
  const std::size_t half = index_of_time(h, 0.5);
  EXPECT_NEAR(h.at("tip_x")[half], 0.0, tol);
  EXPECT_NEAR(h.at("tip_z")[half], 2.0 * L / std::numbers::pi, tol);
  EXPECT_NEAR(h.at("tip_x").back(), 0.0, tol);
  EXPECT_NEAR(h.at("tip_z").back(), 0.0, tol);
  // In-plane problem: the tip never leaves the x-z plane and does not twist (round-off only), and a
  // pure moment leaves no net force at the support (1e-9 of the couple force M / L).
  for (std::size_t i = 0; i < h.at("t").size(); ++i) {
    EXPECT_NEAR(h.at("tip_y")[i], 0.0, 1e-12 * L);
    EXPECT_NEAR(h.at("tip_twist")[i], 0.0, 1e-12);
    EXPECT_NEAR(h.at("reaction_z")[i], 0.0, 1e-9 * 62.83 / L);
  }
}

// Tip of the 45-degree bend under the dead force 600 normal to its plane: within 0.1 (absolute) of the
// inextensible Kirchhoff-rod solution of the issue. With 8 cubic elements the converged discretisation
// error is below 0.05 per component (mesh table in docs/verification.md).
TEST(BeamBenchmarks, BatheBolourchiBendTip) {
  const auto r = run_yaml("bathe-bolourchi", example_text("bathe-bolourchi.yaml"));
  ASSERT_TRUE(r.summary.result.completed()) << r.summary.result.message;
  EXPECT_NEAR(r.history.at("tip_x").back(), 47.151, 0.1);
  EXPECT_NEAR(r.history.at("tip_y").back(), 15.685, 0.1);
  EXPECT_NEAR(r.history.at("tip_z").back(), 53.469, 0.1);
}

// Pure torsion: the twist is linear along the rod, so the basis reproduces it exactly and the only errors
// are round-off and the Newton tolerance (1e-9 relative to the torque): 1e-9 relative on the twist and
// 1e-10 L on the axis. Checked at every load level up to one full turn, and up to ten full turns.
void check_torsion(const CaseRun& r, double turns_at_end) {
  ASSERT_TRUE(r.summary.result.completed()) << r.summary.result.message;
  const double L = 10.0;
  const auto& h = r.history;
  ASSERT_GE(h.at("t").size(), 5u);
  for (std::size_t i = 0; i < h.at("t").size(); ++i) {
    const double exact = 2.0 * std::numbers::pi * turns_at_end * h.at("t")[i];  // T(t) L / (G I_t)
    EXPECT_NEAR(h.at("tip_twist")[i], exact, 1e-9 * std::max(1.0, exact)) << "t = " << h.at("t")[i];
    EXPECT_NEAR(h.at("mid_twist")[i], 0.5 * exact, 1e-9 * std::max(1.0, exact));
    EXPECT_NEAR(h.at("tip_x")[i], L, 1e-10 * L);
    EXPECT_NEAR(h.at("tip_y")[i], 0.0, 1e-10 * L);
    EXPECT_NEAR(h.at("tip_z")[i], 0.0, 1e-10 * L);
  }
}

TEST(BeamBenchmarks, PureTorsionTwistIsTLOverGIt) {
  check_torsion(run_yaml("beam-torsion", example_text("beam-torsion.yaml")), 1.0);
}

TEST(BeamBenchmarks, PureTorsionTenTurns) {
  check_torsion(run_yaml("beam-torsion-10",
                         example_text("beam-torsion.yaml", {{"moment: [616.850275068085, 0, 0]",
                                                             "moment: [6168.50275068085, 0, 0]"}})),
                10.0);
}

// A curved beam with an unsymmetric section under a force, a point moment and a line load, optionally
// with every reference vector rotated by Q.
std::string curved_case(const Eigen::Matrix3d& Q, const std::string& solver = "umfpack") {
  auto v = [&](const Eigen::Vector3d& x) {
    const Eigen::Vector3d y = Q * x;
    std::ostringstream s;
    s.precision(17);
    s << "[" << y.x() << ", " << y.y() << ", " << y.z() << "]";
    return s.str();
  };
  std::ostringstream y;
  y << "beams:\n  - name: rod\n    geometry:\n      arc: {center: " << v({0, 5, 0}) << ", e1: " << v({0, -1, 0})
    << ", e2: " << v({1, 0, 0}) << ", radius: 5, angles: [0, 90]}\n"
    << "    refine: {degree: 3, continuity: 2, elements: 6}\n"
    << "    material: {young: 1.0e4, poisson: 0.3}\n"
    << "    section: {area: 0.03, inertia2: 2.0e-4, inertia3: 5.0e-4, torsion: 3.0e-4}\n"
    << "    director: " << v({0.3, 0.2, 1}) << "\n"
    << "constraints:\n"
    << "  - {body: rod, at: {end: start}, fix: [x, y, z, twist]}\n"
    << "  - {body: rod, at: {end: start}, clamp: [x, y, z]}\n"
    << "loads:\n"
    << "  - {body: rod, type: point_force, at: {end: end}, force: " << v({0.02, -0.03, 0.05}) << "}\n"
    << "  - {body: rod, type: point_moment, at: {end: end}, moment: " << v({0.1, 0.05, -0.08}) << "}\n"
    << "  - {body: rod, type: line_load, force: " << v({0, 0, -0.004}) << "}\n"
    << "monitors:\n";
  for (const char* at : {"{end: end}", "{xi: 0.5}"})
    for (const char* c : {"x", "y", "z", "twist"})
      y << "  - {name: " << (at[1] == 'e' ? "tip_" : "mid_") << c << ", type: position, body: rod, at: " << at
        << ", component: " << c << "}\n";
  // dt_min: fail fast instead of creeping on; umfpack: the load stiffness of a spatial point moment (B8-B9) is not symmetric.
  y << "steps: {t_end: 1.0, dt: 0.25, dt_max: 0.25, dt_min: 0.03, extrapolate: false, tolerance: 1e-12, solver: " << solver
    << "}\n"
    << "output: {vtk: false}\n";
  return y.str();
}

// Objectivity: rotating the reference configuration (geometry, director, loads) by Q rotates the
// deformed configuration by Q and leaves the twist unchanged. Both runs solve to 1e-12 of the load, so
// positions agree to ~1e-11 of the size; 1e-8 relative leaves room for round-off in the refinement.
TEST(BeamBenchmarks, RigidRotationOfReferenceRotatesTheDeformation) {
  const Eigen::Matrix3d Q = Eigen::AngleAxisd(2.1, Eigen::Vector3d(1, -2, 3).normalized()).toRotationMatrix();
  const auto a = run_yaml("beam-objectivity-a", curved_case(Eigen::Matrix3d::Identity()));
  const auto b = run_yaml("beam-objectivity-b", curved_case(Q));
  ASSERT_TRUE(a.summary.result.completed() && b.summary.result.completed());
  const double size = 5.0;
  for (const std::string at : {"tip_", "mid_"}) {
    auto pos = [&](const CaseRun& r) {
      return Eigen::Vector3d(r.history.at(at + "x").back(), r.history.at(at + "y").back(),
                             r.history.at(at + "z").back());
    };
    const Eigen::Vector3d xa = pos(a), xb = pos(b);
    // The case must deform substantially for the test to mean anything (the tip moves by > 0.5 R).
    const double angle = std::numbers::pi / 2.0;
    const Eigen::Vector3d tip0(5.0 * std::sin(angle), 5.0 - 5.0 * std::cos(angle), 0.0);
    if (at == "tip_") {
      EXPECT_GT((xa - tip0).norm(), 0.5 * size) << xa.transpose();
    }
    EXPECT_LT((Q * xa - xb).norm(), 1e-8 * size) << at << ": " << (Q * xa).transpose() << " vs " << xb.transpose();
    const double twist_a = a.history.at(at + "twist").back(), twist_b = b.history.at(at + "twist").back();
    EXPECT_NEAR(twist_a, twist_b, 1e-8 * std::max(1.0, std::abs(twist_a)));
  }
}

// The default solver choice ('auto') follows Model::symmetric(), which must be false when the model has
// point moments: a symmetric factorisation drops the unsymmetric part of their load stiffness and Newton
// stalls (residual oscillating around 1e-1 at every load step, endless cut-backs).
TEST(BeamBenchmarks, SpatialPointMomentConvergesWithDefaultSolver) {
  const auto r = run_yaml("beam-moment-auto", curved_case(Eigen::Matrix3d::Identity(), "auto"));
  EXPECT_TRUE(r.summary.result.completed()) << r.summary.result.message;
}

// Marches an example to t_stop (frame references updated after every converged step), then applies
// `iterations` plain Newton updates towards t_next. Returns the case and the unknowns.
struct Marched {
  casefile::Case c;
  Eigen::VectorXd q;
};

Marched march(const std::string& example, double t_stop, double t_next, int iterations, bool print) {
  const auto dir = fresh_directory("beam-march-" + example);
  std::ofstream(dir / example) << example_text(example);
  Marched r{casefile::read_case((dir / example).string()), {}};
  auto& m = *r.c.model;
  auto solver = solve::make_linear_solver("umfpack", false);
  r.q = m.initial_unknowns();
  solve::LoadStepping(r.c.run.steps, r.c.run.newton).run(m, r.q, *solver, [&](const solve::StepReport& s, const Eigen::VectorXd&) { return s.t < t_stop - 1e-12; });
  for (int k = 0; k < iterations; ++k) {
    m.evaluate(r.q, t_next, true);
    solver->analyze(m.tangent());
    if (!solver->factorize(m.tangent())) break;
    const Eigen::VectorXd dq = solver->solve(m.residual());
    // The lines scripts/beam_convergence.py collects for docs/verification.md.
    if (print)
      std::cout << "newton " << example << " t=" << t_next << " it=" << k << " |r|=" << m.residual().norm()
                << " |dq|=" << dq.norm() << "\n";
    r.q -= dq;
  }
  return r;
}

// The consistent tangent is what makes Newton converge quadratically. The global tangent test checks it
// at small random states; here it is checked where the benchmarks live: after large rotations (the
// roll-up tip turned by 135 degrees, the bend twisted and lifted), with frame references updated several
// times and Newton iterates off equilibrium, including the point-moment load stiffness. Central
// differences with h = 1e-6 on unknowns of size 1..100: truncation and round-off both stay below 1e-8
// relative (measured ~5e-10); 1e-6 still catches any missing term (which would be O(1e-2) or larger).
void expect_tangent_consistent(const std::string& example, double t_stop, double t_next, int iterations) {
  auto r = march(example, t_stop, t_next, iterations, false);
  auto& m = *r.c.model;
  m.evaluate(r.q, t_next, true);
  const Eigen::MatrixXd K = Eigen::MatrixXd(m.tangent());
  const Eigen::MatrixXd Kfd = finite_difference_tangent(m, r.q, t_next, 1e-6);
  EXPECT_LT((K - Kfd).norm(), 1e-6 * K.norm()) << example << " after " << iterations << " iterations";
}

TEST(BeamBenchmarks, TangentMatchesFiniteDifferencesAfterLargeRotations) {
  for (int iterations : {0, 1, 3}) {
    expect_tangent_consistent("beam-rollup.yaml", 0.375, 0.5, iterations);
    expect_tangent_consistent("bathe-bolourchi.yaml", 0.875, 1.0, iterations);
  }
}

// Residual and update norms of the last load step of each benchmark (printed for the docs). Newton must
// reach the round-off level of the residual (1e-10 of the largest internal force scale EA ~ 1e5..1e7,
// i.e. < 1e-4 absolute) within 12 iterations from the previous converged step.
TEST(BeamBenchmarks, NewtonHistoriesOfLastSteps) {
  for (const auto& [example, t_stop, t_next] : {std::tuple<std::string, double, double>{"bathe-bolourchi.yaml", 0.875, 1.0},
                                                {"beam-rollup.yaml", 0.875, 1.0},
                                                {"beam-rollup.yaml", 0.375, 0.5}}) {
    auto r = march(example, t_stop, t_next, 12, true);
    r.c.model->evaluate(r.q, t_next, false);
    EXPECT_LT(r.c.model->residual().norm(), 1e-4) << example;
  }
}

// An arc above 90 degrees is two rational quadratic pieces joined at a double knot; after degree
// elevation the basis is only C0 there, a free hinge for a Bernoulli-Euler beam (singular tangent, Newton
// diverged at the first iteration before this check existed). The case must be rejected as bad input.
TEST(BeamBenchmarks, AxisWithC0KnotIsAnInputError) {
  // A full turn is four quadratic pieces joined C0 (arcs below 360 degrees are C1).
  const std::string yaml = example_text("bathe-bolourchi.yaml", {{"angles: [0, 45]", "angles: [0, 360]"}});
  try {
    run_yaml("beam-c0-axis", yaml);
    FAIL() << "a beam with a C0 knot must be rejected";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("beams[0].geometry: beam 'bend': the axis is only C0 at the interior knot "
                                         "xi = 0.25"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace fibrane::testing
