#pragma once
// Implicit time integration by the generalized-alpha method in its force-averaged form (solve/newmark.hpp
// gives the literature). Inertia is a contribution of the model on the full displacement vector; this
// method tells the model each step's integration constants (StepKinematics), solves the step by Newton,
// advances the kinematic state and keeps the energy account.
//
// The full displacement is u = h + g(t), h = T q (constraints.hpp). Newmark's relations act on h only;
// the prescribed part g and its derivatives are exact (TransientSystem::prescribed_motion):
//   h''_{n+1} = (h_{n+1} - h_n - dt h'_n) / (beta dt^2) - (1/(2 beta) - 1) h''_n
//   h'_{n+1}  = h'_n + dt ((1 - gamma) h''_n + gamma h''_{n+1}),      v = h' + g',  a = h'' + g''.
// The step equation for q_{n+1} (reactions R_w at constrained DOFs, removed by T^T):
//   T^T [ M a_w + C v_w + (1 - alpha_f) r(u_{n+1}, t_{n+1}) + alpha_f r(u_n, t_n) ] = 0,
//   a_w = (1 - alpha_m) h''_{n+1} + alpha_m h''_n + (1 - alpha_f) g''(t_{n+1}) + alpha_f g''(t_n),
//   v_w = (1 - alpha_f) v_{n+1} + alpha_f v_n,     C = a_M M (mass-proportional Rayleigh damping),
// i.e. the inertia of the prescribed motion is averaged like a load. For a linear model this is Chung &
// Hulbert's scheme for the reduced equations T^T M T q'' + T^T C T q' + T^T K T q = F(t) with F
// interpolated linearly in time. (Newmark's relations applied to prescribed DOFs instead would give them
// an acceleration error growing like t for the trapezoidal rule, which consistent masses pass on to the
// free DOFs.) Divided by (1 - alpha_f):
//   T^T [ r(u_{n+1}, t_{n+1}) + M w(u_{n+1}) ] + alpha_f / (1 - alpha_f) T^T r(u_n, t_n) = 0,
//   w = (a_w + a_M v_w) / (1 - alpha_f),
// the bracket being the system's residual (TransientSystem), the last term a constant this method adds.
#include <limits>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include "linalg/constraints.hpp"
#include "path/continuation.hpp"
#include "path/load_stepping.hpp"
#include "path/newmark.hpp"

namespace fibrane::solve {

// A NonlinearSystem with inertia. Its residual and tangent depend on the step set by begin_step():
//   static (no step set):  full residual r(u, t) = f_int - f_ext,    tangent T^T K T;
//   step k set:            full residual r(u, t) + M k.inertia(u),   tangent T^T (K + k.mass_factor M) T,
// u = T q + g(t) the FULL displacement, prescribed DOFs included. M is the constant, symmetric mass matrix
// on the full DOF vector; the reduced mass T^T M T must be positive definite.
class TransientSystem : public NonlinearSystem {
 public:
  // Sets the step the following evaluate() calls belong to (nullptr: static). *step stays valid until the
  // next call.
  virtual void begin_step(const StepKinematics* step) = 0;
  // The elimination u = T q + g(t) behind the reduced vectors.
  virtual const ConstraintSet& constraint_set() const = 0;
  // The prescribed part g(t) (order 0) and its first and second time derivatives (order 1, 2), full
  // vectors, zero at free DOFs. The load functions behind them must be twice differentiable in time.
  virtual Eigen::VectorXd prescribed_motion(double t, int order) const = 0;
  // Full vectors of the last evaluate(): u, the residual as defined above (at constrained DOFs the force the
  // supports supply), and the external force f_ext alone (same sign as in r = f_int - f_ext).
  virtual const Eigen::VectorXd& displacement() const = 0;
  virtual const Eigen::VectorXd& full_residual() const = 0;
  virtual const Eigen::VectorXd& external_force() const = 0;
  // M x for a full vector x. Must not change the results of the last evaluate().
  virtual Eigen::VectorXd mass_times(const Eigen::VectorXd& x) const = 0;
  // The energy stored by the internal forces at the last evaluate() (strain and interaction energy: the
  // potential whose gradient is f_int); NaN if the system does not know it (no energy_tolerance then).
  virtual double stored_energy() const { return std::numeric_limits<double>::quiet_NaN(); }
  // The reduced mass T^T M T, for the initial acceleration. May overwrite the last evaluate()'s results;
  // the reference is read before the next evaluate().
  virtual const Eigen::SparseMatrix<double>& reduced_mass() = 0;
};

// How the run starts and what it integrates, besides the step control.
struct TransientOptions {
  GeneralizedAlphaParameters parameters;  // default-constructed: the trapezoidal rule
  double mass_damping = 0.0;              // a_M >= 0 in C = a_M M
  // Initial acceleration: `solve` takes it from the balance at t_start, T^T M T q''_0 = -T^T (r(u_0, t_0) +
  // C v_0 + M g''(t_0)) (one factorisation of the reduced mass); `rest` sets q''_0 = 0, correct only for
  // a start in equilibrium (r(u_0, t_0) = 0 at the free DOFs, v_0 = 0, g'' = 0); `static_equilibrium`
  // first solves the static problem r(u_0, t_0) = 0 by Newton from the given q (a body released from its
  // static equilibrium, e.g. a fiber hanging in the attraction of a membrane), then takes q''_0 as `solve`.
  enum class Start { solve, rest, static_equilibrium } start = Start::solve;
  // The reduced initial velocity q'_0 (empty: zero); v_0 = T q'_0 + g'(t_0).
  Eigen::VectorXd initial_velocity;
  // > 0: the step size follows the local error estimate of Zienkiewicz & Xie (1991, Earthquake Eng. Struct.
  // Dyn. 20, 871-887), e = (beta - 1/6) dt^2 (a_{n+1} - a_n), measured as eta = |e| / max_k |u_k| (full
  // vectors, Euclidean norms; the largest displacement of the run so far, so that a motion through u = 0
  // does not inflate eta). A converged step with eta > error_tolerance is rejected and retried with
  // dt * max(cutback, 0.9 (tol / eta)^(1/3)) (down to dt_min); an accepted one sets the next dt to
  // dt * min(growth, 0.9 (tol / eta)^(1/3)), at most dt_max. 0: the step size follows Newton alone.
  double error_tolerance = 0.0;
  // > 0: also bounds the change of the energy balance E_kin + E_stored - W_ext - W_prescribed + D in one step
  // (absolute, in energy units; TransientSystem::stored_energy): a converged step that changes it by
  // delta > energy_tolerance is retried with dt * max(cutback, 0.9 (tol / delta)^(1/3)), and the next dt is
  // limited likewise. The balance then drifts by at most energy_tolerance per step. 0: off.
  double energy_tolerance = 0.0;
};

// Throws InputError for invalid parameters (check_parameters) or a_M < 0. (An initial velocity of the wrong
// size is refused at run().)
void check_transient_options(const TransientOptions& o);

// The kinematic state after the last converged step (or at the start), full vectors.
struct TransientState {
  double t = 0;
  // Full vectors; a = h'' + g'', h'' being the method's acceleration variable (acceleration_at_end).
  Eigen::VectorXd u, v, a;
  Eigen::VectorXd residual;        // r(u, t) = f_int - f_ext, without inertia
  Eigen::VectorXd external_force;  // f_ext(u, t)
  // M a(t) + C v + r with the acceleration at t to second order (h'' by acceleration_at_end): at
  // constrained DOFs the support reactions, at free DOFs the equilibrium defect of the scheme at t (zero
  // for the trapezoidal rule, O(dt^2) otherwise).
  Eigen::VectorXd reaction;
  Eigen::VectorXd mass_velocity;   // M v
  EnergyReport energy;
};

// Generalized-alpha time stepping from t_start to t_end with the step control of load stepping: fixed steps
// (dt_initial = dt_max, growth = 1) or adaptive ones (a step whose Newton iteration fails is retried with
// dt * cutback, down to dt_min; a step converged in at most easy_iterations lets dt grow by `growth` up to
// dt_max), optionally also by the local error estimate (TransientOptions::error_tolerance). StepControl::predictor_order > 0 (`extrapolate: true`) selects the predictor h_{n+1} = h_n + dt h'_n + dt^2/2 h''_n (otherwise h_n).
// Never steps past t_end. stop_at_limit_point is ignored: a dynamic run has no limit point.
//
// Energy account per step (Delta x = x_{n+1} - x_n, bar x = (x_n + x_{n+1}) / 2, full vectors):
//   external_work   += Delta u . bar f_ext
//   prescribed_work += Delta g . bar reaction
//   damping         += Delta u . C bar v
//   kinetic          = v^T M v / 2
// i.e. the trapezoidal rule on the integrals of F . du. For the trapezoidal rule (and rho_inf = 1) on a
// linear model whose prescribed motion is at most linear in time this closes the balance exactly
// (Delta u . M bar a = Delta E_kin identically); otherwise the remainder is the algorithmic dissipation
// plus the quadrature error, O(dt^2) for resolved motion.
class GeneralizedAlpha final : public ContinuationMethod {
 public:
  GeneralizedAlpha(StepControl control, NewtonOptions newton, TransientOptions options);
  std::string name() const override { return "generalized_alpha"; }
  // sys must be a TransientSystem (std::invalid_argument otherwise). Starts from (q, t_start) unless
  // restore() was called since the last run(). Every StepReport carries the energy account.
  // With Start::static_equilibrium: Newton for r(q, t_start) = 0 (once; a restored run skips it).
  bool prepare(NonlinearSystem& sys, Eigen::VectorXd& q, LinearSolver& solver, std::string& failure) override;
  ContinuationResult run(NonlinearSystem& sys, Eigen::VectorXd& q, LinearSolver& solver,
                         const StepCallback& on_step) override;
  MethodState save() const override;
  void restore(const MethodState& state) override;
  // After run(): the state of the last converged step.
  const TransientState& state() const { return state_; }
  const Eigen::VectorXd* reactions() const override { return &state_.reaction; }

 private:
  // The state at t_start (initial acceleration as TransientOptions::start says).
  void start(TransientSystem& sys, const Eigen::VectorXd& q);
  // Sets the step from state_ to t_new in the system (prescribed motion at both ends, u_ref, w_ref).
  void set_step(TransientSystem& sys, double t_new);
  // Solves the step from state_ to t_new; on success q_trial holds q_{n+1}.
  NewtonReport solve_step(TransientSystem& sys, double t_new, Eigen::VectorXd& q_trial, LinearSolver& solver);
  // The state at t_new from the converged step (the system's last evaluate()).
  TransientState advanced(TransientSystem& sys, double t_new) const;
  // The factor of dt that the local error estimate and the energy balance of the step from state_ to `next`
  // (balance: next's energy balance) ask for (> 1: may grow; < 1: the step is too long); 1 without control.
  double error_factor(const TransientState& next, double balance, double dt) const;
  // E_kin + E_stored - W_ext - W_prescribed + D of a state whose configuration the system evaluated last.
  static double energy_balance(const TransientSystem& sys, const TransientState& s);

  StepControl control_;
  NewtonOptions newton_;
  TransientOptions options_;
  TransientState state_;
  // The step set in the system during solve_step, with the vectors it points to and the prescribed motion
  // at the step's ends (g, g', g'' at index 0, 1, 2).
  StepKinematics step_;
  Eigen::VectorXd u_ref_, w_ref_;
  Eigen::VectorXd g_old_[3], g_new_[3];
  double dt_ = 0;         // size of the next step
  double largest_displacement_ = 0;  // max |u| over the converged states (error_tolerance's scale)
  double balance_ = 0;               // the energy balance of state_ (energy_tolerance)
  int steps_ = 0;
  bool restored_ = false, prepared_ = false;
};

}  // namespace fibrane::solve
