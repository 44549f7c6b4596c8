#pragma once
// Load stepping: the load parameter t is prescribed step by step and each step is solved by Newton
// (paper Sec. 2.3), with automatic cut-back of failed steps and growth after easy ones. It cannot pass a
// limit point of t (use arc-length continuation for that); a case may declare such a stop its end.
#include <vector>

#include "path/continuation.hpp"
#include "path/event_locator.hpp"

namespace fibrane::solve {

struct StepControl {
  double t_start = 0.0;
  double t_end = 1.0, dt_initial = 0.1, dt_min = 1e-8, dt_max = 0.1;
  int easy_iterations = 4;   // a step converging in at most this many iterations lets dt grow
  double growth = 1.5, cutback = 0.5;
  int max_steps = 100000;
  // Each step starts from a prediction of its state: the polynomial of this degree in t through the last
  // predictor_order + 1 converged states, evaluated at the new t (0: the last converged state; 1: the secant;
  // 2: the parabola; 3: the cubic), of a lower degree while fewer states exist.
  int predictor_order = 1;
  // A failure below dt_min after at least one converged step ends the run as Outcome::limit_point
  // instead of Outcome::failed (displacement-driven pull-off: the path turns back in t there).
  bool stop_at_limit_point = false;
  // The model's events (NonlinearSystem::event_margin) are crossed in steps at most this long, at least
  // 2 dt_min (path/event_locator.hpp); 0: a step crosses them wherever the steps fall.
  double event_tolerance = 0;
  // A step at most this share of the planned step (the dt that steps take without events; a located
  // event's approach and crossing take shorter ones) starts with the factorisation that the attempt before
  // it converged with, where there is one and the model has not changed since (newton_solve's
  // factor_in_hand; it needs NewtonOptions::reuse_below > 0). 0: every step factorises its own tangent first.
  double reuse_in_short_steps = 0;
};

// Throws InputError unless dt_initial, dt_min, dt_max > 0, 0 < cutback < 1, growth >= 1, t_end >= t_start.
void check_step_control(const StepControl& sc);

class LoadStepping final : public ContinuationMethod {
 public:
  LoadStepping(StepControl control, NewtonOptions newton);
  std::string name() const override { return "load_stepping"; }
  // On Newton failure q is restored and the step retried with dt * cutback; below dt_min the run stops.
  // A converged step that crosses an event in more than event_tolerance is withdrawn and retried shorter.
  // Never steps past t_end.
  ContinuationResult run(NonlinearSystem& sys, Eigen::VectorXd& q, LinearSolver& solver,
                         const StepCallback& on_step) override;
  MethodState save() const override;
  void restore(const MethodState& state) override;

 private:
  StepControl control_;
  NewtonOptions newton_;
  // Path state carried between steps (and across a restart).
  double t_ = 0, t_prev_ = 0, dt_ = 0;
  int steps_ = 0;
  // The last attempt converged (kept or withdrawn), so the solver holds its factorisation; not saved in a
  // checkpoint (a restarted run's first step factorises).
  bool factor_held_ = false;
  long factor_changes_ = 0;  // the system's model_changes() when that attempt ended
  // The converged states before the current one, the latest first (at most predictor_order of them).
  std::vector<double> t_past_;
  std::vector<Eigen::VectorXd> q_past_;
  bool restored_ = false;
  // NonlinearSystem::model_changes() when the current state converged (-1: not known, an older checkpoint),
  // and whether the current state crossed a located event (the model changes at its accept()).
  long changes_ = -1;
  bool located_change_ = false;
  EventLocator events_;
  double t_eps_ = 0;  // steps shorter than this count as reaching t_end (round-off in sums of dt)
  // One step's attempts from the converged (q, t_).
  struct Attempt {
    double dt_plan = 0, dt = 0, t_new = 0;  // the planned step, the one tried, and where it ends
    bool shortened = false;                 // dt < dt_plan: for an event ahead or after a withdrawn attempt
    int cutbacks = 0;
    std::vector<double> margins;            // the event margins at the converged state
    NewtonReport newton;
    Eigen::VectorXd q, predicted;           // the converged state; its prediction (after a located change)
  };
  // Attempts the step until one converges and is not withdrawn (true); false when the run ends (res says
  // how): a failure below dt_min.
  bool attempt(NonlinearSystem& sys, const Eigen::VectorXd& q, LinearSolver& solver, Attempt& at,
               ContinuationResult& res);
  // Takes the converged attempt as the new state q: the past states, t, the next dt, the system's accept().
  void advance(NonlinearSystem& sys, Eigen::VectorXd& q, Attempt& at);
  // The predicted state at t_new from q (at t_) and the stored converged states.
  Eigen::VectorXd predict(const Eigen::VectorXd& q, double t_new) const;
  // Keeps q (at t_) as the latest past state before the step to t_new is taken.
  void remember(Eigen::VectorXd& q);
  // After the model changed between the current state q and the converged q_new: moves q and the past
  // states by q_new's Newton correction q_new - predicted, onto the new path.
  void carry_across_change(Eigen::VectorXd& q, const Eigen::VectorXd& q_new, const Eigen::VectorXd& predicted);
};

}  // namespace fibrane::solve
