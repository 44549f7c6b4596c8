// Quasi-time continuation: displacement control through a limit point, cut-back and recovery, failure
// below dt_min, step-size control, reuse of the symbolic analysis, the predictors and their restart.
#include <gtest/gtest.h>

#include <functional>

#include <cmath>

#include "common/error.hpp"
#include "path/load_stepping.hpp"
#include "spring_network.hpp"
#include "toy_systems.hpp"

namespace fibrane::solve {
namespace {

using testing::Bar;
using testing::SpringNetwork;

// Decorator counting the calls that reach the real solver.
class CountingSolver : public LinearSolver {
 public:
  explicit CountingSolver(std::unique_ptr<LinearSolver> inner) : inner_(std::move(inner)) {}
  void analyze(const Eigen::SparseMatrix<double>& a) override { ++analyses, inner_->analyze(a); }
  bool factorize_numeric(const Eigen::SparseMatrix<double>& a) override { return ++factorize_calls, inner_->factorize(a); }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const override { return inner_->solve(b); }
  std::string name() const override { return "counting " + inner_->name(); }
  long factor_nonzeros() const override { return inner_->factor_nonzeros(); }
  int analyses = 0, factorize_calls = 0;

 private:
  std::unique_ptr<LinearSolver> inner_;
};

// Von Mises truss: supports A(-1,0), B(1,0), apex C(0,h); a linear spring from C up to D(0,h+1) whose top
// is pulled down, u_Dy = -2 t (displacement control), and u_Dx = u_Cx (MPC). The apex snaps through
// the flat position; the stiff spring keeps the controlled path stable.
constexpr double kHeight = 0.5, kTruss = 1.0, kSpring = 1.0;

SpringNetwork make_truss() {
  ConstraintSet cs;
  for (int dof : {0, 1, 2, 3}) cs.fix(dof);
  cs.add({6, {{4, 1.0}}, 0.0, -1});
  cs.fix(7, -2.0, 0);
  return SpringNetwork({{-1, 0}, {1, 0}, {0, kHeight}, {0, kHeight + 1}},
                       {{0, 2, kTruss, 0.0}, {1, 2, kTruss, 0.0}, {2, 3, kSpring, 0.0}}, cs, {});
}

// Vertical force the two bars exert on the apex at apex displacement v (positive = up).
double truss_force(double v) {
  const double rest = std::sqrt(1 + kHeight * kHeight), length = std::sqrt(1 + (kHeight + v) * (kHeight + v));
  return -2 * kTruss * (length - rest) * (kHeight + v) / length;
}

// Apex equilibrium truss_force(v) = kSpring (v - w) solved by bisection (the difference is monotonic
// because kSpring exceeds the truss's largest negative stiffness 0.236).
double apex_displacement(double w) {
  double lo = -5, hi = 5;
  auto f = [w](double v) { return kSpring * (v - w) - truss_force(v); };
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (f(mid) > 0 ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

TEST(Continuation, DisplacementControlThroughTheSnapMatchesTheAnalyticalPath) {
  SpringNetwork truss = make_truss();
  truss.set_parallel_threshold(0);  // exercise the threaded assembly inside the full loop
  CountingSolver solver(make_linear_solver("auto", true));
  Eigen::VectorXd q = Eigen::VectorXd::Zero(truss.size());
  StepControl sc;
  sc.dt_initial = 0.02;
  sc.dt_max = 0.05;
  NewtonOptions opt;
  opt.tol_relative = 1e-12;
  double min_reaction = 0, max_reaction = 0;
  auto check = [&](const StepReport& rep, const Eigen::VectorXd& qs) {
    truss.evaluate(qs, rep.t, false);
    const Eigen::VectorXd& u = truss.displacements();
    const Eigen::VectorXd& r = truss.assembler().full_residual();
    const double w = -2.0 * rep.t, v = apex_displacement(w);
    // Newton converged to 1e-12 of O(0.1) forces, the path stiffness is >= 0.76: 1e-10 on displacements.
    EXPECT_NEAR(u[5], v, 1e-10) << "t = " << rep.t;
    EXPECT_NEAR(u[4], 0.0, 1e-12);           // symmetry
    EXPECT_EQ(u[6], u[4]);                   // MPC u_Dx = u_Cx holds exactly (coefficient 1)
    EXPECT_NEAR(u[7], w, 1e-15);             // prescribed value follows the curve
    // r = f_int - f_ext is the force the support at D supplies: it balances the truss force on the apex.
    EXPECT_NEAR(r[7], -truss_force(v), 1e-10);
    EXPECT_NEAR(r[1] + r[3] + r[7], 0.0, 1e-10);  // no external load: reactions balance
    EXPECT_NEAR(r[0] + r[2], 0.0, 1e-10);
    min_reaction = std::min(min_reaction, r[7]);
    max_reaction = std::max(max_reaction, r[7]);
    return true;
  };
  const ContinuationResult res = LoadStepping(sc, opt).run(truss, q, solver, check);
  ASSERT_TRUE(res.completed()) << res.message;
  EXPECT_DOUBLE_EQ(res.t_reached, 1.0);
  EXPECT_EQ(truss.accepted(), res.steps);
  EXPECT_LT(min_reaction, -0.01);  // the transmitted force changes sign: the path crossed the limit point
  EXPECT_GT(max_reaction, 0.01);
  // One symbolic analysis for the whole run, one factorisation per Newton iteration.
  EXPECT_EQ(solver.analyses, 1);
  EXPECT_EQ(solver.factorize_calls, res.total_iterations);
  EXPECT_EQ(solver.factorizations(), solver.factorize_calls);  // LinearSolver's count (summary.json's)
  // A new pattern (e.g. after contact detection changed the element list) forces a new analysis.
  truss.rebuild_pattern();
  q.setZero();  // start away from equilibrium so Newton has to solve
  ASSERT_TRUE(newton_solve(truss, q, 0.25, opt, solver).converged);
  EXPECT_EQ(solver.analyses, 2);
}

// Single saturating bar under load control: k d tanh(e/d) = F t.
SpringNetwork make_bar(double load) {
  ConstraintSet cs;
  cs.fix(0);
  cs.fix(1);
  cs.fix(3);
  return SpringNetwork({{0, 0}, {1, 0}}, {{0, 1, 1.0, 1.0}}, cs, {{2, load, 0}});
}

TEST(Continuation, CutsBackWhenAStepIsTooLargeAndRecovers) {
  const double load = 0.97;  // near the force limit 1: the tip sits far out on the flat part of tanh
  SpringNetwork bar = make_bar(load);
  auto solver = make_linear_solver("auto", true);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(1);
  StepControl sc;
  sc.dt_initial = 1.0;
  sc.dt_max = 1.0;
  NewtonOptions opt;
  opt.max_iterations = 4;  // a full step from rest needs more
  int cutback_steps = 0, cutbacks = 0;
  double t_last = 0;
  const ContinuationResult res = LoadStepping(sc, opt).run(bar, q, *solver, [&](const StepReport& rep, const Eigen::VectorXd& qs) {
    cutback_steps += rep.cutbacks > 0;
    cutbacks += rep.cutbacks;
    EXPECT_GT(rep.t, t_last);
    t_last = rep.t;
    EXPECT_NEAR(qs[0], std::atanh(load * rep.t), 1e-7);  // converged to 1e-9 * F, tangent >= 0.06
    return true;
  });
  ASSERT_TRUE(res.completed()) << res.message;
  EXPECT_GE(cutback_steps, 1);
  // Every failed attempt tells the system (history-dependent state, e.g. projection branches, goes back).
  EXPECT_EQ(bar.rejected(), cutbacks);
  EXPECT_EQ(res.failed_attempts, cutbacks);  // summary.json's count
  EXPECT_EQ(t_last, 1.0);
  EXPECT_NEAR(q[0], std::atanh(load), 1e-7);
}

TEST(Continuation, StopsCleanlyBelowDtMinBeyondTheLimitLoad) {
  const double load = 1.25;  // equilibrium exists only for t < 1 / 1.25 = 0.8
  SpringNetwork bar = make_bar(load);
  auto solver = make_linear_solver("auto", true);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(1);
  StepControl sc;
  sc.dt_min = 1e-4;
  const ContinuationResult res = LoadStepping(sc, NewtonOptions{}).run(bar, q, *solver, nullptr);
  EXPECT_FALSE(res.completed());
  EXPECT_NE(res.message.find("dt_min"), std::string::npos) << res.message;
  EXPECT_EQ(res.failed_attempts, bar.rejected());  // the attempts that ended the run as well
  EXPECT_GT(res.failed_attempts, 0);
  EXPECT_LT(res.t_reached, 0.8);  // no equilibrium beyond: a hard bound
  EXPECT_GT(res.t_reached, 0.75); // steps of >= 1e-4 approach the limit closely (loose on purpose)
  // q is the last converged state: residual |tanh(q) - F t| below the Newton tolerance 1e-9 * scale
  // (scale <= F). Displacements are not compared: on the flat part of tanh they are ill-conditioned.
  EXPECT_LE(std::abs(std::tanh(q[0]) - load * res.t_reached), 1e-9 * load);
}

TEST(Continuation, StepSizeGrowsToDtMaxAndLandsExactlyOnTEnd) {
  ConstraintSet cs;
  cs.fix(0);
  cs.fix(1);
  cs.fix(3);
  SpringNetwork spring({{0, 0}, {1, 0}}, {{0, 1, 2.0, 0.0}}, cs, {{2, 1.0, 0}});  // linear: 1 iteration
  auto solver = make_linear_solver("cholmod", true);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(1);
  StepControl sc;
  sc.dt_initial = 0.01;
  sc.dt_max = 0.3;
  sc.growth = 2.0;
  std::vector<double> dts, ts;
  const ContinuationResult res = LoadStepping(sc, NewtonOptions{}).run(spring, q, *solver, [&](const StepReport& rep, const Eigen::VectorXd&) {
                                                    dts.push_back(rep.dt);
                                                    ts.push_back(rep.t);
                                                    return true;
                                                  });
  ASSERT_TRUE(res.completed());
  // 0.01, 0.02, 0.04, 0.08, 0.16 (t = 0.31), then 0.3, 0.3 (t = 0.91), then the remainder 0.09.
  const std::vector<double> expected = {0.01, 0.02, 0.04, 0.08, 0.16, 0.3, 0.3, 0.09};
  ASSERT_EQ(dts.size(), expected.size());
  for (size_t i = 0; i < dts.size(); ++i) EXPECT_NEAR(dts[i], expected[i], 1e-12) << i;
  EXPECT_EQ(ts.back(), 1.0);
  EXPECT_NEAR(q[0], 0.5, 1e-12);  // linear spring k = 2 under unit load
}

// Steps of 0.3 to t = 1 on the saturating bar (tanh q = 0.5 t): the last step (0.1, at most 0.34 of the
// planned 0.3) starts with the factorisation of the step before it (StepControl::reuse_in_short_steps) and
// converges with chords alone, to the same state within Newton's tolerance; the full steps are untouched.
TEST(Continuation, AShortStepStartsWithTheLastStepsFactorisation) {
  const auto run = [](double share, std::vector<int>& iterations) {
    SpringNetwork bar = make_bar(0.5);
    CountingSolver solver(make_linear_solver("auto", true));
    Eigen::VectorXd q = Eigen::VectorXd::Zero(1);
    StepControl sc;
    sc.dt_initial = sc.dt_max = 0.3;
    sc.reuse_in_short_steps = share;
    NewtonOptions opt;
    opt.reuse_below = 0.1;
    opt.tol_relative = 1e-12;
    const ContinuationResult res = LoadStepping(sc, opt).run(bar, q, solver, [&](const StepReport& rep, const Eigen::VectorXd&) {
      iterations.push_back(rep.iterations);
      return true;
    });
    EXPECT_TRUE(res.completed()) << res.message;
    EXPECT_NEAR(std::tanh(q[0]), 0.5, 1e-11);
    return solver.factorize_calls;
  };
  std::vector<int> own, reused, all_short;
  const int factorized = run(0.0, own), fewer = run(0.34, reused);
  ASSERT_EQ(own.size(), 4u);
  ASSERT_EQ(reused.size(), 4u);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(reused[i], own[i]) << i;
  EXPECT_LT(fewer, factorized);  // the last step factorises no tangent of its own
  // With every step short (share 1), each step after the first starts with the last one's factorisation.
  EXPECT_LT(run(1.0, all_short), fewer);
}

TEST(Continuation, CallbackCanStopEarly) {
  SpringNetwork bar = make_bar(0.5);
  auto solver = make_linear_solver("auto", true);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(1);
  const ContinuationResult res = LoadStepping(StepControl{}, NewtonOptions{}).run(
      bar, q, *solver, [](const StepReport& rep, const Eigen::VectorXd&) { return rep.step < 3; });
  EXPECT_EQ(res.outcome, Outcome::stopped);
  EXPECT_EQ(res.steps, 3);
  EXPECT_NE(res.message.find("callback"), std::string::npos);
}

TEST(Continuation, SecantPredictorSavesIterations) {
  int iterations[2];
  for (int order : {0, 1}) {
    SpringNetwork truss = make_truss();
    auto solver = make_linear_solver("auto", true);
    Eigen::VectorXd q = Eigen::VectorXd::Zero(truss.size());
    StepControl sc;
    sc.dt_initial = sc.dt_max = 0.05;
    sc.predictor_order = order;
    const ContinuationResult res = LoadStepping(sc, NewtonOptions{}).run(truss, q, *solver, nullptr);
    ASSERT_TRUE(res.completed());
    iterations[order] = res.total_iterations;
  }
  EXPECT_LT(iterations[1], iterations[0]);
}

// Load stepping from t = 0 to 1 on r = q - path(t) (r_t = -path'(t)) with the given predictor order, the
// steps growing from 0.05 to 0.2 (0.05, 0.075, 0.1125, 0.169, 0.2, ...): Newton's iterations in all. The
// end state must be the path's.
int iterations_along(const std::function<Eigen::VectorXd(double)>& path,
                     const std::function<Eigen::VectorXd(double)>& slope, int order) {
  testing::ToySystem system(
      2, [&](const Eigen::VectorXd& q, double t) -> Eigen::VectorXd { return q - path(t); },
      [](const Eigen::VectorXd&, double) -> Eigen::MatrixXd { return Eigen::MatrixXd::Identity(2, 2); },
      [&](const Eigen::VectorXd&, double t) -> Eigen::VectorXd { return -slope(t); });
  auto solver = make_linear_solver("auto", true);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(2);
  StepControl sc;
  sc.dt_initial = 0.05;
  sc.dt_max = 0.2;
  sc.predictor_order = order;
  const ContinuationResult res = LoadStepping(sc, NewtonOptions{}).run(system, q, *solver, nullptr);
  EXPECT_TRUE(res.completed());
  EXPECT_GE(res.steps, 7);
  EXPECT_LT((q - path(1.0)).norm(), 1e-12);
  return res.total_iterations;
}

// r = q - (a t + b t^2): the path is a parabola in t. The quadratic predictor reproduces it exactly from
// the third step on (Newton's first residual is round-off, below the tolerance: no update), also across
// the steps whose size grows; the secant predictor leaves an O(dt^2) residual at every step.
TEST(Continuation, QuadraticPredictorFollowsAParabolicPathExactly) {
  const Eigen::Vector2d a(1.0, -2.0), b(3.0, 0.5);
  auto path = [&](double t) -> Eigen::VectorXd { return a * t + b * t * t; };
  auto slope = [&](double t) -> Eigen::VectorXd { return a + 2 * t * b; };
  EXPECT_EQ(iterations_along(path, slope, 2), 2);  // the first step (no predictor) and the second (secant)
  EXPECT_GT(iterations_along(path, slope, 1), 5);
}

// r = q - (a t + b t^2 + c t^3): the cubic predictor reproduces it exactly from the fourth step on; the
// quadratic predictor leaves an O(dt^3) residual at every step.
TEST(Continuation, CubicPredictorFollowsACubicPathExactly) {
  const Eigen::Vector2d a(1.0, -2.0), b(3.0, 0.5), c(-1.5, 2.0);
  auto path = [&](double t) -> Eigen::VectorXd { return a * t + b * t * t + c * t * t * t; };
  auto slope = [&](double t) -> Eigen::VectorXd { return a + 2 * t * b + 3 * t * t * c; };
  EXPECT_EQ(iterations_along(path, slope, 3), 3);  // no predictor, the secant, the parabola
  EXPECT_GT(iterations_along(path, slope, 2), 5);
}

// A run stopped after three steps and continued by a fresh LoadStepping from save() / restore() takes the
// same steps with the same predictions as the uninterrupted run: the same iterations and the same end state
// to round-off (both compute the same operations; the tolerance allows for a different summation order).
TEST(Continuation, PredictorsContinueAfterARestart) {
  for (int order : {2, 3}) {
    SCOPED_TRACE(order);
    StepControl sc;
    sc.dt_initial = sc.dt_max = 0.1;
    sc.predictor_order = order;
    auto run = [&](bool interrupted) {
      SpringNetwork truss = make_truss();
      auto solver = make_linear_solver("auto", true);
      Eigen::VectorXd q = Eigen::VectorXd::Zero(truss.size());
      LoadStepping first(sc, NewtonOptions{});
      ContinuationResult res = first.run(truss, q, *solver, [&](const StepReport& rep, const Eigen::VectorXd&) {
        return !interrupted || rep.step < 4;
      });
      int iterations = res.total_iterations;
      if (interrupted) {
        EXPECT_EQ(res.outcome, Outcome::stopped);
        LoadStepping second(sc, NewtonOptions{});
        second.restore(first.save());
        res = second.run(truss, q, *solver, nullptr);
        iterations += res.total_iterations;
      }
      EXPECT_TRUE(res.completed());
      return std::make_pair(iterations, Eigen::VectorXd(q));
    };
    const auto [whole_iterations, whole_q] = run(false);
    const auto [resumed_iterations, resumed_q] = run(true);
    EXPECT_EQ(resumed_iterations, whole_iterations);
    EXPECT_LT((resumed_q - whole_q).norm(), 1e-12 * whole_q.norm());
  }
}

TEST(Continuation, InvalidStepControlIsAnInputError) {
  SpringNetwork bar = make_bar(0.5);
  auto solver = make_linear_solver("auto", true);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(1);
  StepControl zero_step;
  zero_step.dt_initial = 0.0;
  EXPECT_THROW(LoadStepping(zero_step, NewtonOptions{}).run(bar, q, *solver, nullptr), InputError);
  StepControl bad_cutback;
  bad_cutback.cutback = 1.0;  // would retry the same failing step forever
  EXPECT_THROW(LoadStepping(bad_cutback, NewtonOptions{}).run(bar, q, *solver, nullptr), InputError);
}

}  // namespace
}  // namespace fibrane::solve
