#pragma once
// Quasi-time continuation (paper Sec. 2.3: the forcing term is incremented and equilibrium is found by
// Newton's method at a finite number of quasi-time steps), with automatic cut-back and growth of the step.
#include <functional>
#include <string>
#include <vector>

#include "solve/nonlinear.hpp"

namespace fibrane::solve {

struct StepControl {
  double t_start = 0.0;
  double t_end = 1.0, dt_initial = 0.1, dt_min = 1e-8, dt_max = 0.1;
  int easy_iterations = 4;   // a step converging in at most this many iterations lets dt grow
  double growth = 1.5, cutback = 0.5;
  int max_steps = 100000;
  bool extrapolate = true;   // secant predictor from the last two converged states
};

struct StepReport {
  int step;        // 1-based count of converged steps
  double t, dt;
  int iterations;  // Newton iterations of the converged attempt
  double residual_norm;
  int cutbacks;    // failed attempts before this step converged
  std::vector<double> history;  // residual norms of the converged attempt
};

struct ContinuationResult {
  bool completed;
  double t_reached;
  int steps;
  int total_iterations;  // including failed attempts
  std::string message;
  bool step_too_small = false;  // ended because a step failed even below dt_min (e.g. at a limit point)
};

// Marches t from t_start to t_end. After each converged step: sys.accept(q, t), then on_step(report, q);
// on_step returning false stops early (completed = false). On Newton failure q is restored and the step is
// retried with dt * cutback; below dt_min the run stops with a message. Never steps past t_end.
ContinuationResult run_continuation(NonlinearSystem& sys, Eigen::VectorXd& q, const StepControl& sc,
                                    const NewtonOptions& opt, LinearSolver& solver,
                                    const std::function<bool(const StepReport&, const Eigen::VectorXd&)>& on_step);

}  // namespace fibrane::solve
