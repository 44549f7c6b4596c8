// Arc-length continuation on toy systems with analytic equilibrium paths: a scalar fold, the von Mises
// truss (snap-through under load control) and the truss behind a soft spring (snap-back); the toys' load
// derivatives against central differences; restarts; the extended system where K cannot be factorised.
//
// Tolerances. Newton converges to |r| <= 1e-10 (tol_relative = 1e-10 of max(|r_0|, 1), |r_0| < 1 at the
// predictors here). Each toy's path is a graph over one displacement (q, w or w1), so the distance of a
// converged point from the analytic path at its own displacement is |r| times a constant of the toy
// (stated at each check); round-off of the O(1) residual terms adds ~1e-15.
#include <gtest/gtest.h>

#include <cmath>
#include <tuple>
#include <vector>

#include "common/error.hpp"
#include "path/arc_length.hpp"
#include "toy_systems.hpp"

namespace fibrane::solve {
namespace {

using testing::dense_negative_eigenvalues;
using testing::InertiaSolver;
using testing::PathPoint;
using testing::ToySystem;
using testing::Truss;

constexpr double kTol = 1e-10;

NewtonOptions tight_newton() {
  NewtonOptions opt;
  opt.tol_relative = kTol;
  opt.tol_absolute = 1e-14;
  return opt;
}

// Vertex (x, y) of the parabola through three points: the located extremum of y(x).
std::pair<double, double> parabola_vertex(double x0, double y0, double x1, double y1, double x2, double y2) {
  // Newton form y = y0 + d01 (x - x0) + a (x - x0) (x - x1); y' = 0 at x = (x0 + x1) / 2 - d01 / (2 a).
  const double d01 = (y1 - y0) / (x1 - x0), d12 = (y2 - y1) / (x2 - x1), a = (d12 - d01) / (x2 - x0);
  const double x = 0.5 * (x0 + x1) - d01 / (2 * a);
  return {x, y0 + d01 * (x - x0) + a * (x - x0) * (x - x1)};
}

TEST(ArcLength, ScalarFoldIsTracedPastTheLimitPointAndBackToZeroLoad) {
  struct Variant {
    ArcLengthCorrector corrector;
    double load_scale;
  };
  for (const Variant v : {Variant{ArcLengthCorrector::quadratic, -1.0}, Variant{ArcLengthCorrector::linearized, -1.0},
                          Variant{ArcLengthCorrector::quadratic, 0.0}}) {
    SCOPED_TRACE(::testing::Message() << "corrector " << static_cast<int>(v.corrector) << ", c " << v.load_scale);
    ToySystem fold = testing::make_fold();
    auto solver = make_linear_solver("auto", true);
    ArcLengthControl ac;
    ac.t_end = 0.0;  // the start (t = 0) does not count: the run ends where the path comes back to t = 0
    ac.ds_initial = 0.1;
    ac.ds_max = 0.2;
    ac.load_scale = v.load_scale;
    ac.max_steps = 200;
    ArcLength method(ac, tight_newton());
    std::vector<PathPoint> path;
    const ContinuationResult res = testing::trace(method, fold, Eigen::VectorXd::Zero(1), *solver, path);
    ASSERT_EQ(res.outcome, Outcome::reached_end) << res.message;
    int limits = 0;
    double q_last = 0, t_peak = 0;
    for (const PathPoint& p : path) {
      const double q = p.q[0], t = p.report.t;
      // The path t = f(q) is a graph over q: |t - f(q)| = |r| <= 1e-10.
      EXPECT_LE(std::abs(t - testing::fold_f(q)), kTol + 1e-15) << "step " << p.report.step;
      EXPECT_GT(q, q_last) << "the path turned back at step " << p.report.step;
      // t rises while f' = 1 - q^2 > 0 and falls after (steps next to the limit point excepted).
      if (std::abs(q - 1) > 0.3) {
        EXPECT_EQ(p.report.dt > 0, q < 1) << "step " << p.report.step;
      }
      limits += p.report.limit_point;
      t_peak = std::max(t_peak, t);
      q_last = q;
    }
    EXPECT_EQ(limits, 1);
    // The highest converged point is within the parabola's reach of the limit load 2/3: steps of ds <= 0.2,
    // so |q - 1| <= 0.1 for the nearest point and f(1) - f(q) = (q - 1)^2 (1 + (q - 1) / 3) <= 0.011.
    EXPECT_LE(t_peak, 2.0 / 3.0);
    EXPECT_GT(t_peak, 2.0 / 3.0 - 0.011);
    // Landed exactly on t_end = 0 on the falling branch, at q = sqrt(3) (|q error| = |r| / |f'| = |r| / 2).
    EXPECT_EQ(path.back().report.t, 0.0);
    EXPECT_NEAR(path.back().q[0], std::sqrt(3.0), kTol);
    EXPECT_EQ(fold.accepted(), res.steps);
  }
}

// Indices i (> 1) where y[i] - y[i-1] and y[i-1] - y[i-2] differ in sign: an extremum of y lies near y[i-1].
std::vector<size_t> reversals(const std::vector<double>& y) {
  std::vector<size_t> at;
  for (size_t i = 2; i < y.size(); ++i)
    if ((y[i] - y[i - 1]) * (y[i - 1] - y[i - 2]) < 0) at.push_back(i);
  return at;
}

// Tolerances of located extrema. The parabola through three converged points h apart misses the vertex
// of y(x) by O(h^3 |y'''| / 6) in the value and O(h^2 |y'''| / |y''|) in the position; here h <= ds_max =
// 0.05 and |y'''| / 6, |y'''| / |y''| are O(1): 1e-4 and 3e-3 (measured at most 1e-5 and 2.4e-4). The
// highest converged point alone would miss the limit load by up to |y''| h^2 / 8 ~ 3e-4.
constexpr double kExtremumValueTol = 1e-4, kExtremumPositionTol = 3e-3;

// The von Mises truss under the dead load t (P = 1): path t = U'(w), a graph over w; U'' < 0 (one negative
// eigenvalue, det K < 0) exactly between the limit points w = h -+ z*. `reported`: the solver's count in
// the reports must be there and match the dense one (otherwise it is checked only where the solver reports
// it, i.e. >= 0).
void check_truss_path(const Truss& truss, const ToySystem& sys, const std::vector<PathPoint>& path, bool reported) {
  ASSERT_GE(path.size(), 3u);
  std::vector<double> w = {0.0}, t = {0.0};
  int prev_negative = 0, unstable = 0;
  for (const PathPoint& p : path) {
    const double wi = p.q[0], ti = p.report.t;
    EXPECT_LE(std::abs(ti - truss.force(wi)), kTol + 1e-15) << "step " << p.report.step;  // |t - U'(w)| = |r|
    EXPECT_GT(wi, w.back()) << "the path turned back at step " << p.report.step;
    const int negative = dense_negative_eigenvalues(sys.dense_tangent_at(p.q, ti));
    EXPECT_EQ(negative, truss.stiffness(wi) < 0 ? 1 : 0);
    // Between two states of the same stability t rises on the stable and falls on the unstable branch.
    if (negative == prev_negative) {
      EXPECT_EQ(p.report.dt < 0, negative == 1) << "step " << p.report.step;
    }
    if (reported || p.report.negative_eigenvalues >= 0) {
      EXPECT_EQ(p.report.negative_eigenvalues, negative);
    }
    unstable += negative;
    prev_negative = negative;
    w.push_back(wi);
    t.push_back(ti);
  }
  EXPECT_GT(unstable, 5);
  // Limit loads: t = U'(w) at U''(w) = 0, +-0.265021 at w = 1 -+ 0.509830 for h = k = 1.
  const std::vector<size_t> limits = reversals(t);
  ASSERT_EQ(limits.size(), 2u);
  const auto [w_max, w_min] = truss.where_stiffness(0.0);
  const double analytic_w[2] = {w_max, w_min};
  for (int j = 0; j < 2; ++j) {
    const size_t i = limits[static_cast<size_t>(j)];
    EXPECT_TRUE(path[i - 1].report.limit_point) << "the report flags the step after the extremum";
    const auto [wv, tv] = parabola_vertex(w[i - 2], t[i - 2], w[i - 1], t[i - 1], w[i], t[i]);
    EXPECT_NEAR(tv, truss.force(analytic_w[j]), kExtremumValueTol);
    EXPECT_NEAR(wv, analytic_w[j], kExtremumPositionTol);
  }
  int flagged = 0;
  for (const PathPoint& p : path) flagged += p.report.limit_point;
  EXPECT_EQ(flagged, 2);
}

ArcLengthControl truss_control() {
  ArcLengthControl ac;
  ac.t_end = 0.5;  // above the upper limit load: reached on the third, stable branch (w > 2)
  ac.ds_max = 0.05;
  ac.max_steps = 1000;
  return ac;
}

TEST(ArcLength, VonMisesTrussSnapsThroughUnderLoadControl) {
  const Truss truss;
  ToySystem sys = testing::make_truss(truss, 1.0);
  // CHOLMOD LL^T, LDL^T on the unstable branch. Its negative_eigenvalues() may report -1 (not known):
  // the reports are then checked only where they give a count; the dense eigen-decomposition is checked
  // everywhere.
  auto solver = make_linear_solver("auto", true);
  ArcLength method(truss_control(), tight_newton());
  std::vector<PathPoint> path;
  const ContinuationResult res = testing::trace(method, sys, Eigen::VectorXd::Zero(1), *solver, path);
  ASSERT_EQ(res.outcome, Outcome::reached_end) << res.message;
  check_truss_path(truss, sys, path, false);
  EXPECT_EQ(path.back().report.t, 0.5);
  EXPECT_NEAR(truss.force(path.back().q[0]), 0.5, kTol);
  EXPECT_GT(path.back().q[0], 2.0);
  EXPECT_EQ(method.load_scale(), 1.0);  // |dw/dt| = 1 / U''(0) = 1
}

TEST(ArcLength, DeterminantRuleAloneTracesTheSnapThrough) {
  const Truss truss;
  ToySystem sys = testing::make_truss(truss, 1.0);
  InertiaSolver solver(make_linear_solver("auto", true));
  ArcLengthControl ac = truss_control();
  ac.ambiguous_cosine = 1.0;  // the determinant rule decides every direction
  ArcLength method(ac, tight_newton());
  std::vector<PathPoint> path;
  const ContinuationResult res = testing::trace(method, sys, Eigen::VectorXd::Zero(1), solver, path);
  ASSERT_EQ(res.outcome, Outcome::reached_end) << res.message;
  check_truss_path(truss, sys, path, true);
  EXPECT_EQ(method.sign_disagreements(), 0);  // the angle rule would have chosen the same directions
}

// A solver reporting no negative eigenvalue at all misleads the determinant rule: at the first limit point
// it keeps t rising, so the path turns back towards the stable branch. (Shows the rule is really in charge.)
class NoInertiaSolver : public InertiaSolver {
 public:
  using InertiaSolver::InertiaSolver;
  int negative_eigenvalues() const override { return 0; }
};

TEST(ArcLength, WrongInertiaMisleadsTheDeterminantRule) {
  ToySystem sys = testing::make_truss(Truss{}, 1.0);
  NoInertiaSolver solver(make_linear_solver("auto", true));
  ArcLengthControl ac = truss_control();
  ac.ambiguous_cosine = 1.0;
  ac.max_steps = 40;
  ArcLength method(ac, tight_newton());
  std::vector<PathPoint> path;
  testing::trace(method, sys, Eigen::VectorXd::Zero(1), solver, path);
  int turned_back = 0;  // steps with w decreasing (it swings back and forth across the limit point)
  for (size_t i = 1; i < path.size(); ++i) turned_back += path[i].q[0] < path[i - 1].q[0];
  EXPECT_GT(turned_back, 0);
  EXPECT_GT(method.sign_disagreements(), 0);
}

// Crisfield's snap-back example: the truss (h = k = 1) behind a spring k_s = 0.5 < 2 (L0 - 1) = 0.83, dead
// load t at the spring's top. See make_truss_with_spring for the analytic path, parametrised by w1.
void check_snap_back(const ArcLengthControl& ac) {
  const Truss truss;
  const double spring = 0.5;
  ToySystem sys = testing::make_truss_with_spring(truss, spring, 1.0);
  InertiaSolver solver(make_linear_solver("auto", true));
  ArcLength method(ac, tight_newton());
  std::vector<PathPoint> path;
  const ContinuationResult res = testing::trace(method, sys, Eigen::VectorXd::Zero(2), solver, path);
  ASSERT_EQ(res.outcome, Outcome::reached_end) << res.message;
  std::vector<double> w1 = {0.0}, w2 = {0.0}, t = {0.0};
  int prev_negative = 0, flagged = 0;
  for (const PathPoint& p : path) {
    const double a = p.q[0], b = p.q[1], ti = p.report.t;
    // At the converged w1: t - U'(w1) = -(r1 + r2) and w2 - w2(w1) = -r1 / k_s, so |r| <= 1e-10 bounds
    // them by 1.5e-10 and 2e-10.
    EXPECT_LE(std::abs(ti - truss.force(a)), 1.5e-10) << "step " << p.report.step;
    EXPECT_LE(std::abs(b - a - truss.force(a) / spring), 2e-10) << "step " << p.report.step;
    EXPECT_GT(a, w1.back()) << "the path turned back at step " << p.report.step;
    const int negative = dense_negative_eigenvalues(sys.dense_tangent_at(p.q, ti));
    EXPECT_EQ(negative, truss.stiffness(a) < 0 ? 1 : 0);  // det K = k_s U''(w1)
    EXPECT_EQ(p.report.negative_eigenvalues, negative);
    if (negative == prev_negative) {
      EXPECT_EQ(p.report.dt < 0, negative == 1) << "step " << p.report.step;
    }
    prev_negative = negative;
    flagged += p.report.limit_point;
    w1.push_back(a);
    w2.push_back(b);
    t.push_back(ti);
  }
  EXPECT_EQ(flagged, 2);
  // Both limit points of t (U'' = 0) and both turning points of w2 (U'' = -k_s) are passed and located.
  const std::vector<size_t> t_turns = reversals(t), w2_turns = reversals(w2);
  ASSERT_EQ(t_turns.size(), 2u);
  ASSERT_EQ(w2_turns.size(), 2u);
  const auto [t_max_at, t_min_at] = truss.where_stiffness(0.0);
  const auto [w2_max_at, w2_min_at] = truss.where_stiffness(-spring);
  const double t_at[2] = {t_max_at, t_min_at}, w2_at[2] = {w2_max_at, w2_min_at};
  for (int j = 0; j < 2; ++j) {
    size_t i = t_turns[static_cast<size_t>(j)];
    auto [x, y] = parabola_vertex(w1[i - 2], t[i - 2], w1[i - 1], t[i - 1], w1[i], t[i]);
    EXPECT_NEAR(y, truss.force(t_at[j]), kExtremumValueTol) << "limit point of t " << j;
    EXPECT_NEAR(x, t_at[j], kExtremumPositionTol) << "limit point of t " << j;
    i = w2_turns[static_cast<size_t>(j)];
    std::tie(x, y) = parabola_vertex(w1[i - 2], w2[i - 2], w1[i - 1], w2[i - 1], w1[i], w2[i]);
    EXPECT_NEAR(y, w2_at[j] + truss.force(w2_at[j]) / spring, kExtremumValueTol) << "turning point of w2 " << j;
    EXPECT_NEAR(x, w2_at[j], kExtremumPositionTol) << "turning point of w2 " << j;
  }
  EXPECT_EQ(t.back(), 0.5);
  EXPECT_EQ(method.sign_disagreements(), 0);
}

TEST(ArcLength, TrussBehindASoftSpringSnapsBack) {
  struct Variant {
    ArcLengthCorrector corrector;
    double load_scale;
  };
  for (const Variant v : {Variant{ArcLengthCorrector::quadratic, -1.0}, Variant{ArcLengthCorrector::linearized, -1.0},
                          Variant{ArcLengthCorrector::quadratic, 0.0}}) {
    SCOPED_TRACE(::testing::Message() << "corrector " << static_cast<int>(v.corrector) << ", c " << v.load_scale);
    ArcLengthControl ac = truss_control();
    ac.corrector = v.corrector;
    ac.load_scale = v.load_scale;
    check_snap_back(ac);
  }
}

TEST(ArcLength, RefusedFactorisationsGoThroughTheExtendedSystem) {
  ToySystem fold = testing::make_fold();
  testing::RefusingSolver solver;
  ArcLengthControl ac;
  ac.t_end = 0.0;
  ac.ds_max = 0.2;
  ac.max_steps = 200;
  ArcLength method(ac, tight_newton());
  std::vector<PathPoint> path;
  const ContinuationResult res = testing::trace(method, fold, Eigen::VectorXd::Zero(1), solver, path);
  ASSERT_EQ(res.outcome, Outcome::reached_end) << res.message;
  EXPECT_GT(solver.refusals, res.steps);
  for (const PathPoint& p : path) {
    EXPECT_LE(std::abs(p.report.t - testing::fold_f(p.q[0])), kTol + 1e-15) << "step " << p.report.step;
    EXPECT_EQ(p.report.negative_eigenvalues, -1);
  }
  EXPECT_NEAR(path.back().q[0], std::sqrt(3.0), kTol);
}

TEST(ArcLength, StartsFromAnExactLimitPointWithTheBorderedTangent) {
  // The state at the limit point q = 1, t = 2/3 (f'(1) = 0: K singular), arrived at from q = 0.9.
  ArcLength method(ArcLengthControl{}, tight_newton());
  method.restore({{"t", {2.0 / 3.0}}, {"ds", {0.1}}, {"load_scale", {1.0}}, {"path_length", {1.0}},
                  {"steps", {7}}, {"have_prev", {1}}, {"dq_prev", {0.1}},
                  {"dt_prev", {2.0 / 3.0 - testing::fold_f(0.9)}},
                  {"tangent_dt_sign", {1}}, {"negative_eigenvalues", {0}}});
  ToySystem fold = testing::make_fold();
  auto solver = make_linear_solver("auto", true);
  std::vector<PathPoint> path;
  Eigen::VectorXd q = Eigen::VectorXd::Ones(1);
  method.run(fold, q, *solver, [&](const StepReport& rep, const Eigen::VectorXd& qs) {
    path.push_back({rep, qs});
    return rep.step < 10;
  });
  ASSERT_EQ(path.size(), 3u);
  EXPECT_EQ(path[0].report.step, 8);
  EXPECT_TRUE(path[0].report.limit_point);
  for (const PathPoint& p : path) {
    EXPECT_GT(p.q[0], 1.0);  // forward along the last increment, onto the falling branch
    EXPECT_LT(p.report.dt, 0.0);
    EXPECT_LE(std::abs(p.report.t - testing::fold_f(p.q[0])), kTol + 1e-15);
  }
}

}  // namespace
}  // namespace fibrane::solve
