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
    : control_(control),
      newton_(std::move(newton)),
      events_(control.event_tolerance > 0 ? std::max(control.event_tolerance, 2 * control.dt_min) : 0.0) {
  check_step_control(control_);
}

namespace {
// A predictor of degree 2 or more uses past states spanning at least this share of the step it predicts.
constexpr double kSpanForCurvature = 0.5;

// The checkpoint's keys of the k-th past state (0: the latest): t_prev, q_prev, t_prev2, q_prev2, ...
std::string past_key(const char* what, std::size_t k) {
  return std::string(what) + "_prev" + (k == 0 ? std::string() : std::to_string(k + 1));
}
}  // namespace

MethodState LoadStepping::save() const {
  MethodState s;
  s["t"] = {t_};
  s["t_prev"] = {t_prev_};
  s["dt"] = {dt_};
  s["steps"] = {static_cast<double>(steps_)};
  s["model_changes"] = {static_cast<double>(changes_), located_change_ ? 1.0 : 0.0};
  s["have_prev"] = {q_past_.empty() ? 0.0 : 1.0};
  s["q_prev"] = {};
  for (std::size_t k = 0; k < q_past_.size(); ++k) {
    if (k > 0) s[past_key("t", k)] = {t_past_[k]};
    s[past_key("q", k)] = std::vector<double>(q_past_[k].data(), q_past_[k].data() + q_past_[k].size());
  }
  events_.save(s);
  return s;
}

void LoadStepping::restore(const MethodState& s) {
  t_ = s.at("t").at(0);
  t_prev_ = s.at("t_prev").at(0);
  dt_ = s.at("dt").at(0);
  steps_ = static_cast<int>(s.at("steps").at(0));
  const auto changes = s.find("model_changes");
  const bool known = changes != s.end() && changes->second.size() == 2;
  changes_ = known ? static_cast<long>(changes->second[0]) : -1;
  located_change_ = known && changes->second[1] != 0.0;
  t_past_.clear();
  q_past_.clear();
  if (s.at("have_prev").at(0) != 0.0)
    for (std::size_t k = 0; s.count(past_key("q", k)) > 0; ++k) {
      const auto& q = s.at(past_key("q", k));
      t_past_.push_back(k == 0 ? t_prev_ : s.at(past_key("t", k)).at(0));
      q_past_.emplace_back(Eigen::Map<const Eigen::VectorXd>(q.data(), static_cast<Eigen::Index>(q.size())));
    }
  events_.restore(s, t_);
  restored_ = true;
}

Eigen::VectorXd LoadStepping::predict(const Eigen::VectorXd& q, double t_new) const {
  std::size_t m = std::min(static_cast<std::size_t>(std::max(control_.predictor_order, 0)), q_past_.size());
  // A parabola or cubic through states much closer together than the step (after the short steps at an
  // event) would extrapolate their round-off and the kink of a model change: such states are left out.
  while (m >= 2 && t_ - t_past_[m - 1] < kSpanForCurvature * (t_new - t_)) --m;
  if (m == 0) return q;
  if (m == 1)  // secant: q(t_new) ~ q + (q - q_prev) dt / dt_prev
    return q + (q - q_past_[0]) * ((t_new - t_) / (t_ - t_past_[0]));
  // Lagrange's polynomial through the m + 1 states (the oldest first), evaluated at t_new.
  std::vector<double> t(m + 1);
  std::vector<const Eigen::VectorXd*> states(m + 1);
  for (std::size_t i = 0; i < m; ++i) {
    t[i] = t_past_[m - 1 - i];
    states[i] = &q_past_[m - 1 - i];
  }
  t[m] = t_;
  states[m] = &q;
  auto weight = [&](std::size_t i) {  // the Lagrange basis polynomial of state i at t_new
    double num = 1.0, den = 1.0;
    for (std::size_t j = 0; j <= m; ++j)
      if (j != i) {
        num *= t_new - t[j];
        den *= t[i] - t[j];
      }
    return num / den;
  };
  Eigen::VectorXd out = weight(0) * *states[0];
  for (std::size_t i = 1; i <= m; ++i) out += weight(i) * *states[i];
  return out;
}

void LoadStepping::remember(Eigen::VectorXd& q) {
  const auto keep = static_cast<std::size_t>(std::max(control_.predictor_order, 0));
  if (keep > 0) {
    q_past_.resize(std::min(q_past_.size() + 1, keep));
    t_past_.resize(q_past_.size());
    for (std::size_t k = q_past_.size() - 1; k > 0; --k) {  // the oldest falls off the end
      q_past_[k].swap(q_past_[k - 1]);
      t_past_[k] = t_past_[k - 1];
    }
    q_past_[0].swap(q);
    t_past_[0] = t_;
  }
  t_prev_ = t_;
}

void LoadStepping::carry_across_change(Eigen::VectorXd& q, const Eigen::VectorXd& q_new,
                                       const Eigen::VectorXd& predicted) {
  const Eigen::VectorXd d = q_new - predicted;
  q += d;
  for (Eigen::VectorXd& past : q_past_) past += d;
}

bool LoadStepping::attempt(NonlinearSystem& sys, const Eigen::VectorXd& q, LinearSolver& solver, Attempt& at,
                           ContinuationResult& res) {
  const StepControl& sc = control_;
  for (;;) {
    at.t_new = (sc.t_end - (t_ + at.dt) <= t_eps_) ? sc.t_end : t_ + at.dt;
    at.q = predict(q, at.t_new);
    if (located_change_) at.predicted = at.q;
    // A factorisation from before a change of the model (a point switched to the soft minimum at the last
    // accept) lacks the change's stiffness: the chord with it stalls, and the step factorises anyway.
    const bool in_hand = factor_held_ && factor_changes_ == sys.model_changes();
    at.newton = newton_solve(sys, at.q, at.t_new, newton_, solver, in_hand && at.dt <= sc.reuse_in_short_steps * dt_);
    factor_held_ = at.newton.converged;  // a failed solve releases its factor
    factor_changes_ = sys.model_changes();
    res.total_iterations += at.newton.iterations;
    res.local_updates += at.newton.local_updates;
    if (at.newton.converged) {
      at.margins = sys.event_margins();
      if (!events_.withdraw(t_, at.t_new, at.margins)) return true;
      if (newton_.verbose)
        std::fprintf(stderr, "step at t=%.6g dt=%.3g crossed an event: withdrawn, shorter\n", at.t_new, at.dt);
      sys.withdraw();
      ++res.withdrawn_attempts;
      const double shorter = events_.step(t_, at.dt_plan);  // within the bracket: shorter than the withdrawn
      at.dt = shorter < at.dt ? shorter : at.dt * sc.cutback;
      at.shortened = true;
      continue;
    }
    if (newton_.verbose)
      std::fprintf(stderr, "step at t=%.6g dt=%.3g failed: %s; cutting back\n", at.t_new, at.dt,
                   at.newton.failure.c_str());
    sys.reject();
    ++at.cutbacks;
    ++res.failed_attempts;
    at.dt *= sc.cutback;
    if (at.dt < sc.dt_min) {
      const bool limit = sc.stop_at_limit_point && res.steps > 0;
      res.outcome = limit ? Outcome::limit_point : Outcome::failed;
      res.message = limit ? "ended at a limit point after t = " + format_number(t_) +
                                " (no equilibrium could be continued: for displacement-driven adhesion, pull-off)"
                          : "step from t = " + format_number(t_) + " failed with dt below dt_min = " +
                                format_number(sc.dt_min) + ": " + at.newton.failure;
      if (const std::string hint = sys.failure_hint(); !hint.empty() && !limit) res.message += ". " + hint;
      return false;
    }
  }
}

void LoadStepping::advance(NonlinearSystem& sys, Eigen::VectorXd& q, Attempt& at) {
  const StepControl& sc = control_;
  // A model changed by a located event: the states before it lie within a tolerance of the change (the
  // crossing's short steps), so a parabola or cubic through them and the new state would multiply the jump
  // between the two models' paths by the new state's large weight. Moved by the first step's Newton
  // correction, they leave that step's own prediction error in the jump's place, the smaller of the two
  // there (docs/interaction.md, section 7). Elsewhere (events not located, switches after failed attempts)
  // the states are a step apart, the weight is ~3 and the prediction error not small against the jump:
  // the polynomial keeps the states as they are.
  if (const long changes = sys.model_changes(); changes != changes_) {
    if (located_change_) carry_across_change(q, at.q, at.predicted);
    changes_ = changes;
  }
  located_change_ = false;
  remember(q);
  q = at.q;
  t_ = at.t_new;
  ++steps_;
  // Grow only after an easy step taken at full size; after a cut-back continue with the size that worked.
  if (!(at.shortened && at.cutbacks == 0))
    dt_ = (at.cutbacks == 0 && at.newton.iterations <= sc.easy_iterations) ? std::min(at.dt * sc.growth, sc.dt_max)
                                                                          : at.dt;
  // A located event changes the model at this state (the next step's predictor then moves the past states).
  located_change_ = events_.located(at.margins);
  sys.accept(q, t_);
  events_.accepted(t_, sys.event_margins());
}

ContinuationResult LoadStepping::run(NonlinearSystem& sys, Eigen::VectorXd& q, LinearSolver& solver,
                                     const StepCallback& on_step) {
  const StepControl& sc = control_;
  factor_held_ = false;
  if (!restored_) {
    t_ = t_prev_ = sc.t_start;
    dt_ = std::min(sc.dt_initial, sc.dt_max);
    steps_ = 0;
    t_past_.clear();
    q_past_.clear();
    events_.start(t_);
    changes_ = sys.model_changes();
    located_change_ = false;
  }
  if (changes_ < 0) changes_ = sys.model_changes();
  ContinuationResult res;
  res.t_reached = t_;
  res.steps = steps_;
  // Steps shorter than this fraction of the range count as reaching t_end (round-off in sums of dt).
  t_eps_ = 1e-12 * std::max(1.0, std::abs(sc.t_end));
  while (sc.t_end - t_ > t_eps_) {
    if (res.steps >= sc.max_steps) {
      res.outcome = Outcome::max_steps;
      res.message = "stopped after max_steps = " + std::to_string(sc.max_steps) + " steps";
      return res;
    }
    Attempt at;
    at.dt_plan = std::min(dt_, sc.t_end - t_);
    at.dt = events_.step(t_, at.dt_plan);
    // The first step on a model changed by a located event is one tolerance long: its Newton correction,
    // which moves the past states (advance), is then the jump between the two models' paths with little
    // of the step's own prediction error.
    if (located_change_) at.dt = std::min(at.dt, events_.tolerance());
    at.shortened = at.dt < at.dt_plan;  // for an event ahead: the planned dt_ stands for the steps after it
    if (!attempt(sys, q, solver, at, res)) return res;
    advance(sys, q, at);
    res.t_reached = t_;
    res.steps = steps_;
    StepReport report;
    report.step = res.steps;
    report.t = t_;
    report.dt = t_ - t_prev_;
    report.iterations = at.newton.iterations;
    report.residual_norm = at.newton.residual_norm;
    report.cutbacks = at.cutbacks;
    report.history = at.newton.history;
    report.negative_eigenvalues = at.newton.negative_eigenvalues;
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
