#include "solve/continuation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/error.hpp"

namespace fibrane::solve {

ContinuationResult run_continuation(NonlinearSystem& sys, Eigen::VectorXd& q, const StepControl& sc,
                                    const NewtonOptions& opt, LinearSolver& solver,
                                    const std::function<bool(const StepReport&, const Eigen::VectorXd&)>& on_step) {
  if (!(sc.dt_initial > 0) || !(sc.dt_max > 0) || !(sc.dt_min > 0) || !(sc.cutback > 0 && sc.cutback < 1) ||
      !(sc.growth >= 1) || !(sc.t_end >= sc.t_start))
    throw InputError("step control: need dt_initial, dt_min, dt_max > 0, 0 < cutback < 1, growth >= 1 and "
                     "t_end >= t_start");
  ContinuationResult res{false, sc.t_start, 0, 0, ""};
  double t = sc.t_start;
  double dt = std::min(sc.dt_initial, sc.dt_max);
  // Steps shorter than this fraction of the range count as reaching t_end (round-off in sums of dt).
  const double t_eps = 1e-12 * std::max(1.0, std::abs(sc.t_end));
  Eigen::VectorXd q_prev;
  double t_prev = t;
  bool have_prev = false;

  while (sc.t_end - t > t_eps) {
    if (res.steps >= sc.max_steps) {
      res.message = "stopped after max_steps = " + std::to_string(sc.max_steps) + " steps";
      return res;
    }
    double dt_try = std::min(dt, sc.t_end - t);
    int cutbacks = 0;
    NewtonReport newton;
    Eigen::VectorXd q_trial;
    double t_new = t;
    for (;;) {
      t_new = (sc.t_end - (t + dt_try) <= t_eps) ? sc.t_end : t + dt_try;
      q_trial = q;
      if (sc.extrapolate && have_prev)  // secant predictor: q(t_new) ~ q + (q - q_prev) dt / dt_prev
        q_trial += (q - q_prev) * ((t_new - t) / (t - t_prev));
      newton = newton_solve(sys, q_trial, t_new, opt, solver);
      res.total_iterations += newton.iterations;
      if (newton.converged) break;
      if (opt.verbose)
        std::fprintf(stderr, "step at t=%.6g dt=%.3g failed: %s; cutting back\n", t_new, dt_try,
                     newton.failure.c_str());
      sys.reject();
      ++cutbacks;
      dt_try *= sc.cutback;
      if (dt_try < sc.dt_min) {
        res.step_too_small = true;
        res.message = "step from t = " + std::to_string(t) + " failed with dt below dt_min = " +
                      std::to_string(sc.dt_min) + ": " + newton.failure;
        if (const std::string hint = sys.failure_hint(); !hint.empty()) res.message += ". " + hint;
        return res;
      }
    }
    q_prev = q;
    t_prev = t;
    have_prev = true;
    q = q_trial;
    t = t_new;
    res.t_reached = t;
    ++res.steps;
    // Grow only after an easy step taken at full size; after a cut-back continue with the size that worked.
    dt = (cutbacks == 0 && newton.iterations <= sc.easy_iterations) ? std::min(dt_try * sc.growth, sc.dt_max)
                                                                     : dt_try;
    sys.accept(q, t);
    const StepReport report{res.steps, t, t - t_prev, newton.iterations, newton.residual_norm, cutbacks,
                            newton.history};
    if (on_step && !on_step(report, q)) {
      res.message = "stopped by the step callback at t = " + std::to_string(t);
      return res;
    }
  }
  res.completed = true;
  res.message = "reached t_end = " + std::to_string(sc.t_end);
  return res;
}

}  // namespace fibrane::solve
