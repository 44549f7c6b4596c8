#include "path/arc_length.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "common/error.hpp"
#include "common/format.hpp"
#include "path/arc_length_detail.hpp"

namespace fibrane::solve {

using arc_length_detail::quadratic_roots;

// A tangent of the path at a converged state, not normalised: K dq + r_t dt = 0.
// One attempt at a step: the corrector's outcome.
struct ArcLength::Attempt {
  bool converged = false;
  Eigen::VectorXd q;
  double t = 0;
  int iterations = 0;
  std::vector<double> history;  // |r| at every evaluation
  std::string failure;
  bool tangent_current = false;  // the system's last evaluation was at (q, t) with the tangent
  bool landed = false;           // (q, t) was solved at fixed t = t_end
};


bool ArcLength::corrector_update(NonlinearSystem& sys, LinearSolver& solver, const Eigen::VectorXd& dq, double dt,
                                 double ds, Eigen::VectorXd& delta_q, double& delta_t, std::string& failure) {
  const Eigen::SparseMatrix<double>& k = sys.tangent();
  const Eigen::VectorXd& r = sys.residual();
  const Eigen::VectorXd& r_t = sys.load_derivative();
  if (!sys.tangent_finite() || !r_t.allFinite()) {
    failure = "non-finite tangent or load derivative";
    return false;
  }
  const double c2 = c_ * c_;
  const double g = 0.5 * (dq.squaredNorm() + c2 * dt * dt - ds * ds);  // constraint residual
  analyze_if_needed(solver, sys, k);
  if (solver.factorize(k)) {
    const Eigen::VectorXd a = solver.solve(-r), b = solver.solve(-r_t);
    if (a.allFinite() && b.allFinite()) {
      bool solved = false;
      if (control_.corrector == ArcLengthCorrector::quadratic) {
        // Crisfield (1981): |dq + a + x b|^2 + c^2 (dt + x)^2 = ds^2.
        const Eigen::VectorXd u = dq + a;
        double x1 = 0, x2 = 0;
        if (quadratic_roots(b.squaredNorm() + c2, 2 * (b.dot(u) + c2 * dt), u.squaredNorm() + c2 * dt * dt - ds * ds,
                            x1, x2)) {
          // The root whose new increment makes the smaller angle with the current one (both have length ds).
          auto alignment = [&](double x) { return dq.dot(u) + x * dq.dot(b) + c2 * dt * (dt + x); };
          delta_t = alignment(x1) >= alignment(x2) ? x1 : x2;
          solved = true;
        }
      }
      const double denominator = dq.dot(b) + c2 * dt;
      if (!solved && denominator != 0) {  // linearised constraint: dq . delta_q + c^2 dt delta_t = -g
        delta_t = -(g + dq.dot(a)) / denominator;
        solved = true;
      }
      if (solved) {
        delta_q = a + delta_t * b;
        if (delta_q.allFinite() && std::isfinite(delta_t)) return true;
      }
    }
  }
  if (sys.distributed()) {  // the extended system needs the whole tangent
    failure = "factorization failed (" + solver.name() + ")";
    return false;
  }
  if (bordered_solve(k, r_t, dq, c2 * dt, -r, -g, delta_q, delta_t)) return true;
  failure = "factorization failed (" + solver.name() + "), also for the extended system";
  return false;
}

// Predictor along `tangent` with length ds, then corrector iterations until the residual test of
// newton_solve is met or the attempt fails.
ArcLength::Attempt ArcLength::correct(NonlinearSystem& sys, const Eigen::VectorXd& q0, double t0,
                                      const Tangent& tangent, int sign, double ds, LinearSolver& solver) {
  Attempt at;
  const double length = std::sqrt(tangent.dq.squaredNorm() + c_ * c_ * tangent.dt * tangent.dt);
  if (!(length > 0)) {  // cylindrical constraint (c = 0) on a state where dq/dt = 0
    at.failure = "the tangent has no length in the constraint's norm";
    return at;
  }
  Eigen::VectorXd dq = (sign * ds / length) * tangent.dq;
  double dt = sign * ds / length * tangent.dt;
  at.q = q0 + dq;
  at.t = t0 + dt;
  double scale = 0, previous_norm = 0;
  bool small_update = false;
  for (int it = 0;; ++it) {
    sys.evaluate(at.q, at.t, true);
    const double norm = sys.residual().norm();
    at.history.push_back(norm);
    if (newton_.verbose) std::fprintf(stderr, "  arc length t=%.6g it=%d |r|=%.6e\n", at.t, it, norm);
    if (!std::isfinite(norm)) {
      at.failure = "non-finite residual at iteration " + std::to_string(it);
      return at;
    }
    if (it == 0) scale = std::max(norm, sys.residual_scale());
    // Convergence as in newton_solve, including its round-off floor rule.
    const bool at_floor =
        small_update && norm <= 2.0 * previous_norm && norm <= std::sqrt(newton_.tol_relative) * scale;
    if (norm <= std::max(newton_.tol_relative * scale, newton_.tol_absolute) || at_floor) {
      at.converged = at.tangent_current = true;
      return at;
    }
    previous_norm = norm;
    if (norm > newton_.divergence_factor * scale) {
      at.failure = "diverged at iteration " + std::to_string(it) + " (|r| = " + format_number(norm) + ")";
      return at;
    }
    if (it >= newton_.max_iterations) {
      at.failure = "no convergence in " + std::to_string(newton_.max_iterations) + " iterations (|r| = " +
                   format_number(norm) + ")";
      return at;
    }
    Eigen::VectorXd delta_q;
    double delta_t = 0;
    if (!corrector_update(sys, solver, dq, dt, ds, delta_q, delta_t, at.failure)) {
      at.failure += " at iteration " + std::to_string(it);
      return at;
    }
    dq += delta_q;
    dt += delta_t;
    at.q += delta_q;
    at.t = t0 + dt;
    small_update = newton_.tol_increment > 0 && delta_q.norm() <= newton_.tol_increment * at.q.norm();
    at.iterations = it + 1;
  }
}

// The converged attempt from (q0, t0) crossed t_end: it is replaced by the solution of Newton at fixed
// t = t_end started from the linear interpolation between the two states. False (with the reason in
// attempt.failure) if Newton fails or ends farther than ds from the interpolation.
bool ArcLength::land_on_t_end(NonlinearSystem& sys, const Eigen::VectorXd& q0, double t0, double ds,
                              Attempt& attempt, LinearSolver& solver) {
  const double t_end = control_.t_end;
  const double theta = (t_end - t0) / (attempt.t - t0);
  const Eigen::VectorXd interpolated = q0 + theta * (attempt.q - q0);
  Eigen::VectorXd q = interpolated;
  sys.reject();  // the discarded solution's evaluations must not count as history
  const NewtonReport newton = newton_solve(sys, q, t_end, newton_, solver);
  attempt.iterations += newton.iterations;
  attempt.converged = false;
  if (!newton.converged) {
    attempt.failure = "landing on t_end = " + format_number(t_end) + " failed: " + newton.failure;
    return false;
  }
  if ((q - interpolated).norm() > ds) {
    attempt.failure = "landing on t_end = " + format_number(t_end) + " converged to another branch";
    return false;
  }
  attempt.converged = attempt.landed = true;
  attempt.q = q;
  attempt.t = t_end;
  attempt.history = newton.history;
  attempt.tangent_current = false;
  return true;
}

// One step from the converged (q, t_): attempts with ds cut back after each failure. False when ds fell
// below ds_min (res then holds the failure).
bool ArcLength::step(NonlinearSystem& sys, const Eigen::VectorXd& q, const Tangent& tangent, LinearSolver& solver,
                     Attempt& at, double& ds, int& cutbacks, ContinuationResult& res) {
  const int sign = predictor_sign(tangent);
  const double t_end = control_.t_end;
  for (cutbacks = 0;; ++cutbacks) {
    at = correct(sys, q, t_, tangent, sign, ds, solver);
    res.total_iterations += at.iterations;
    const bool crossed = t_ != t_end && (at.t - t_end) * (t_ - t_end) <= 0;
    if (at.converged && crossed) {
      const int corrector_iterations = at.iterations;
      land_on_t_end(sys, q, t_, ds, at, solver);
      res.total_iterations += at.iterations - corrector_iterations;
    }
    if (at.converged) return true;
    if (newton_.verbose)
      std::fprintf(stderr, "arc-length step at t=%.6g ds=%.3g failed: %s; cutting back\n", t_, ds, at.failure.c_str());
    sys.reject();
    ++res.failed_attempts;
    ds *= control_.cutback;
    if (ds < control_.ds_min) {
      res.outcome = Outcome::failed;
      res.message = "arc-length step from t = " + format_number(t_) + " failed with ds below ds_min = " +
                    format_number(control_.ds_min) + ": " + at.failure;
      if (const std::string hint = sys.failure_hint(); !hint.empty()) res.message += ". " + hint;
      return false;
    }
  }
}

// Records the converged attempt as the new state, prepares the next predictor's tangent at it (before
// sys.accept()) and returns the step's report.
StepReport ArcLength::advance(NonlinearSystem& sys, Eigen::VectorXd& q, const Attempt& at, double ds, int cutbacks,
                              LinearSolver& solver, Tangent& tangent, bool& have_tangent) {
  const ArcLengthControl& ac = control_;
  StepReport report;
  report.dt = at.t - t_;
  report.limit_point = have_prev_ && report.dt * dt_prev_ < 0;
  dq_prev_ = at.q - q;
  dt_prev_ = report.dt;
  have_prev_ = true;
  path_length_ += at.landed ? std::sqrt(dq_prev_.squaredNorm() + c_ * c_ * report.dt * report.dt) : ds;
  q = at.q;
  t_ = at.t;
  report.step = ++steps_;
  // Crisfield (1981): ds_new = ds (I_desired / I)^(1/2), no growth right after a cut-back.
  const double factor = std::sqrt(static_cast<double>(ac.desired_iterations) / std::max(at.iterations, 1));
  ds_ = std::clamp(ds * std::clamp(factor, ac.cutback, cutbacks > 0 ? 1.0 : ac.growth), ac.ds_min, ac.ds_max);
  if (!at.tangent_current) sys.evaluate(q, t_, true);
  have_tangent = tangent_at_state(sys, solver, tangent);
  sys.accept(q, t_);
  report.t = t_;
  report.iterations = at.iterations;
  report.residual_norm = at.history.back();
  report.cutbacks = cutbacks;
  report.history = at.history;
  report.negative_eigenvalues = have_tangent ? tangent.negative_eigenvalues : -1;
  report.path_length = path_length_;
  if (have_tangent) {  // the tangent oriented like the step that arrived here (the angle rule)
    const double c2 = c_ * c_;
    const double norm = std::sqrt(tangent.dq.squaredNorm() + c2 * tangent.dt * tangent.dt);
    const double along = tangent.dq.dot(dq_prev_) + c2 * tangent.dt * dt_prev_;
    if (norm > 0) report.dt_ds = (along >= 0 ? 1.0 : -1.0) * tangent.dt / norm;
  }
  if (newton_.verbose)
    std::fprintf(stderr, "arc-length step %d: t=%.6g dt=%.3g ds=%.3g iterations=%d%s\n", steps_, t_, report.dt, ds,
                 at.iterations, report.limit_point ? " (limit point)" : "");
  return report;
}

// True (with the outcome in res) when the step just taken ends the run: t_end, the load range or the
// path length.
bool ArcLength::end_reached(bool landed, ContinuationResult& res) const {
  const ArcLengthControl& ac = control_;
  const bool long_enough = path_length_ >= ac.max_path_length * (1 - 1e-12);
  if (!landed && !long_enough && t_ >= ac.t_min && t_ <= ac.t_max) return false;
  res.outcome = Outcome::reached_end;
  res.message = landed        ? "reached t_end = " + format_number(ac.t_end)
                : long_enough ? "reached the path length " + format_number(path_length_)
                              : "t = " + format_number(t_) + " left [t_min, t_max]";
  return true;
}

// A path starts at an equilibrium: a start that is not one (a beam released above a plate it attracts)
// is first solved at fixed t_start by Newton, and that state is reported as a step with dt = 0.
bool ArcLength::start_in_equilibrium(NonlinearSystem& sys, Eigen::VectorXd& q, LinearSolver& solver,
                                     const StepCallback& on_step, ContinuationResult& res) {
  sys.evaluate(q, t_, false);
  const double r0 = sys.residual().norm();
  if (sys.invalid_state().empty() && r0 <= std::max(newton_.tol_relative * sys.residual_scale(), newton_.tol_absolute))
    return true;
  const NewtonReport newton = newton_solve(sys, q, t_, newton_, solver);
  res.total_iterations += newton.iterations;
  if (!newton.converged) {
    sys.reject();
    res.outcome = Outcome::failed;
    res.message = "no equilibrium at the start t = " + format_number(t_) + ": " + newton.failure;
    return false;
  }
  sys.accept(q, t_);
  StepReport report;
  report.step = steps_ = res.steps = 1;
  report.t = t_;
  report.iterations = newton.iterations;
  report.residual_norm = newton.residual_norm;
  report.history = newton.history;
  report.negative_eigenvalues = newton.negative_eigenvalues;
  if (on_step && !on_step(report, q)) {
    res.outcome = Outcome::stopped;
    res.message = "stopped by the step callback at the start";
    return false;
  }
  return true;
}

ContinuationResult ArcLength::run(NonlinearSystem& sys, Eigen::VectorXd& q, LinearSolver& solver,
                                  const StepCallback& on_step) {
  if (q.size() != sys.size()) throw std::invalid_argument("ArcLength::run: q has the wrong size");
  const ArcLengthControl& ac = control_;
  if (!restored_) {
    t_ = ac.t_start;
    ds_ = std::min(ac.ds_initial, ac.ds_max);
    c_ = ac.load_scale;
    path_length_ = 0;
    steps_ = 0;
    have_prev_ = false;
    tangent_dt_sign_ = 0;
    inertia_prev_ = -1;
    have_tangent_ = false;
  }
  ContinuationResult res;
  res.t_reached = t_;
  res.steps = steps_;
  if (!restored_ && !start_in_equilibrium(sys, q, solver, on_step, res)) return res;
  Tangent& tangent = tangent_;
  bool& have_tangent = have_tangent_;
  if (have_tangent && tangent.dq.size() != q.size())
    throw std::invalid_argument("ArcLength::run: the restored tangent has the wrong size");
  for (;;) {
    if (res.steps >= ac.max_steps) {
      res.outcome = Outcome::max_steps;
      res.message = "stopped after max_steps = " + std::to_string(ac.max_steps) + " steps";
      return res;
    }
    if (!have_tangent) sys.evaluate(q, t_, true);
    if (!have_tangent && !tangent_at_state(sys, solver, tangent)) {
      res.outcome = Outcome::failed;
      res.message = "no tangent of the path at t = " + format_number(t_) + " (singular or non-finite)";
      return res;
    }
    if (c_ < 0) {  // automatic scaling: |dq/dt| of the first tangent
      c_ = tangent.dt != 0 ? tangent.dq.norm() / std::abs(tangent.dt) : 0.0;
      if (!(c_ > 0 && std::isfinite(c_))) c_ = 1.0;
    }
    Attempt at;
    double ds = std::min(ds_, ac.max_path_length - path_length_);
    int cutbacks = 0;
    if (!step(sys, q, tangent, solver, at, ds, cutbacks, res)) return res;
    const StepReport report = advance(sys, q, at, ds, cutbacks, solver, tangent, have_tangent);
    res.t_reached = t_;
    res.steps = steps_;
    if (on_step && !on_step(report, q)) {
      res.outcome = Outcome::stopped;
      res.message = "stopped by the step callback at t = " + format_number(t_);
      return res;
    }
    if (end_reached(at.landed, res)) return res;
  }
}

}  // namespace fibrane::solve
