// Event location in load stepping (StepControl::event_tolerance, path/event_locator.hpp): a model that
// changes after the converged step at which an event's margin is <= 0 first changes within the tolerance
// of the margin's crossing, whatever the steps; without location it changes where the steps fall.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "path/load_stepping.hpp"

namespace fibrane::solve {
namespace {

// q = t until a converged state where g = 0.5 - q - q^2 <= 0 (q >= (sqrt 3 - 1) / 2 at the crossing);
// from that state (q_s) on, 2 q - t - q_s = 0, continuous there: q(1) = (1 + q_s) / 2 depends on where the
// switch happens, as a soft-minimum point's later path depends on the state it switched at. A second
// event, g = 0.8 - q, changes nothing and crosses later; both end NaN once they have happened.
class SwitchingLine final : public NonlinearSystem {
 public:
  SwitchingLine() : r_(1), k_(1, 1) { k_.insert(0, 0) = 1.0; }
  int size() const override { return 1; }
  void evaluate(const Eigen::VectorXd& q, double t, bool) override {
    q_ = q[0];
    r_[0] = switched_ ? 2 * q_ - t - q_switch_ : q_ - t;
    k_.coeffRef(0, 0) = switched_ ? 2.0 : 1.0;
  }
  const Eigen::VectorXd& residual() const override { return r_; }
  const Eigen::SparseMatrix<double>& tangent() const override { return k_; }
  int pattern_version() const override { return 0; }
  std::vector<double> event_margins() const override {
    return {switched_ ? NAN : 0.5 - q_ - q_ * q_, second_ ? NAN : 0.8 - q_};
  }
  void accept(const Eigen::VectorXd& q, double) override {
    const std::vector<double> g = event_margins();
    if (g[0] <= 0) switched_ = true, q_switch_ = q[0];
    if (g[1] <= 0) second_ = true, q_second_ = q[0];
  }
  void withdraw() override { ++withdrawn; }
  double q_switch() const { return q_switch_; }
  double q_second() const { return q_second_; }
  int withdrawn = 0;

 private:
  double q_ = 0, q_switch_ = NAN, q_second_ = NAN;
  bool switched_ = false, second_ = false;
  Eigen::VectorXd r_;
  Eigen::SparseMatrix<double> k_;
};

const double kCrossing = 0.5 * (std::sqrt(3.0) - 1.0);

struct LineRun {
  ContinuationResult result;
  double q_end, q_switch, q_second;
  int withdrawn;
};

// A run to t = 1 with steps of up to dt_max; stopped after `stop_after` steps and continued by a fresh
// LoadStepping from save() / restore() where that is > 0.
LineRun run(double dt_max, double tolerance, int stop_after = 0, bool drop_event_keys = false) {
  StepControl sc;
  sc.dt_initial = sc.dt_max = dt_max;
  sc.event_tolerance = tolerance;
  SwitchingLine line;
  auto solver = make_linear_solver("auto", true);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(1);
  LoadStepping first(sc, NewtonOptions{});
  ContinuationResult res = first.run(line, q, *solver, [&](const StepReport& rep, const Eigen::VectorXd&) {
    return stop_after == 0 || rep.step < stop_after;
  });
  if (stop_after > 0 && res.outcome == Outcome::stopped) {
    const int withdrawn = res.withdrawn_attempts, iterations = res.total_iterations;
    LoadStepping second(sc, NewtonOptions{});
    MethodState saved = first.save();
    if (drop_event_keys) {
      for (const char* key : {"events_t", "events_last", "events_before", "events_far"}) EXPECT_EQ(saved.erase(key), 1u);
    }
    second.restore(saved);
    res = second.run(line, q, *solver, nullptr);
    res.withdrawn_attempts += withdrawn;
    res.total_iterations += iterations;
  }
  EXPECT_TRUE(res.completed()) << res.message;
  return {res, q[0], line.q_switch(), line.q_second(), line.withdrawn};
}

// With a tolerance the switch happens at the first converged state past the crossing, at most one
// tolerance past it (the crossing step is at most that long), for steps of 0.03 to 0.3; the event is
// located, withdrawn attempts are counted, and q(1) follows ((1 + q_s) / 2 on this line).
TEST(EventLocation, TheSwitchHappensWithinTheToleranceWhateverTheSteps) {
  constexpr double tol = 1e-3;
  for (double dt_max : {0.03, 0.07, 0.1, 0.3}) {
    SCOPED_TRACE(dt_max);
    const LineRun r = run(dt_max, tol);
    EXPECT_GE(r.q_switch, kCrossing);
    EXPECT_LE(r.q_switch, kCrossing + tol);
    // The second event on the switched line 2 q = t + q_s: g = 0.8 - q crosses at t = 1.6 - q_s, after
    // t = 1, so it does not happen.
    EXPECT_TRUE(std::isnan(r.q_second));
    EXPECT_NEAR(r.q_end, 0.5 * (1 + r.q_switch), 1e-9);  // Newton's tolerance
    EXPECT_EQ(r.withdrawn, r.result.withdrawn_attempts);
    EXPECT_EQ(r.result.failed_attempts, 0);
  }
}

// Without location the switch state is the first step end past the crossing: up to a whole step late.
// The test would pass with location as well only if the steps happened to end near the crossing; with
// these steps they end 0.034 and 0.134 past it.
TEST(EventLocation, WithoutToleranceTheSwitchFollowsTheSteps) {
  EXPECT_NEAR(run(0.1, 0).q_switch - kCrossing, 0.4 - kCrossing, 1e-12);
  EXPECT_NEAR(run(0.25, 0).q_switch - kCrossing, 0.5 - kCrossing, 1e-12);
  EXPECT_EQ(run(0.25, 0).result.withdrawn_attempts, 0);
}

// Two events on the line q = t, which does not change: margins g_a(q) and g_b(q), each NaN once it has
// happened (at the first accepted state where it is <= 0). Records the q of each event and every accepted t.
class TwoEventsOnALine final : public NonlinearSystem {
 public:
  TwoEventsOnALine(std::function<double(double)> a, std::function<double(double)> b)
      : g_{std::move(a), std::move(b)}, r_(1), k_(1, 1) {
    k_.insert(0, 0) = 1.0;
  }
  int size() const override { return 1; }
  void evaluate(const Eigen::VectorXd& q, double t, bool) override { q_ = q[0], r_[0] = q_ - t; }
  const Eigen::VectorXd& residual() const override { return r_; }
  const Eigen::SparseMatrix<double>& tangent() const override { return k_; }
  int pattern_version() const override { return 0; }
  std::vector<double> event_margins() const override {
    return {std::isnan(qa) ? g_[0](q_) : NAN, std::isnan(qb) ? g_[1](q_) : NAN};
  }
  void accept(const Eigen::VectorXd& q, double t) override {
    accepted.push_back(t);
    if (std::isnan(qa) && g_[0](q[0]) <= 0) qa = q[0];
    if (std::isnan(qb) && g_[1](q[0]) <= 0) qb = q[0];
  }
  double qa = NAN, qb = NAN;
  std::vector<double> accepted;

 private:
  std::function<double(double)> g_[2];
  double q_ = 0;
  Eigen::VectorXd r_;
  Eigen::SparseMatrix<double> k_;
};

// A run of `line` to t = 1 with steps of up to dt_max and a tolerance of 1e-3.
ContinuationResult run_located(TwoEventsOnALine& line, double dt_max) {
  StepControl sc;
  sc.dt_initial = sc.dt_max = dt_max;
  sc.event_tolerance = 1e-3;
  auto solver = make_linear_solver("auto", true);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(1);
  return LoadStepping(sc, NewtonOptions{}).run(line, q, *solver, nullptr);
}

// g_a = 0.35 - q^2 and g_b = 0.8 - q. Each is located on its own, from its own margins: the earlier one's
// location does not hide the later one.
TEST(EventLocation, EachEventIsLocatedOnItsOwn) {
  for (double dt_max : {0.05, 0.15}) {
    SCOPED_TRACE(dt_max);
    TwoEventsOnALine two([](double q) { return 0.35 - q * q; }, [](double q) { return 0.8 - q; });
    EXPECT_TRUE(run_located(two, dt_max).completed());
    EXPECT_GE(two.qa, std::sqrt(0.35));
    EXPECT_LE(two.qa, std::sqrt(0.35) + 1e-3);
    EXPECT_GE(two.qb, 0.8);
    EXPECT_LE(two.qb, 0.8 + 1e-3);
  }
}

// Two events that one withdrawn attempt crosses together: g_a = 0.3 - q^2 and g_b = 0.32 - q^2 (crossings
// at 0.5477 and 0.5657). With steps of 0.15 the linear estimate from t = 0.3 and 0.45 puts a at 0.58, so
// the attempt to 0.5735 crosses both and bounds the bracket. Once a has happened (its margin NaN), the
// bracket's far end still holds its old negative margin; it must not bisect toward it as if a were still
// to come (that put a step at 0.560 before b's landing). Each event still happens within the tolerance of
// its crossing; between the two switches lie only the first step on the changed model (one tolerance
// long) and b's landing, and after b's switch one such step and the planned one.
TEST(EventLocation, AnEventThatHappenedNoLongerBoundsTheBracket) {
  TwoEventsOnALine two([](double q) { return 0.3 - q * q; }, [](double q) { return 0.32 - q * q; });
  const ContinuationResult res = run_located(two, 0.15);
  ASSERT_TRUE(res.completed()) << res.message;
  EXPECT_GE(res.withdrawn_attempts, 1);
  EXPECT_GE(two.qa, std::sqrt(0.3));
  EXPECT_LE(two.qa, std::sqrt(0.3) + 1e-3);
  EXPECT_GE(two.qb, std::sqrt(0.32));
  EXPECT_LE(two.qb, std::sqrt(0.32) + 1e-3);
  std::string steps;
  int between = 0;
  double after_b = NAN, next = NAN;
  for (double t : two.accepted) {
    steps += std::to_string(t) + " ";
    if (t > two.qa && t < two.qb) ++between;
    if (t > after_b && std::isnan(next)) next = t;
    if (t > two.qb && std::isnan(after_b)) after_b = t;
  }
  EXPECT_EQ(between, 2) << "accepted steps: " << steps;  // the first step after a's switch, b's landing
  EXPECT_NEAR(after_b - two.qb, 1e-3, 1e-12) << "accepted steps: " << steps;  // the first after b's switch
  EXPECT_NEAR(next - after_b, 0.15, 1e-12) << "accepted steps: " << steps;
}

// Stopped after any step and continued from the saved state (inside a bracket after a withdrawn attempt
// too), the run switches at the same state and ends at the same q with the same Newton iterations as the
// uninterrupted one.
TEST(EventLocation, ContinuesAfterARestartAtAnyStep) {
  const LineRun whole = run(0.1, 1e-3);
  ASSERT_GT(whole.result.withdrawn_attempts, 0);
  for (int stop = 1; stop < whole.result.steps; ++stop) {
    SCOPED_TRACE(stop);
    const LineRun resumed = run(0.1, 1e-3, stop);
    EXPECT_EQ(resumed.q_switch, whole.q_switch);
    EXPECT_EQ(resumed.q_end, whole.q_end);
    EXPECT_EQ(resumed.result.total_iterations, whole.result.total_iterations);
    EXPECT_EQ(resumed.result.withdrawn_attempts, whole.result.withdrawn_attempts);
  }
}

// A checkpoint without the locator's keys (written before they existed) continues from its t with nothing
// known: it still ends, and the switch still happens within the tolerance of the crossing.
TEST(EventLocation, ContinuesFromACheckpointWithoutItsKeys) {
  const LineRun whole = run(0.1, 1e-3);
  for (int stop = 1; stop < whole.result.steps; ++stop) {
    SCOPED_TRACE(stop);
    const LineRun resumed = run(0.1, 1e-3, stop, true);
    EXPECT_GE(resumed.q_switch, kCrossing);
    EXPECT_LE(resumed.q_switch, kCrossing + 1e-3);
    EXPECT_NEAR(resumed.q_end, 0.5 * (1 + resumed.q_switch), 1e-9);
  }
}

// On the path q = t^2 the parabola predictor is exact. After the short steps that locate the event
// 0.09 - q <= 0 (at t = 0.3), a step longer than twice the span of the last two leaves the oldest state
// out and predicts by the secant, whose residual at the predicted state is exactly (t2 - t0)(t2 - t1)
// (t0 < t1 the last two states); every other step starts at round-off.
TEST(EventLocation, AParabolaLeavesOutStatesBunchedAgainstTheStep) {
  class Parabola final : public NonlinearSystem {
   public:
    Parabola() : r_(1), k_(1, 1) { k_.insert(0, 0) = 1.0; }
    int size() const override { return 1; }
    void evaluate(const Eigen::VectorXd& q, double t, bool) override { q_ = q[0], r_[0] = q_ - t * t; }
    const Eigen::VectorXd& residual() const override { return r_; }
    const Eigen::SparseMatrix<double>& tangent() const override { return k_; }
    int pattern_version() const override { return 0; }
    std::vector<double> event_margins() const override { return {0.09 - q_}; }

   private:
    double q_ = 0;
    Eigen::VectorXd r_;
    Eigen::SparseMatrix<double> k_;
  } path;
  StepControl sc;
  sc.dt_initial = sc.dt_max = 0.1;
  sc.predictor_order = 2;
  sc.event_tolerance = 1e-3;
  NewtonOptions newton;
  newton.tol_absolute = 1e-14;
  auto solver = make_linear_solver("auto", true);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(1);
  std::vector<double> t{0.0}, predicted{0.0};
  const auto res = LoadStepping(sc, newton).run(path, q, *solver, [&](const StepReport& rep, const Eigen::VectorXd&) {
    t.push_back(rep.t);
    predicted.push_back(rep.history.front());
    return true;
  });
  ASSERT_TRUE(res.completed()) << res.message;
  int secant_steps = 0;
  for (std::size_t k = 3; k < t.size(); ++k) {
    SCOPED_TRACE(t[k]);
    if (t[k - 1] - t[k - 3] < 0.5 * (t[k] - t[k - 1])) {
      ++secant_steps;
      EXPECT_NEAR(predicted[k], (t[k] - t[k - 2]) * (t[k] - t[k - 1]), 1e-12);
    } else {
      EXPECT_LT(predicted[k], 1e-12);
    }
  }
  EXPECT_GE(secant_steps, 1);
}

// On q = t^2 the model changes once g = 0.09 - q <= 0 (t = 0.3) to q = t^2 + J: the path jumps by J there.
// With the event located, the first step on the changed model is one tolerance long, and the states before
// the change are moved by its Newton correction: J plus that step's own prediction error e. The next step
// (0.1, longer than twice the last two states' span) predicts by the secant through a moved state and the
// new one, and starts at its error on t^2 plus e times the moved state's weight; the one after it, by the
// parabola, at e times that state's weight; the steps start at round-off once the moved states have left
// the predictor. Without location the parabola keeps the states as they are: the second step after the
// change (steps of 0.1) starts at 2 J, the jump times its weight 3 at t = 0.5 less the jump.
TEST(EventLocation, APredictorMovesThePastStatesAcrossALocatedChange) {
  constexpr double J = 0.05;
  class JumpingParabola final : public NonlinearSystem {
   public:
    JumpingParabola() : r_(1), k_(1, 1) { k_.insert(0, 0) = 1.0; }
    int size() const override { return 1; }
    void evaluate(const Eigen::VectorXd& q, double t, bool) override {
      q_ = q[0], r_[0] = q_ - t * t - (switched_ ? J : 0.0);
    }
    const Eigen::VectorXd& residual() const override { return r_; }
    const Eigen::SparseMatrix<double>& tangent() const override { return k_; }
    int pattern_version() const override { return 0; }
    std::vector<double> event_margins() const override { return {switched_ ? NAN : 0.09 - q_}; }
    long model_changes() const override { return switched_ ? 1 : 0; }
    void accept(const Eigen::VectorXd& q, double t) override {
      if (!switched_ && 0.09 - q[0] <= 0) switched_ = true, t_switch = t;
    }
    double t_switch = NAN;

   private:
    double q_ = 0;
    bool switched_ = false;
    Eigen::VectorXd r_;
    Eigen::SparseMatrix<double> k_;
  };
  // The steps' t and |r| at the predicted state; stopped after `stop_after` steps (> 0) and continued by a
  // fresh LoadStepping from save() / restore().
  auto steps = [](double tolerance, JumpingParabola& path, int stop_after = 0) {
    StepControl sc;
    sc.dt_initial = sc.dt_max = 0.1;
    sc.predictor_order = 2;
    sc.event_tolerance = tolerance;
    NewtonOptions newton;
    newton.tol_absolute = 1e-14;
    auto solver = make_linear_solver("auto", true);
    Eigen::VectorXd q = Eigen::VectorXd::Zero(1);
    std::vector<std::pair<double, double>> t_and_r{{0.0, 0.0}};
    auto record = [&](const StepReport& rep, const Eigen::VectorXd&) {
      t_and_r.emplace_back(rep.t, rep.history.front());
      return stop_after == 0 || rep.step < stop_after;
    };
    LoadStepping first(sc, newton);
    auto res = first.run(path, q, *solver, record);
    if (res.outcome == Outcome::stopped) {
      stop_after = 0;
      LoadStepping second(sc, newton);
      second.restore(first.save());
      res = second.run(path, q, *solver, record);
    }
    EXPECT_TRUE(res.completed()) << res.message;
    EXPECT_NEAR(q[0], 1.0 + J, 1e-12);
    return t_and_r;
  };
  JumpingParabola located;
  const auto s = steps(1e-3, located);
  std::size_t after = 0;  // the first step after the change
  while (after < s.size() && !(s[after].first > located.t_switch)) ++after;
  ASSERT_LT(after + 3, s.size());
  // The first step past the change, one tolerance long: the old path's prediction misses the jump J and
  // its own error e on t^2.
  const double t1 = s[after - 1].first, t2 = s[after].first, t = s[after + 1].first, t3 = s[after + 2].first;
  EXPECT_NEAR(t2 - t1, 1e-3, 1e-12);
  const double e = s[after].second - J;
  EXPECT_GT(e, 0.0);
  EXPECT_LT(e, 1e-3 * J);
  // The next step's secant through the moved state at t1 (on t^2 + J + e) and the new one at t2 (on
  // t^2 + J): its error on t^2, (t - t1)(t - t2), plus e times the moved state's weight (t - t2) / (t2 - t1).
  ASSERT_GT(t - t2, 2 * (t2 - t1));
  EXPECT_NEAR(s[after + 1].second, (t - t1) * (t - t2) + e * (t - t2) / (t2 - t1), 1e-12);
  // The parabola through t1, t2 and t is exact on t^2: e times the moved state's weight at t3.
  EXPECT_NEAR(s[after + 2].second, e * std::abs((t3 - t2) * (t3 - t) / ((t1 - t2) * (t1 - t))), 1e-12);
  for (std::size_t k = after + 3; k < s.size(); ++k) {  // no moved state left in the parabola
    SCOPED_TRACE(s[k].first);
    EXPECT_LT(s[k].second, 1e-12);
  }
  // Stopped after any step and continued from the saved state, the same steps with the same residuals.
  for (int stop = 1; stop + 1 < static_cast<int>(s.size()); ++stop) {
    SCOPED_TRACE(stop);
    JumpingParabola resumed;
    EXPECT_EQ(steps(1e-3, resumed, stop), s);
  }
  JumpingParabola plain;
  const auto p = steps(0, plain);
  ASSERT_GE(p.size(), 6u);
  EXPECT_NEAR(p[4].second, J, 1e-12);      // t = 0.4: the old path's prediction
  EXPECT_NEAR(p[5].second, 2 * J, 1e-12);  // t = 0.5
}

}  // namespace
}  // namespace fibrane::solve
