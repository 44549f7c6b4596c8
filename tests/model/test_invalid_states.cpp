// States that an overflowing time step produces (non-finite unknowns or time, coordinates near 1e200) are
// invalid states that Newton fails on, never exceptions out of the evaluation; an exception inside an
// OpenMP parallel region is carried out of it (common/parallel_errors.hpp) instead of ending the process;
// and an exception during a run's march ends it as a failed run with summary.json.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>

#include "case/case_reader.hpp"
#include "common/parallel_errors.hpp"
#include "run/run.hpp"
#include "linalg/linear_solver.hpp"
#include "temp_directory.hpp"

namespace fibrane {
namespace {

// The coupled dynamics case of the hostile runs (a beam over a membrane, Lennard-Jones FF).
casefile::Case coupled_case() {
  return casefile::read_case(std::string(FIBRANE_SOURCE_DIR) + "/tests/app/hostile_runs/dynamics_huge_dt.yaml");
}

TEST(InvalidStates, NonFiniteUnknownsOrTimeAreAnInvalidState) {
  casefile::Case c = coupled_case();
  model::Model& m = *c.model;
  const Eigen::VectorXd q0 = m.initial_unknowns();
  m.evaluate(q0, 0.0, true);
  ASSERT_TRUE(m.invalid_state().empty()) << m.invalid_state();
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (double bad : {nan, inf, -inf}) {
    Eigen::VectorXd q = q0;
    q[q.size() / 2] = bad;
    for (bool with_tangent : {false, true}) {
      ASSERT_NO_THROW(m.evaluate(q, 0.0, with_tangent));
      EXPECT_NE(m.invalid_state().find("not finite"), std::string::npos) << m.invalid_state();
      EXPECT_EQ(m.residual().size(), q0.size());
    }
  }
  ASSERT_NO_THROW(m.evaluate(q0, inf, false));
  EXPECT_NE(m.invalid_state().find("not finite"), std::string::npos);
  m.evaluate(q0, 0.0, true);  // a valid state is valid again
  EXPECT_TRUE(m.invalid_state().empty()) << m.invalid_state();
  EXPECT_TRUE(m.residual().allFinite());
}

// Finite but overflowing coordinates (squared distances infinite): the evaluation returns, with a state
// that Newton cannot accept (invalid, or a non-finite residual).
TEST(InvalidStates, OverflowingCoordinatesAreNotAnException) {
  casefile::Case c = coupled_case();
  model::Model& m = *c.model;
  const Eigen::VectorXd q0 = m.initial_unknowns();
  m.evaluate(q0, 0.0, false);
  for (double huge : {1e200, -1e300, 1e155}) {
    ASSERT_NO_THROW(m.evaluate(Eigen::VectorXd::Constant(q0.size(), huge), 0.0, true)) << huge;
    EXPECT_TRUE(!m.invalid_state().empty() || !m.residual().allFinite()) << huge;
  }
}

// A linear solver that throws at its n-th solve: an error no step anticipates.
class FailingSolver : public solve::LinearSolver {
 public:
  FailingSolver(std::unique_ptr<solve::LinearSolver> inner, int fail_at) : inner_(std::move(inner)), left_(fail_at) {}
  void analyze(const Eigen::SparseMatrix<double>& a) override { inner_->analyze(a); }
  bool factorize_numeric(const Eigen::SparseMatrix<double>& a) override { return inner_->factorize(a); }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const override {
    if (--left_ == 0) throw std::runtime_error("injected solver error");
    return inner_->solve(b);
  }
  std::string name() const override { return inner_->name(); }
  long factor_nonzeros() const override { return inner_->factor_nonzeros(); }

 private:
  std::unique_ptr<solve::LinearSolver> inner_;
  mutable int left_;
};

// An exception during the march ends the run as failed after its last finished step, with summary.json
// saying why (the command line then exits with 1).
TEST(RunErrors, AnExceptionDuringTheMarchEndsTheRunAsFailedWithASummary) {
  const auto dir = fibrane::testing::fresh_directory("run-error") / "out";
  casefile::Case c = casefile::read_case(std::string(FIBRANE_SOURCE_DIR) + "/examples/rollup-strip.yaml");
  run::RunOptions options;
  options.output_directory = dir.string();
  options.quiet = true;
  options.make_solver = [](bool symmetric) {
    return std::make_unique<FailingSolver>(solve::make_linear_solver("auto", symmetric), 30);
  };
  run::RunSummary summary;
  ASSERT_NO_THROW(summary = run::run_case(c, options));
  EXPECT_EQ(summary.result.outcome, solve::Outcome::failed);
  EXPECT_NE(summary.result.message.find("injected solver error"), std::string::npos) << summary.result.message;
  EXPECT_GT(summary.result.steps, 0);
  std::ifstream in(dir / "summary.json");
  std::stringstream json;
  json << in.rdbuf();
  EXPECT_NE(json.str().find("\"outcome\": \"failed\""), std::string::npos) << json.str();
  EXPECT_NE(json.str().find("injected solver error"), std::string::npos) << json.str();
}

TEST(FirstError, AnExceptionInAParallelRegionIsRethrownAfterIt) {
  FirstError error;
  std::atomic<int> ran{0};
#pragma omp parallel for schedule(dynamic, 1)
  for (int i = 0; i < 64; ++i) error.run([&] {
    ++ran;
    if (i % 8 == 3) throw std::out_of_range("item " + std::to_string(i));
  });
  EXPECT_EQ(ran.load(), 64);  // the other items still ran
  EXPECT_TRUE(error.failed());
  EXPECT_THROW(error.rethrow(), std::out_of_range);
  FirstError none;
#pragma omp parallel for
  for (int i = 0; i < 8; ++i) none.run([] {});
  EXPECT_FALSE(none.failed());
  EXPECT_NO_THROW(none.rethrow());
}

}  // namespace
}  // namespace fibrane
