// The local first update (steps.local_first_update) and Newton's local solves (steps.local_newton) against
// Newton's global updates on the bending example at a coarse mesh (contact fronts, soft points switching):
// the same steps and states to Newton's tolerance, with fewer factorisations of the whole tangent.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>

#include "case_runner.hpp"
#include "linalg/linear_solver.hpp"
#include "model/model.hpp"
#include "linalg/rank_one_terms.hpp"
#include "path/local_correction.hpp"

namespace fibrane::testing {
namespace {

// Forwards to the run's solver and counts its numeric factorisations.
class CountingSolver final : public solve::LinearSolver {
 public:
  CountingSolver(std::unique_ptr<solve::LinearSolver> inner, int& count) : inner_(std::move(inner)), count_(count) {}
  void analyze(const Eigen::SparseMatrix<double>& a) override { inner_->analyze(a); }
  bool factorize_numeric(const Eigen::SparseMatrix<double>& a) override {
    ++count_;
    return inner_->factorize(a);
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const override { return inner_->solve(b); }
  std::string name() const override { return inner_->name(); }
  long factor_nonzeros() const override { return inner_->factor_nonzeros(); }
  int negative_eigenvalues() const override { return inner_->negative_eigenvalues(); }

 private:
  std::unique_ptr<solve::LinearSolver> inner_;
  int& count_;
};

struct CountedRun {
  CaseRun run;
  int factorizations = 0;
};

CountedRun run_counted(const std::string& name, const std::string& yaml) {
  const auto dir = fresh_directory(name);
  CountedRun p{{read_yaml_in(dir, name, yaml), {}, {}, dir / "out"}, 0};
  run::RunOptions opt;
  opt.output_directory = p.run.directory.string();
  opt.quiet = true;
  opt.threads = 1;
  opt.make_solver = [&p](bool symmetric) -> std::unique_ptr<solve::LinearSolver> {
    return std::make_unique<CountingSolver>(solve::make_linear_solver("auto", symmetric), p.factorizations);
  };
  p.run.summary = run::run_case(p.run.c, opt);
  p.run.history = read_history(p.run.directory / "history.csv");
  return p;
}

// Both runs completed with the same steps and states. Newton accepts a state at the tolerance or at its
// round-off floor (~1e-7 to 1e-6 here, the `residual` column): a force imbalance of that size.
// Displacements and energies then agree to ~1e-8 of their largest magnitude, checked to 1e-6 (a step
// converged to another state, a soft point switching elsewhere, differs by 1e-3 or more); the adhesion
// force's components, sums of the points' forces whose z component nearly cancels, to ten times the
// largest accepted residual.
void expect_the_same_path(const CountedRun& global, const CountedRun& local) {
  ASSERT_TRUE(global.run.summary.result.completed()) << global.run.summary.result.message;
  ASSERT_TRUE(local.run.summary.result.completed()) << local.run.summary.result.message;
  const History& a = global.run.history;
  const History& b = local.run.history;
  EXPECT_EQ(a.at("t"), b.at("t")) << "the same steps";
  double accepted = 0;
  for (const History* h : {&a, &b})
    for (const double r : h->at("residual")) accepted = std::max(accepted, r);
  expect_same_columns(a, b, [accepted](const std::string& name, double scale) {
    return name.rfind("adhesion_force", 0) == 0 ? 10 * accepted : 1e-6 * scale;
  });
}

TEST(LocalFirstUpdate, BendingTakesTheGlobalPathsStepsWithFewerFactorisations) {
  // Newton's tolerance tightened from the paper mesh's round-off floor (1e-4) to 1e-8: the two paths'
  // states then agree to ~1e-8 of forces of O(1). Steps of one size: a step's size would otherwise follow
  // its predecessors' iteration counts (easy_iterations), which the two paths need not share.
  const std::vector<std::pair<std::string, std::string>> coarse = {
      {"elements: [100, 100]", "elements: [16, 16]"},
      {"elements: 400", "elements: 64"},
      {"dt: 0.01", "dt: 0.025"},
      {"dt_max: 0.04", "dt_max: 0.025"},
      {"tolerance_absolute: 1.0e-4", "tolerance_absolute: 1.0e-8"},
      {"output: {directory: out/bending, vtk_every: 5}", "output: {vtk: false}"}};
  auto global_edits = coarse;
  global_edits.emplace_back("  local_first_update: 0.1\n", "");
  const CountedRun global = run_counted("local-update-global", example_text("bending.yaml", global_edits));
  const CountedRun local = run_counted("local-update-local", example_text("bending.yaml", coarse));
  expect_the_same_path(global, local);
  // About one factorisation per step where the global path takes two (measured: 43 and 82 for 40 steps).
  EXPECT_LT(local.factorizations, 0.6 * global.factorizations);
  // summary.json's `local_updates`: one per attempt at a step (no first iterate converges at once here),
  // none on the global path.
  const solve::ContinuationResult& res = local.run.summary.result;
  EXPECT_EQ(res.local_updates, res.steps + res.failed_attempts);
  EXPECT_EQ(global.run.summary.result.local_updates, 0);
  std::ifstream json(local.run.directory / "summary.json");
  const std::string text((std::istreambuf_iterator<char>(json)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("\"local_updates\": " + std::to_string(res.local_updates) + ","), std::string::npos) << text;
  // summary.json's `factorizations`: the run solver's numeric factorisations, as the decorator counted them.
  EXPECT_NE(text.find("\"factorizations\": " + std::to_string(local.factorizations) + ","), std::string::npos) << text;
}

// Newton's local solves (steps.local_newton) against global updates on the coarse bending example with a
// finer fiber (the local first update off in both): the same steps and states to Newton's tolerance, local
// solves taken, and no more factorisations of the whole tangent.
TEST(LocalNewton, BendingTakesTheGlobalPathsSteps) {
  const std::vector<std::pair<std::string, std::string>> global_edits = {
      {"elements: [100, 100]", "elements: [16, 16]"},
      {"elements: 400", "elements: 256"},
      {"dt: 0.01", "dt: 0.025"},
      {"dt_max: 0.04", "dt_max: 0.025"},
      {"t_end: 1.0", "t_end: 0.5"},
      {"tolerance_absolute: 1.0e-4", "tolerance_absolute: 1.0e-8"},
      {"  local_first_update: 0.1\n", ""},
      {"output: {directory: out/bending, vtk_every: 5}", "output: {vtk: false}"}};
  auto local_edits = global_edits;
  local_edits.emplace_back("  reuse_factorization: 0.1\n", "  reuse_factorization: 0.1\n  local_newton: 6\n");
  const CountedRun global = run_counted("local-newton-global", example_text("bending.yaml", global_edits));
  const CountedRun local = run_counted("local-newton-local", example_text("bending.yaml", local_edits));
  expect_the_same_path(global, local);
  EXPECT_GT(local.run.summary.result.local_updates, 0);
  EXPECT_EQ(global.run.summary.result.local_updates, 0);
  EXPECT_LE(local.factorizations, global.factorizations);
  // The rows every local solve takes in: exactly the free unknowns whose DOF is the fiber's (y and z of
  // each control point here: x and twist are fixed), sorted.
  const model::Model& m = *local.run.c.model;
  const std::vector<int> rows = m.local_solve_rows();
  const int block = m.beams.front().block;
  const int first = m.dofs.block_offset(block), end = first + m.dofs.block_size(block);
  std::vector<int> fiber;
  for (int i = 0; i < m.size(); ++i)
    if (const int d = m.constraints.free_dof(i); d >= first && d < end) fiber.push_back(i);
  EXPECT_EQ(rows, fiber);
  EXPECT_GE(static_cast<int>(fiber.size()), 2 * m.beams.front().num_control_points() - 2);
}

// The partial evaluation behind the local update (Model::evaluate_tangent_on): at the bending example's
// state after 5 steps (fiber in contact), the principal submatrix on the local rows of that state's
// residual is the full evaluation's, bit for bit (the same element matrices added in the same order,
// one thread), while entries away from the rows are left out.
TEST(LocalFirstUpdate, PartialEvaluationGivesThePrincipalSubmatrix) {
  auto r = run_yaml("local-update-partial", example_text("bending.yaml", {
      {"elements: [100, 100]", "elements: [16, 16]"},
      {"elements: 400", "elements: 64"},
      {"t_end: 1.0", "t_end: 0.1"},
      {"output: {directory: out/bending, vtk_every: 5}", "output: {vtk: false}"}}), 1);
  ASSERT_TRUE(r.summary.result.completed()) << r.summary.result.message;
  model::Model& m = *r.c.model;
  const Eigen::VectorXd q = r.summary.q;
  const double t = r.summary.result.t_reached;
  m.evaluate(q, t, true);
  const Eigen::SparseMatrix<double> whole = m.tangent();
  // The rows a local update would take at the next step's predicted state: here those of a residual
  // concentrated at the fiber's end (its last control point's four unknowns are the seeds).
  Eigen::VectorXd seeds = Eigen::VectorXd::Zero(m.size());
  for (int i = 0; i < 4; ++i) seeds[m.size() - 1 - i] = 1.0;
  const std::vector<int> rows = solve::local_rows(seeds, whole, {.share = 0.1});
  ASSERT_GT(rows.size(), 50u);
  const model::PhaseTimes before = m.times();
  m.evaluate_tangent_on(q, t, rows, nullptr);
  EXPECT_EQ(m.times().partial_tangents, before.partial_tangents + 1);
  EXPECT_EQ(m.times().tangents, before.tangents);
  const Eigen::SparseMatrix<double>& part = m.tangent();
  std::vector<char> in(static_cast<std::size_t>(m.size()), 0);
  for (const int i : rows) in[static_cast<std::size_t>(i)] = 1;
  long compared = 0, left_out = 0;
  for (int j = 0; j < whole.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(whole, j); it; ++it) {
      if (in[static_cast<std::size_t>(it.row())] && in[static_cast<std::size_t>(j)]) {
        ASSERT_EQ(part.coeff(it.row(), j), it.value()) << it.row() << ", " << j;
        ++compared;
      } else if (part.coeff(it.row(), j) != it.value()) {
        ++left_out;
      }
    }
  EXPECT_GT(compared, 1000);
  EXPECT_GT(left_out, compared);  // most of the shell's elements were not evaluated
  // A full evaluation afterwards is the first one again.
  m.evaluate(q, t, true);
  EXPECT_EQ((m.tangent() - whole).norm(), 0.0);
}

// The soft-minimum points' rank-one terms held apart (Model::evaluate_tangent_on with `apart`): at the
// coarse bending example's end, where beam points lie on the soft minimum, the partial evaluation on all
// unknowns plus the terms held apart is the full evaluation's tangent (to round-off: the terms are summed
// in another order), one term per soft point; where only the terms write, the partial tangent holds exact
// zeros, which local_matrix leaves out among the soft elements' rows.
TEST(LocalFirstUpdate, SoftPointsRankOneTermsHeldApartSumToTheTangent) {
  auto r = run_yaml("local-update-rank-one", example_text("bending.yaml", {
      {"elements: [100, 100]", "elements: [16, 16]"},
      {"elements: 400", "elements: 64"},
      {"output: {directory: out/bending, vtk_every: 5}", "output: {vtk: false}"}}), 1);
  ASSERT_TRUE(r.summary.result.completed()) << r.summary.result.message;
  model::Model& m = *r.c.model;
  const int soft = static_cast<int>(m.model_changes());
  ASSERT_GE(soft, 2);  // the coarse run ends with 2 soft points
  const Eigen::VectorXd q = r.summary.q;
  const double t = r.summary.result.t_reached;
  m.evaluate(q, t, true);
  const Eigen::SparseMatrix<double> whole = m.tangent();
  std::vector<int> all(static_cast<std::size_t>(m.size()));
  for (int i = 0; i < m.size(); ++i) all[static_cast<std::size_t>(i)] = i;
  solve::RankOneTerms apart;
  m.evaluate_tangent_on(q, t, all, &apart);
  EXPECT_EQ(apart.size(), soft);
  const Eigen::SparseMatrix<double> part = m.tangent();
  const Eigen::SparseMatrix<double> sum = part + apart.assembled(m.size());
  const auto largest = [](const Eigen::SparseMatrix<double>& k) { return k.coeffs().cwiseAbs().maxCoeff(); };
  const double scale = largest(whole);
  EXPECT_LT(largest(sum - whole), 1e-12 * scale);
  // The terms are not negligible: without them the tangent is another.
  EXPECT_GT(largest(part - whole), 1e-6 * scale);
  // local_matrix drops exactly the zeros among the soft elements' rows.
  std::vector<char> fill(static_cast<std::size_t>(m.size()), 0);
  for (const int i : apart.fill_rows) fill[static_cast<std::size_t>(i)] = 1;
  long zeros = 0;
  for (int j = 0; j < part.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(part, j); it; ++it)
      zeros += it.value() == 0.0 && fill[static_cast<std::size_t>(it.row())] && fill[static_cast<std::size_t>(j)];
  const Eigen::SparseMatrix<double> kss = solve::local_matrix(part, all, apart);
  EXPECT_GT(zeros, 0);
  EXPECT_EQ(kss.nonZeros(), part.nonZeros() - zeros);
  // A local update with the terms apart solves with the whole tangent: its backward error is round-off's,
  // as that of the update with the whole tangent factorised.
  const Eigen::VectorXd residual = Eigen::VectorXd::LinSpaced(m.size(), -1.0, 1.0);
  Eigen::VectorXd with_terms, with_whole;
  ASSERT_TRUE(solve::local_update(residual, kss, apart, true, all, with_terms));
  ASSERT_TRUE(solve::local_update(residual, whole, {}, true, all, with_whole));
  const auto backward_error = [&](const Eigen::VectorXd& dq) {
    return (whole * dq + residual).norm() / (scale * dq.norm() + residual.norm());
  };
  EXPECT_LT(backward_error(with_whole), 1e-14);
  EXPECT_LT(backward_error(with_terms), 1e-13);
  // Without `apart` the partial evaluation holds every term in the tangent; the full evaluation afterwards
  // is the first one again.
  m.evaluate_tangent_on(q, t, all, nullptr);
  EXPECT_EQ((m.tangent() - whole).norm(), 0.0);
  m.evaluate(q, t, true);
  EXPECT_EQ((m.tangent() - whole).norm(), 0.0);
}

}  // namespace
}  // namespace fibrane::testing
