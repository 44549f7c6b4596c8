// Arc-length continuation's control: the toys' load derivatives, restarts, the ends of a run (t_end,
// t_max, path length, max_steps, callback), step-length adaptation, cut-backs and failure.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "common/error.hpp"
#include "path/arc_length.hpp"
#include "toy_systems.hpp"

namespace fibrane::solve {
namespace {

using testing::PathPoint;
using testing::ToySystem;
using testing::Truss;

NewtonOptions tight_newton() {
  NewtonOptions opt;
  opt.tol_relative = 1e-10;
  opt.tol_absolute = 1e-14;
  return opt;
}

// Scaled length of the increment between two converged points.
double chord(const PathPoint& a, const PathPoint& b, double c) {
  const double dt = b.report.t - a.report.t;
  return std::sqrt((b.q - a.q).squaredNorm() + c * c * dt * dt);
}

TEST(ArcLengthToys, LoadDerivativeAndTangentMatchCentralDifferences) {
  // The spring-loaded truss with a curved load function lambda(t) = sin t, so that r is not linear in t.
  auto sine = [](double t) { return std::sin(t); };
  auto cosine = [](double t) { return std::cos(t); };
  std::vector<ToySystem> toys = {testing::make_fold(), testing::make_truss(Truss{}, 1.3),
                                 testing::make_truss_with_spring(Truss{0.7, 1.2}, 0.4, 0.9, sine, cosine)};
  // Central differences with h = 1e-5: truncation h^2 |r'''| / 6 ~ 2e-11 for third derivatives of O(1),
  // round-off 1e-16 / 1e-5 = 1e-11; 1e-6 relative (of max(|exact|, 1)) is far above both and far below any
  // wrong term or factor.
  const double h = 1e-5;
  for (size_t i = 0; i < toys.size(); ++i) {
    const ToySystem& toy = toys[i];
    for (const double t : {-0.4, 0.3, 1.1}) {
      for (const double shift : {0.2, 0.9, 1.7}) {
        const Eigen::VectorXd q = Eigen::VectorXd::LinSpaced(toy.size(), shift, 1.3 * shift);
        const Eigen::VectorXd exact = toy.load_derivative_at(q, t);
        ASSERT_EQ(exact.size(), toy.size());
        const Eigen::VectorXd fd = (toy.residual_at(q, t + h) - toy.residual_at(q, t - h)) / (2 * h);
        EXPECT_LE((fd - exact).norm(), 1e-6 * std::max(exact.norm(), 1.0)) << "toy " << i << " t " << t;
        const Eigen::MatrixXd k = toy.dense_tangent_at(q, t);
        for (int j = 0; j < toy.size(); ++j) {
          Eigen::VectorXd qp = q, qm = q;
          qp[j] += h;
          qm[j] -= h;
          const Eigen::VectorXd column = (toy.residual_at(qp, t) - toy.residual_at(qm, t)) / (2 * h);
          EXPECT_LE((column - k.col(j)).norm(), 1e-6 * std::max(k.col(j).norm(), 1.0))
              << "toy " << i << " column " << j;
        }
      }
    }
  }
}

// The snap-back run (2 unknowns, both limit points; solver-reported inertia and ambiguous_cosine = 1, so
// the determinant rule decides every direction and its state must survive the restart) stopped after
// `stop` steps, saved, and continued by a new method object on a new system from the saved state.
TEST(ArcLengthControl, SaveAndRestoreMidPathContinueOnTheSamePath) {
  ArcLengthControl ac;
  ac.t_end = 0.5;
  ac.ds_max = 0.05;
  ac.max_steps = 1000;
  ac.ambiguous_cosine = 1.0;
  auto run = [&](int stop, MethodState* saved, const MethodState* restored, Eigen::VectorXd& q) {
    ToySystem sys = testing::make_truss_with_spring(Truss{}, 0.5, 1.0);
    testing::InertiaSolver solver(make_linear_solver("auto", true));
    ArcLength method(ac, tight_newton());
    if (restored) method.restore(*restored);
    std::vector<PathPoint> path;
    method.run(sys, q, solver, [&](const StepReport& rep, const Eigen::VectorXd& qs) {
      path.push_back({rep, qs});
      return rep.step != stop;
    });
    if (saved) *saved = method.save();
    return path;
  };
  Eigen::VectorXd q_full = Eigen::VectorXd::Zero(2), q = Eigen::VectorXd::Zero(2);
  const std::vector<PathPoint> full = run(-1, nullptr, nullptr, q_full);
  const int stop = 40;  // after the first limit point, before the turning point of w2
  MethodState state;
  const std::vector<PathPoint> first = run(stop, &state, nullptr, q);
  ASSERT_EQ(first.size(), static_cast<size_t>(stop));
  int limits_before = 0;
  for (const PathPoint& p : first) limits_before += p.report.limit_point;
  ASSERT_EQ(limits_before, 1);
  const std::vector<PathPoint> second = run(-1, nullptr, &state, q);
  ASSERT_EQ(first.size() + second.size(), full.size());
  // Same operations on the same numbers: the restart reproduces the path to round-off (1e-12 allows for a
  // different evaluation order of the tangent at the restart point; measured: identical).
  for (size_t i = 0; i < second.size(); ++i) {
    const PathPoint& a = full[static_cast<size_t>(stop) + i];
    const PathPoint& b = second[i];
    EXPECT_EQ(a.report.step, b.report.step);
    EXPECT_NEAR(a.report.t, b.report.t, 1e-12) << "step " << a.report.step;
    EXPECT_LE((a.q - b.q).norm(), 1e-12) << "step " << a.report.step;
    EXPECT_EQ(a.report.limit_point, b.report.limit_point);
    EXPECT_EQ(a.report.iterations, b.report.iterations);
    EXPECT_EQ(a.report.negative_eigenvalues, b.report.negative_eigenvalues);
  }
  EXPECT_EQ(q, q_full);
}

TEST(ArcLengthControl, StepLengthGrowsWhileStepsAreEasyAndLandsOnTEnd) {
  // Linear spring r = 2 q - t: the tangent predictor is exact, every step converges at the predictor, so
  // ds doubles (growth) up to ds_max; c = |dq/dt| = 0.5.
  ToySystem spring(
      1, [](const Eigen::VectorXd& q, double t) { return Eigen::VectorXd::Constant(1, 2 * q[0] - t); },
      [](const Eigen::VectorXd&, double) { return Eigen::MatrixXd::Constant(1, 1, 2.0); },
      [](const Eigen::VectorXd&, double) { return Eigen::VectorXd::Constant(1, -1.0); });
  auto solver = make_linear_solver("cholmod", true);
  ArcLengthControl ac;
  ac.ds_initial = 0.01;
  ac.ds_max = 0.1;
  ac.t_end = 1.0;
  ArcLength method(ac, NewtonOptions{});
  std::vector<PathPoint> path = {{StepReport{}, Eigen::VectorXd::Zero(1)}};
  const ContinuationResult res = testing::trace(method, spring, Eigen::VectorXd::Zero(1), *solver, path);
  ASSERT_EQ(res.outcome, Outcome::reached_end) << res.message;
  EXPECT_NEAR(method.load_scale(), 0.5, 1e-15);
  const std::vector<double> expected = {0.01, 0.02, 0.04, 0.08, 0.1};
  for (size_t i = 1; i + 1 < path.size(); ++i)
    EXPECT_NEAR(chord(path[i - 1], path[i], 0.5), expected[std::min(i - 1, expected.size() - 1)], 1e-14) << i;
  EXPECT_EQ(path.back().report.t, 1.0);
  EXPECT_NEAR(path.back().q[0], 0.5, 1e-14);
  EXPECT_LT(path[path.size() - 2].report.t, 1.0);
}

TEST(ArcLengthControl, EndsOutsideTheLoadRangeAndAtThePathLength) {
  {
    ToySystem fold = testing::make_fold();
    auto solver = make_linear_solver("auto", true);
    ArcLengthControl ac;
    ac.t_max = 0.5;
    ac.t_end = 2.0;
    std::vector<PathPoint> path;
    const ContinuationResult res = testing::trace(*std::make_unique<ArcLength>(ac, tight_newton()), fold,
                                                  Eigen::VectorXd::Zero(1), *solver, path);
    EXPECT_EQ(res.outcome, Outcome::reached_end);
    EXPECT_NE(res.message.find("t_max"), std::string::npos) << res.message;
    EXPECT_GT(path.back().report.t, 0.5);  // the step that left the range is reported, the one before not
    EXPECT_LE(path[path.size() - 2].report.t, 0.5);
  }
  ToySystem truss = testing::make_truss(Truss{}, 1.0);
  auto solver = make_linear_solver("auto", true);
  ArcLengthControl ac;
  ac.max_path_length = 1.0;  // through the first limit point (at path length ~0.7)
  ac.ds_max = 0.15;
  ArcLength method(ac, tight_newton());
  std::vector<PathPoint> path = {{StepReport{}, Eigen::VectorXd::Zero(1)}};
  const ContinuationResult res = testing::trace(method, truss, Eigen::VectorXd::Zero(1), *solver, path);
  EXPECT_EQ(res.outcome, Outcome::reached_end);
  EXPECT_NE(res.message.find("path length"), std::string::npos) << res.message;
  EXPECT_NEAR(method.save().at("path_length").at(0), 1.0, 1e-12);
  // Every converged step of the quadratic corrector lies on its sphere: the chords add up to the length.
  double length = 0;
  for (size_t i = 1; i < path.size(); ++i) length += chord(path[i - 1], path[i], method.load_scale());
  EXPECT_NEAR(length, 1.0, 1e-9);
  int limits = 0;
  for (const PathPoint& p : path) limits += p.report.limit_point;
  EXPECT_EQ(limits, 1);
}

TEST(ArcLengthControl, StopsAfterMaxStepsAndOnTheCallback) {
  ToySystem fold = testing::make_fold();
  auto solver = make_linear_solver("auto", true);
  ArcLengthControl ac;
  ac.max_steps = 3;
  Eigen::VectorXd q = Eigen::VectorXd::Zero(1);
  ContinuationResult res = ArcLength(ac, tight_newton()).run(fold, q, *solver, nullptr);
  EXPECT_EQ(res.outcome, Outcome::max_steps);
  EXPECT_EQ(res.steps, 3);
  ac.max_steps = 100;
  q.setZero();
  res = ArcLength(ac, tight_newton()).run(fold, q, *solver, [](const StepReport& rep, const Eigen::VectorXd&) {
    return rep.step < 2;
  });
  EXPECT_EQ(res.outcome, Outcome::stopped);
  EXPECT_EQ(res.steps, 2);
  EXPECT_NEAR(res.t_reached, testing::fold_f(q[0]), 1e-10);  // q is the last converged state
}

TEST(ArcLengthControl, CutsBackFailedStepsAndRejectsEveryAttempt) {
  // One Newton update per attempt: only steps short enough for the predictor to be within the quadratic
  // convergence radius (ds ~ 1e-3) converge, so the first attempts with ds = 1.6, 0.8, ... fail.
  ToySystem fold = testing::make_fold();
  auto solver = make_linear_solver("auto", true);
  ArcLengthControl ac;
  ac.ds_initial = 1.6;
  ac.ds_max = 1.6;
  ac.max_steps = 30;
  NewtonOptions opt = tight_newton();
  opt.max_iterations = 1;
  ArcLength method(ac, opt);
  std::vector<PathPoint> path;
  const ContinuationResult res = testing::trace(method, fold, Eigen::VectorXd::Zero(1), *solver, path);
  EXPECT_EQ(res.outcome, Outcome::max_steps) << res.message;
  int cutbacks = 0;
  for (const PathPoint& p : path) {
    cutbacks += p.report.cutbacks;
    EXPECT_LE(p.report.iterations, 1);
    EXPECT_LE(std::abs(p.report.t - testing::fold_f(p.q[0])), 1e-10);
  }
  EXPECT_GE(path.front().report.cutbacks, 5);
  EXPECT_EQ(fold.rejected(), cutbacks);  // sys.reject() before every retry
  EXPECT_EQ(res.failed_attempts, cutbacks);
  EXPECT_EQ(fold.accepted(), res.steps);
}

TEST(ArcLengthControl, FailsCleanlyBelowDsMin) {
  ToySystem fold = testing::make_fold();
  auto solver = make_linear_solver("auto", true);
  ArcLengthControl ac;
  ac.ds_initial = ac.ds_max = 1.6;
  ac.ds_min = 0.5;
  NewtonOptions opt = tight_newton();
  opt.max_iterations = 1;
  Eigen::VectorXd q = Eigen::VectorXd::Zero(1);
  const ContinuationResult res = ArcLength(ac, opt).run(fold, q, *solver, nullptr);
  EXPECT_EQ(res.outcome, Outcome::failed);
  EXPECT_FALSE(res.completed());
  EXPECT_NE(res.message.find("ds_min"), std::string::npos) << res.message;
  EXPECT_EQ(q[0], 0.0);  // the starting state, untouched
  EXPECT_EQ(fold.rejected(), 2);  // 1.6 and 0.8 tried, 0.4 < ds_min
  EXPECT_EQ(res.failed_attempts, 2);
  EXPECT_EQ(fold.accepted(), 0);
}

// Newton at fixed t = t_end needs a factorisation of K; a solver that refuses all of them (the arc-length
// steps themselves go through the extended system) makes every landing fail: the crossing step is cut
// back until ds < ds_min, and q stays at the last point before t_end.
TEST(ArcLengthControl, FailedLandingsOnTEndAreCutBack) {
  ToySystem fold = testing::make_fold();
  testing::RefusingSolver solver;
  ArcLengthControl ac;
  ac.t_end = 0.5;
  ac.ds_min = 1e-3;
  Eigen::VectorXd q = Eigen::VectorXd::Zero(1);
  const ContinuationResult res = ArcLength(ac, tight_newton()).run(fold, q, solver, nullptr);
  EXPECT_EQ(res.outcome, Outcome::failed);
  EXPECT_NE(res.message.find("landing on t_end"), std::string::npos) << res.message;
  EXPECT_LT(res.t_reached, 0.5);
  EXPECT_LE(std::abs(testing::fold_f(q[0]) - res.t_reached), 1e-10);
  // Each failed landing: one reject before the landing Newton, one before the retry.
  EXPECT_EQ(fold.rejected() % 2, 0);
  EXPECT_GE(fold.rejected(), 14);  // ds >= 0.1 at the crossing: at least 7 halvings to fall below 1e-3
}

TEST(ArcLengthControl, InvalidOptionsAndMissingLoadDerivativeAreRefused) {
  ArcLengthControl bad;
  bad.cutback = 1.0;
  EXPECT_THROW(ArcLength(bad, NewtonOptions{}), InputError);
  bad = ArcLengthControl{};
  bad.ds_min = 0.0;
  EXPECT_THROW(ArcLength(bad, NewtonOptions{}), InputError);
  bad = ArcLengthControl{};
  bad.initial_direction = 0;
  EXPECT_THROW(ArcLength(bad, NewtonOptions{}), InputError);
  bad = ArcLengthControl{};
  bad.t_start = 2.0;
  bad.t_max = 1.0;
  EXPECT_THROW(ArcLength(bad, NewtonOptions{}), InputError);
  ToySystem no_derivative(
      1, [](const Eigen::VectorXd& q, double t) { return Eigen::VectorXd::Constant(1, q[0] - t); },
      [](const Eigen::VectorXd&, double) { return Eigen::MatrixXd::Constant(1, 1, 1.0); },
      [](const Eigen::VectorXd&, double) { return Eigen::VectorXd(); });
  auto solver = make_linear_solver("auto", true);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(1);
  EXPECT_THROW(ArcLength(ArcLengthControl{}, NewtonOptions{}).run(no_derivative, q, *solver, nullptr),
               std::invalid_argument);
}

}  // namespace
}  // namespace fibrane::solve
