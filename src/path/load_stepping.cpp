#include "path/load_stepping.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/error.hpp"
#include "common/format.hpp"

namespace fibrane::solve {

void check_step_control(const StepControl& sc) {
  if (!(sc.dt_initial > 0) || !(sc.dt_max > 0) || !(sc.dt_min > 0) || !(sc.cutback > 0 && sc.cutback < 1) ||
      !(sc.growth >= 1) || !(sc.t_end >= sc.t_start))
    throw InputError("step control: need dt_initial, dt_min, dt_max > 0, 0 < cutback < 1, growth >= 1 and "
                     "t_end >= t_start");
}

LoadStepping::LoadStepping(StepControl control, NewtonOptions newton)
    : control_(control), newton_(std::move(newton)) {
  check_step_control(control_);
}

MethodState LoadStepping::save() const {
  MethodState s;
  s["t"] = {t_};
  s["t_prev"] = {t_prev_};
  s["dt"] = {dt_};
  s["steps"] = {static_cast<double>(steps_)};
  s["have_prev"] = {have_prev_ ? 1.0 : 0.0};
  s["q_prev"] = std::vector<double>(q_prev_.data(), q_prev_.data() + q_prev_.size());
  if (have_prev2_) {
    s["t_prev2"] = {t_prev2_};
    s["q_prev2"] = std::vector<double>(q_prev2_.data(), q_prev2_.data() + q_prev2_.size());
  }
  return s;
}

void LoadStepping::restore(const MethodState& s) {
  t_ = s.at("t").at(0);
  t_prev_ = s.at("t_prev").at(0);
  dt_ = s.at("dt").at(0);
  steps_ = static_cast<int>(s.at("steps").at(0));
  have_prev_ = s.at("have_prev").at(0) != 0.0;
  const auto& qp = s.at("q_prev");
  q_prev_ = Eigen::Map<const Eigen::VectorXd>(qp.data(), static_cast<Eigen::Index>(qp.size()));
  have_prev2_ = s.count("q_prev2") > 0;
  if (have_prev2_) {
    t_prev2_ = s.at("t_prev2").at(0);
    const auto& qp2 = s.at("q_prev2");
    q_prev2_ = Eigen::Map<const Eigen::VectorXd>(qp2.data(), static_cast<Eigen::Index>(qp2.size()));
  }
  restored_ = true;
}

Eigen::VectorXd LoadStepping::predict(const Eigen::VectorXd& q, double t_new) const {
  if (control_.predictor_order < 1 || !have_prev_) return q;
  if (control_.predictor_order < 2 || !have_prev2_)  // secant: q(t_new) ~ q + (q - q_prev) dt / dt_prev
    return q + (q - q_prev_) * ((t_new - t_) / (t_ - t_prev_));
  // Lagrange parabola through (t_prev2, q_prev2), (t_prev, q_prev), (t, q), evaluated at t_new.
  const double a = t_prev2_, b = t_prev_, c = t_;
  const double la = (t_new - b) * (t_new - c) / ((a - b) * (a - c));
  const double lb = (t_new - a) * (t_new - c) / ((b - a) * (b - c));
  const double lc = (t_new - a) * (t_new - b) / ((c - a) * (c - b));
  return la * q_prev2_ + lb * q_prev_ + lc * q;
}

ContinuationResult LoadStepping::run(NonlinearSystem& sys, Eigen::VectorXd& q, LinearSolver& solver,
                                     const StepCallback& on_step) {
  const StepControl& sc = control_;
  if (!restored_) {
    t_ = t_prev_ = sc.t_start;
    dt_ = std::min(sc.dt_initial, sc.dt_max);
    steps_ = 0;
    have_prev_ = have_prev2_ = false;
  }
  ContinuationResult res;
  res.t_reached = t_;
  res.steps = steps_;
  // Steps shorter than this fraction of the range count as reaching t_end (round-off in sums of dt).
  const double t_eps = 1e-12 * std::max(1.0, std::abs(sc.t_end));
  while (sc.t_end - t_ > t_eps) {
    if (res.steps >= sc.max_steps) {
      res.outcome = Outcome::max_steps;
      res.message = "stopped after max_steps = " + std::to_string(sc.max_steps) + " steps";
      return res;
    }
    double dt_try = std::min(dt_, sc.t_end - t_);
    int cutbacks = 0;
    NewtonReport newton;
    Eigen::VectorXd q_trial;
    double t_new = t_;
    for (;;) {
      t_new = (sc.t_end - (t_ + dt_try) <= t_eps) ? sc.t_end : t_ + dt_try;
      q_trial = predict(q, t_new);
      newton = newton_solve(sys, q_trial, t_new, newton_, solver);
      res.total_iterations += newton.iterations;
      if (newton.converged) break;
      if (newton_.verbose)
        std::fprintf(stderr, "step at t=%.6g dt=%.3g failed: %s; cutting back\n", t_new, dt_try,
                     newton.failure.c_str());
      sys.reject();
      ++cutbacks;
      ++res.failed_attempts;
      dt_try *= sc.cutback;
      if (dt_try < sc.dt_min) {
        const bool limit = sc.stop_at_limit_point && res.steps > 0;
        res.outcome = limit ? Outcome::limit_point : Outcome::failed;
        res.message = limit ? "ended at a limit point after t = " + format_number(t_) +
                                  " (no equilibrium could be continued: for displacement-driven adhesion, pull-off)"
                            : "step from t = " + format_number(t_) + " failed with dt below dt_min = " +
                                  format_number(sc.dt_min) + ": " + newton.failure;
        if (const std::string hint = sys.failure_hint(); !hint.empty() && !limit) res.message += ". " + hint;
        return res;
      }
    }
    if (have_prev_ && sc.predictor_order >= 2) {
      q_prev2_.swap(q_prev_);
      t_prev2_ = t_prev_;
      have_prev2_ = true;
    }
    q_prev_ = q;
    t_prev_ = t_;
    have_prev_ = true;
    q = q_trial;
    t_ = t_new;
    res.t_reached = t_;
    steps_ = ++res.steps;
    // Grow only after an easy step taken at full size; after a cut-back continue with the size that worked.
    dt_ = (cutbacks == 0 && newton.iterations <= sc.easy_iterations) ? std::min(dt_try * sc.growth, sc.dt_max)
                                                                     : dt_try;
    sys.accept(q, t_);
    StepReport report;
    report.step = res.steps;
    report.t = t_;
    report.dt = t_ - t_prev_;
    report.iterations = newton.iterations;
    report.residual_norm = newton.residual_norm;
    report.cutbacks = cutbacks;
    report.history = newton.history;
    report.negative_eigenvalues = newton.negative_eigenvalues;
    if (on_step && !on_step(report, q)) {
      res.outcome = Outcome::stopped;
      res.message = "stopped by the step callback at t = " + format_number(t_);
      return res;
    }
  }
  res.outcome = Outcome::reached_end;
  res.message = "reached t_end = " + format_number(sc.t_end);
  return res;
}

}  // namespace fibrane::solve
