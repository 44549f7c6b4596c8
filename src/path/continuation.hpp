#pragma once
// Continuation methods: how a run marches along the equilibrium path of a NonlinearSystem (paper
// Sec. 2.3: the forcing term is incremented and each increment is solved by Newton's method). Every
// method is one class behind ContinuationMethod; the run driver picks one by name from the case file
// (steps.method) and knows nothing of its inner workings.
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "path/nonlinear.hpp"

namespace fibrane::solve {

// Energy bookkeeping of a time-integration method at a converged step. The work and dissipation are
// cumulative from the start of the run; with the model's stored energies (strain, interaction) the balance
//   E_kin + E_strain + E_interaction - external_work - prescribed_work + damping = const
// holds up to the scheme's algorithmic dissipation (solve/generalized_alpha.hpp says how each is summed).
struct EnergyReport {
  double kinetic = 0;          // 1/2 v^T M v at the step's time
  double external_work = 0;    // work of the external loads f_ext
  double prescribed_work = 0;  // work of the support reactions on the prescribed motion
  double damping = 0;          // energy dissipated by the damping forces C v
};

// One converged point of the path.
struct StepReport {
  int step = 0;          // 1-based count of converged steps (0: the initial state)
  double t = 0, dt = 0;  // load parameter (quasi-time or time) and its increment
  int iterations = 0;    // Newton iterations of the converged attempt
  double residual_norm = 0;
  int cutbacks = 0;              // failed attempts before this step converged
  std::vector<double> history;   // residual norms of the converged attempt
  // Of the last tangent Newton factorised in this step (an iterate before the converged one: Newton
  // assembles no tangent at a state it predicts converged, and may reuse a factorisation); -1: not known.
  int negative_eigenvalues = -1;
  bool limit_point = false;       // the load parameter passed an extremum within this step
  double path_length = 0;         // arc-length methods: the path's length from the start to this point
  // Arc-length methods: dt/ds of the path's tangent at this point, oriented along the path (NaN: unknown).
  double dt_ds = std::numeric_limits<double>::quiet_NaN();
  std::optional<EnergyReport> energy{};  // time-integration methods only
};

// How a run ended.
enum class Outcome {
  reached_end,   // t_end (or the method's own end) was reached
  stopped,       // a stop rule of the caller ended the run (the step callback returned false)
  limit_point,   // load stepping could not pass a limit point and the case accepts that as the end
  max_steps,     // the step budget ran out
  failed,        // a step failed below the smallest allowed step
  interrupted,   // the run driver ended the run on a signal (SIGINT, SIGTERM)
};
const char* outcome_name(Outcome o);

struct ContinuationResult {
  Outcome outcome = Outcome::failed;
  double t_reached = 0;
  int steps = 0;
  int total_iterations = 0;  // including failed attempts
  int failed_attempts = 0;   // attempts that did not converge (each retried smaller, or the run's end)
  // Newton's local first updates (NewtonOptions::local_share; load stepping only), failed attempts' and
  // those taken back included
  int local_updates = 0;
  // Converged attempts discarded because they crossed a model event in a step longer than the event
  // tolerance (load stepping: StepControl::event_tolerance), each retried shorter
  int withdrawn_attempts = 0;
  std::string message;
  // Completed runs: the end, a stop rule, or a limit point the case declared acceptable.
  bool completed() const { return outcome == Outcome::reached_end || outcome == Outcome::stopped ||
                                  outcome == Outcome::limit_point; }
};

// Called after every converged step with its report and the converged unknowns; false stops the run.
using StepCallback = std::function<bool(const StepReport&, const Eigen::VectorXd&)>;

// The state a method needs to continue after a restart, as named arrays (written to checkpoints).
using MethodState = std::map<std::string, std::vector<double>>;

class ContinuationMethod {
 public:
  virtual ~ContinuationMethod() = default;
  virtual std::string name() const = 0;
  // Brings q to the state the method starts from, before the run's initial state is reported (e.g. a
  // static equilibrium that a dynamic run starts from); run() calls it if the caller has not. Returns
  // false with `failure` set when that state cannot be found. Default: q as given.
  virtual bool prepare(NonlinearSystem& /*sys*/, Eigen::VectorXd& /*q*/, LinearSolver& /*solver*/,
                       std::string& /*failure*/) {
    return true;
  }
  // Marches from (q, t) = (q, start time) until the end, the callback stops it, or it fails. After each
  // converged step: sys.accept(q, t), then on_step. q holds the last converged state on return.
  virtual ContinuationResult run(NonlinearSystem& sys, Eigen::VectorXd& q, LinearSolver& solver,
                                 const StepCallback& on_step) = 0;
  // Support forces at the constrained DOFs of the last converged step that replace the residual's, where
  // the method computes its own (time integration: inertia included); nullptr where the residual's hold.
  virtual const Eigen::VectorXd* reactions() const { return nullptr; }
  // Restart support: the state after the last converged step, and its restoration before run().
  virtual MethodState save() const { return {}; }
  virtual void restore(const MethodState& /*state*/) {}
};

}  // namespace fibrane::solve
