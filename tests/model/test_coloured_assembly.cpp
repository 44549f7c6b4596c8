// The coloured assembly (SparseAssembler::Strategy::Colours, the default) against the per-thread buffers
// (Strategy::ThreadBuffers) on whole models with two threads, at random deformed states: shells, beams,
// the beam-shell coupling's pairs, loads, moments, prescribed motion (the load derivative) and inertia.
#include <gtest/gtest.h>

#include <omp.h>

#include <random>

#include "case_runner.hpp"
#include "model/coupling.hpp"
#include "path/newmark.hpp"

namespace fibrane::testing {
namespace {

using solve::SparseAssembler;

double relative(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  const double scale = b.cwiseAbs().maxCoeff();
  return scale > 0 ? (a - b).cwiseAbs().maxCoeff() / scale : (a - b).cwiseAbs().maxCoeff();
}

Eigen::VectorXd values(const Eigen::SparseMatrix<double>& k) {
  return Eigen::Map<const Eigen::VectorXd>(k.valuePtr(), k.nonZeros());
}

// Evaluates two models of `yaml` (the coloured and the buffered assembly) at 3 random states, entries of q
// uniform in +-amplitude; with `dynamic`, inside a time step with random reference vectors. `prepare` runs
// on each model first.
void expect_equal_evaluations(const std::string& name, const std::string& yaml, double amplitude, bool dynamic,
                              const std::function<void(model::Model&)>& prepare = {}) {
  const auto dir = fresh_directory(name);
  std::ofstream(dir / "case.yaml") << yaml;
  auto coloured = casefile::read_case((dir / "case.yaml").string());
  auto buffered = casefile::read_case((dir / "case.yaml").string());
  model::Model& a = *coloured.model;
  model::Model& b = *buffered.model;
  b.set_assembly(SparseAssembler::Strategy::ThreadBuffers);
  const int threads = omp_get_max_threads();
  omp_set_num_threads(2);
  if (prepare) {
    prepare(a);
    prepare(b);
  }
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uniform(-1, 1);
  const int n_full = a.dofs.size();
  const Eigen::VectorXd u_ref = Eigen::VectorXd::NullaryExpr(n_full, [&] { return amplitude * uniform(rng); });
  const Eigen::VectorXd w_ref = Eigen::VectorXd::NullaryExpr(n_full, [&] { return uniform(rng); });
  solve::StepKinematics step;
  step.t_n = 0.2;
  step.t = step.dt = 0.3;
  step.mass_factor = 25.0;
  step.u_ref = &u_ref;
  step.w_ref = &w_ref;
  for (int state = 0; state < 3; ++state) {
    const Eigen::VectorXd q = Eigen::VectorXd::NullaryExpr(a.size(), [&] { return amplitude * uniform(rng); });
    const double t = 0.5 + 0.4 * uniform(rng);
    for (bool with_tangent : {true, false}) {
      for (model::Model* m : {&a, &b}) {
        if (dynamic) m->begin_step(&step);
        m->evaluate(q, t, with_tangent);
        ASSERT_EQ(m->invalid_state(), "");
      }
      // The same sums in another order: round-off of the largest entry.
      EXPECT_LE(relative(a.full_residual(), b.full_residual()), 1e-13) << "state " << state;
      EXPECT_LE(relative(a.residual(), b.residual()), 1e-13) << "state " << state;
      if (!with_tangent) continue;
      ASSERT_EQ(a.tangent().nonZeros(), b.tangent().nonZeros());
      EXPECT_LE(relative(values(a.tangent()), values(b.tangent())), 1e-13) << "state " << state;
      EXPECT_LE(relative(a.load_derivative(), b.load_derivative()), 1e-13) << "state " << state;
    }
  }
  // The buffered assembly holds a copy of the matrix values for the second thread; the coloured one none.
  const std::size_t matrix_bytes = sizeof(double) * static_cast<std::size_t>(a.tangent().nonZeros());
  EXPECT_GE(b.assembly_buffer_bytes(), matrix_bytes);
  EXPECT_LT(a.assembly_buffer_bytes(), matrix_bytes / 4);
  omp_set_num_threads(threads);
}

TEST(ColouredAssembly, BendingExampleEqualsTheBufferedAssembly) {
  expect_equal_evaluations("coloured-bending", example_text("bending.yaml", {
      {"elements: [100, 100]", "elements: [12, 12]"},
      {"elements: 400", "elements: 48"}}), 0.02, false);
}

// Every beam point on the soft minimum (`below: 2`, switched at the first accepted state): the soft element's
// overlapping sub-blocks are added after its parallel loop, still without a per-thread copy.
TEST(ColouredAssembly, SoftMinimumPointsEqualTheBufferedAssembly) {
  expect_equal_evaluations("coloured-soft", beam_over_panel_case(", soft_minimum: {width: 5.0e-3, below: 2}"), 0.005,
                           false, [](model::Model& m) {
                             const Eigen::VectorXd q = Eigen::VectorXd::Zero(m.size());
                             m.evaluate(q, 1.0, true);
                             m.accept(q, 1.0);
                             m.evaluate(q, 1.0, true);
                             ASSERT_GT(m.interactions_of<model::Coupling>()[0]->soft_points(), 10);
                           });
}

// Newton's round-off floor (Model::roundoff_floor, summed over the tangent's columns on the threads in an
// ordered sum) is the one-thread sum to round-off: a column range left out would change it at O(1).
TEST(ModelThreads, RoundoffFloorIsTheOneThreadSum) {
  if (omp_get_thread_limit() < 2) GTEST_SKIP() << "needs two OpenMP threads (OMP_THREAD_LIMIT)";
  const auto dir = fresh_directory("coloured-floor");
  std::ofstream(dir / "case.yaml") << example_text("bending.yaml", {{"elements: [100, 100]", "elements: [12, 12]"},
                                                                   {"elements: 400", "elements: 48"}});
  auto c = casefile::read_case((dir / "case.yaml").string());
  model::Model& m = *c.model;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> uniform(-1, 1);
  const Eigen::VectorXd q = Eigen::VectorXd::NullaryExpr(m.size(), [&] { return 0.02 * uniform(rng); });
  const int threads = omp_get_max_threads();
  double floor[2];
  for (int k : {0, 1}) {
    omp_set_num_threads(k + 1);
    m.evaluate(q, 0.7, true);
    floor[k] = m.roundoff_floor();
  }
  omp_set_num_threads(threads);
  ASSERT_GT(m.tangent().nonZeros(), 200000);  // large enough for the parallel sum
  EXPECT_GT(floor[0], 0.0);
  EXPECT_NEAR(floor[1], floor[0], 1e-13 * floor[0]);
}

TEST(ColouredAssembly, DynamicSnapToContactEqualsTheBufferedAssembly) {
  expect_equal_evaluations("coloured-dynamic", example_text("snap-to-contact-dynamic.yaml"), 0.01, true);
}

}  // namespace
}  // namespace fibrane::testing
