// The Krylov path (steps.krylov: factorisations reused as preconditioners) against the direct path on
// arc-length runs through limit points: the coarse peeling example (pull-off and the detached beam) and
// the shallow roof (snap-through). Every corrector solve is a Krylov solve to 1e-8 (arc-length passes no
// forcing term), so both paths take the same steps and agree to the Newton tolerance.
#include <gtest/gtest.h>

#include <cmath>

#include "case_runner.hpp"
#include "linalg/krylov_reuse.hpp"

namespace fibrane::testing {
namespace {

struct PathRun {
  CaseRun run;
  solve::KrylovReuseStatistics stats;  // of the Krylov run
};

// Forwards to a KrylovReuseSolver and copies its statistics out when the run destroys it.
class RecordingSolver final : public solve::LinearSolver {
 public:
  RecordingSolver(std::unique_ptr<solve::KrylovReuseSolver> inner, solve::KrylovReuseStatistics& out)
      : inner_(std::move(inner)), out_(out) {}
  ~RecordingSolver() override { out_ = inner_->statistics(); }
  void analyze(const Eigen::SparseMatrix<double>& a) override { inner_->analyze(a); }
  bool factorize_numeric(const Eigen::SparseMatrix<double>& a) override { return inner_->factorize(a); }
  bool factorize_exactly(const Eigen::SparseMatrix<double>& a) override { return inner_->factorize_exactly(a); }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const override { return inner_->solve(b); }
  Eigen::VectorXd solve_to(const Eigen::VectorXd& b, double accuracy) const override {
    return inner_->solve_to(b, accuracy);
  }
  std::string name() const override { return inner_->name(); }
  long factor_nonzeros() const override { return inner_->factor_nonzeros(); }
  std::string analysis_summary() const override { return inner_->analysis_summary(); }
  int negative_eigenvalues() const override { return inner_->negative_eigenvalues(); }
  bool exact() const override { return inner_->exact(); }

 private:
  std::unique_ptr<solve::KrylovReuseSolver> inner_;
  solve::KrylovReuseStatistics& out_;
};

// Runs the case with the direct solver, or through a KrylovReuseSolver whose statistics are returned.
PathRun run_path(const std::string& name, const std::string& yaml, bool krylov) {
  const auto dir = fresh_directory(name);
  const auto file = dir / (name + ".yaml");
  std::ofstream(file) << yaml;
  PathRun p{{casefile::read_case(file.string()), {}, {}, dir / "out"}, {}};
  run::RunOptions opt;
  opt.output_directory = p.run.directory.string();
  opt.quiet = true;
  opt.threads = 1;
  if (krylov)
    opt.make_solver = [&p](bool symmetric) -> std::unique_ptr<solve::LinearSolver> {
      return std::make_unique<RecordingSolver>(
          std::make_unique<solve::KrylovReuseSolver>(solve::make_linear_solver("auto", symmetric),
                                                     solve::KrylovReuseOptions{}, symmetric),
          p.stats);
    };
  p.run.summary = run::run_case(p.run.c, opt);
  p.run.history = read_history(p.run.directory / "history.csv");
  return p;
}

// Every column of `b` equals `a`'s to `tolerance` times the column's largest magnitude (columns that are
// zero up to round-off, below 1e-12, such as the peeling beam's lateral force, to 1e-12 absolute).
void expect_same_path(const History& a, const History& b, double tolerance) {
  expect_same_columns(a, b, [tolerance](const std::string&, double scale) {
    return scale < 1e-12 ? 1e-12 : tolerance * scale;
  });
}

TEST(KrylovPath, PeelingThroughPullOffEqualsTheDirectPath) {
  const std::string yaml = example_text("peeling.yaml", {{"elements: [20, 10]", "elements: [6, 4]"},
                                                         {"elements: 100", "elements: 20"},
                                                         {"ds: 0.02, ds_max: 0.5", "ds: 0.01, ds_max: 0.4"},
                                                         {"output: {directory: out/peeling, vtk_every: 5}",
                                                          "output: {vtk: false}"}});
  const PathRun direct = run_path("krylov-peeling-direct", yaml, false);
  const PathRun krylov = run_path("krylov-peeling", yaml, true);
  ASSERT_TRUE(direct.run.summary.result.completed());
  ASSERT_TRUE(krylov.run.summary.result.completed()) << krylov.run.summary.result.message;
  // Newton's absolute tolerance is 1e-8 on forces of O(0.1-1): states agree to ~1e-8 relative; 1e-6 of each
  // column's range leaves room for the conditioning at the turns of the path and still catches a path
  // that took another step or branch (those differ by 1e-2 or more).
  expect_same_path(direct.run.history, krylov.run.history, 1e-6);
  const auto& limit = krylov.run.history.at("limit_point");
  EXPECT_EQ(std::count(limit.begin(), limit.end(), 1.0), 2) << "pull-off and the lowest point";
  // The reuse worked across the limit points: fewer factorisations than corrector solves, and the Krylov
  // solves iterated.
  EXPECT_GT(krylov.stats.krylov_iterations, 0);
  EXPECT_LT(krylov.stats.factorizations, krylov.stats.solves / 2);
  // summary.json's linear_solver_statistics gives the same count.
  const std::string summary = read_text(krylov.run.directory / "summary.json");
  EXPECT_NE(summary.find(std::to_string(krylov.stats.factorizations) + " factorisations"), std::string::npos) << summary;
}

TEST(KrylovPath, ShallowRoofSnapThroughEqualsTheDirectPath) {
  const std::string yaml = example_text("shallow-roof.yaml");
  const PathRun direct = run_path("krylov-roof-direct", yaml, false);
  const PathRun krylov = run_path("krylov-roof", yaml, true);
  ASSERT_TRUE(direct.run.summary.result.completed());
  ASSERT_TRUE(krylov.run.summary.result.completed()) << krylov.run.summary.result.message;
  // Default Newton tolerance 1e-9 relative: 1e-6 of each column's range as above.
  expect_same_path(direct.run.history, krylov.run.history, 1e-6);
  EXPECT_GT(krylov.stats.krylov_iterations, 0);
  EXPECT_LT(krylov.stats.factorizations, krylov.stats.solves / 2);
}

}  // namespace
}  // namespace fibrane::testing
