#include "path/generalized_alpha.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "common/error.hpp"
#include "common/format.hpp"
#include "linalg/linear_solver.hpp"

namespace fibrane::solve {

GeneralizedAlphaParameters GeneralizedAlphaParameters::chung_hulbert(double rho_inf) {
  if (!(rho_inf >= 0.0 && rho_inf <= 1.0))
    throw InputError("generalized-alpha: the spectral radius rho_inf must lie in [0, 1], got " + format_number(rho_inf));
  GeneralizedAlphaParameters p;
  // Chung & Hulbert 1993, Eqs. (25), (17), (20).
  p.alpha_m = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0);
  p.alpha_f = rho_inf / (rho_inf + 1.0);
  p.gamma = 0.5 - p.alpha_m + p.alpha_f;
  p.beta = 0.25 * (1.0 - p.alpha_m + p.alpha_f) * (1.0 - p.alpha_m + p.alpha_f);
  return p;
}

void check_parameters(const GeneralizedAlphaParameters& p) {
  const double eps = 1e-12;
  if (!(std::abs(p.gamma - (0.5 - p.alpha_m + p.alpha_f)) <= eps))
    throw InputError("generalized-alpha: gamma = 1/2 - alpha_m + alpha_f is needed for second-order accuracy");
  // Chung & Hulbert 1993, Sec. 3: unconditional stability for linear problems.
  if (!(p.alpha_m <= p.alpha_f + eps && p.alpha_f <= 0.5 + eps && p.beta >= 0.25 + 0.5 * (p.alpha_f - p.alpha_m) - eps))
    throw InputError("generalized-alpha: unconditional stability needs alpha_m <= alpha_f <= 1/2 and "
                     "beta >= 1/4 + (alpha_f - alpha_m)/2");
}

void check_transient_options(const TransientOptions& o) {
  check_parameters(o.parameters);
  if (!(o.mass_damping >= 0.0))
    throw InputError("generalized-alpha: the mass-proportional damping coefficient must be >= 0");
  if (!(o.error_tolerance >= 0.0)) throw InputError("generalized-alpha: error_tolerance must be >= 0");
  if (!(o.energy_tolerance >= 0.0)) throw InputError("generalized-alpha: energy_tolerance must be >= 0");
}

namespace {

// T x for a reduced vector x (the homogeneous part of u = T q + g).
Eigen::VectorXd apply_t(const ConstraintSet& cs, const Eigen::VectorXd& x) {
  Eigen::VectorXd out(cs.num_dofs());
  for (int d = 0; d < cs.num_dofs(); ++d) {
    double value = 0.0;
    for (const auto& [i, coef] : cs.expansion(d)) value += coef * x[i];
    out[d] = value;
  }
  return out;
}

// The step's Newton system: the transient system's residual plus a constant reduced vector (the
// alpha_f / (1 - alpha_f) T^T r(u_n, t_n) term of the force-averaged balance).
class StepSystem final : public NonlinearSystem {
 public:
  StepSystem(TransientSystem& sys, Eigen::VectorXd shift) : sys_(sys), shift_(std::move(shift)) {}
  int size() const override { return sys_.size(); }
  void evaluate(const Eigen::VectorXd& q, double t, bool with_tangent) override {
    sys_.evaluate(q, t, with_tangent);
    if (shift_.size() > 0) residual_ = sys_.residual() + shift_;
  }
  const Eigen::VectorXd& residual() const override { return shift_.size() > 0 ? residual_ : sys_.residual(); }
  const Eigen::SparseMatrix<double>& tangent() const override { return sys_.tangent(); }
  bool tangent_finite() const override { return sys_.tangent_finite(); }
  Eigen::VectorXd tangent_times(const Eigen::VectorXd& x) const override { return sys_.tangent_times(x); }
  bool distributed() const override { return sys_.distributed(); }
  void unite_flags(std::vector<char>& flags) const override { sys_.unite_flags(flags); }
  Eigen::SparseMatrix<double> sum_over_processes(Eigen::SparseMatrix<double> part) const override {
    return sys_.sum_over_processes(std::move(part));
  }
  const Eigen::VectorXd& load_derivative() const override { return sys_.load_derivative(); }
  int pattern_version() const override { return sys_.pattern_version(); }
  bool symmetric() const override { return sys_.symmetric(); }
  std::optional<std::vector<int>> skew_candidates() const override { return sys_.skew_candidates(); }
  double residual_scale() const override { return sys_.residual_scale(); }
  std::string failure_hint() const override { return sys_.failure_hint(); }

 private:
  TransientSystem& sys_;
  Eigen::VectorXd shift_, residual_;
};

Eigen::VectorXd or_zero(const Eigen::VectorXd& x, Eigen::Index n, const char* what) {
  if (x.size() == 0) return Eigen::VectorXd::Zero(n);
  if (x.size() != n)
    throw InputError(std::string("generalized-alpha: ") + what + " has " + std::to_string(x.size()) +
                     " entries instead of " + std::to_string(n));
  return x;
}

std::vector<double> to_vector(const Eigen::VectorXd& x) { return std::vector<double>(x.data(), x.data() + x.size()); }

Eigen::VectorXd from_vector(const std::vector<double>& x) {
  return Eigen::Map<const Eigen::VectorXd>(x.data(), static_cast<Eigen::Index>(x.size()));
}

StepReport step_report(int step, double t, double dt, int cutbacks, const NewtonReport& newton, const EnergyReport& energy) {
  StepReport r;
  r.step = step;
  r.t = t;
  r.dt = dt;
  r.iterations = newton.iterations;
  r.residual_norm = newton.residual_norm;
  r.cutbacks = cutbacks;
  r.history = newton.history;
  r.negative_eigenvalues = newton.negative_eigenvalues;
  r.energy = energy;
  return r;
}

}  // namespace

GeneralizedAlpha::GeneralizedAlpha(StepControl control, NewtonOptions newton, TransientOptions options)
    : control_(control), newton_(std::move(newton)), options_(std::move(options)) {
  check_step_control(control_);
  check_transient_options(options_);
}

void GeneralizedAlpha::start(TransientSystem& sys, const Eigen::VectorXd& q) {
  TransientState& s = state_;
  const double a_m = options_.mass_damping;
  const ConstraintSet& cs = sys.constraint_set();
  sys.begin_step(nullptr);
  sys.evaluate(q, control_.t_start, false);
  s.t = control_.t_start;
  s.u = sys.displacement();
  s.residual = sys.full_residual();
  s.external_force = sys.external_force();
  const Eigen::VectorXd g_rate = sys.prescribed_motion(s.t, 1), g_second = sys.prescribed_motion(s.t, 2);
  s.v = apply_t(cs, or_zero(options_.initial_velocity, cs.num_free(), "the initial velocity")) + g_rate;
  s.mass_velocity = sys.mass_times(s.v);
  s.a = g_second;
  if (options_.start == TransientOptions::Start::solve) {
    // T^T M T q''_0 = -T^T (r_0 + C v_0 + M g''_0), a_0 = T q''_0 + g''_0.
    const Eigen::VectorXd rhs = -cs.restrict_vector(s.residual + a_m * s.mass_velocity + sys.mass_times(g_second));
    auto mass_solver = make_linear_solver("auto", true);
    const Eigen::SparseMatrix<double>& m = sys.reduced_mass();
    mass_solver->analyze(m);
    if (!mass_solver->factorize(m))
      throw InputError("generalized-alpha: the reduced mass matrix is singular (a free DOF without mass?); "
                       "start at rest to skip the initial acceleration");
    s.a += apply_t(cs, mass_solver->solve(rhs));
  }
  s.reaction = sys.mass_times(s.a) + a_m * s.mass_velocity + s.residual;
  s.energy = EnergyReport{};
  s.energy.kinetic = 0.5 * s.v.dot(s.mass_velocity);
}

void GeneralizedAlpha::set_step(TransientSystem& sys, double t_new) {
  const GeneralizedAlphaParameters& p = options_.parameters;
  const TransientState& s = state_;
  const double dt = t_new - s.t, a_m = options_.mass_damping;
  for (int k = 0; k < 3; ++k) {
    g_old_[k] = sys.prescribed_motion(s.t, k);
    g_new_[k] = sys.prescribed_motion(t_new, k);
  }
  const Eigen::VectorXd h = s.u - g_old_[0], h_rate = s.v - g_old_[1], h_second = s.a - g_old_[2];
  // Reference point h_{n+1} = h_n; w is affine in u with slope mass_factor (StepKinematics).
  u_ref_ = g_new_[0] + h;
  const Eigen::VectorXd h_second_ref = newmark_acceleration<Eigen::VectorXd>(p, dt, h, h_rate, h_second, h);
  const Eigen::VectorXd h_rate_ref = newmark_velocity<Eigen::VectorXd>(p, dt, h_rate, h_second, h_second_ref);
  const Eigen::VectorXd a_w = weighted<Eigen::VectorXd>(p.alpha_m, h_second, h_second_ref) +
                              weighted<Eigen::VectorXd>(p.alpha_f, g_old_[2], g_new_[2]);
  const Eigen::VectorXd v_w = weighted<Eigen::VectorXd>(p.alpha_f, s.v, h_rate_ref + g_new_[1]);
  w_ref_ = (a_w + a_m * v_w) / (1.0 - p.alpha_f);
  step_ = StepKinematics{s.t, t_new, dt,
                         inertia_tangent_factor(p, dt) + a_m * damping_tangent_factor(p, dt), &u_ref_, &w_ref_};
  sys.begin_step(&step_);
}

NewtonReport GeneralizedAlpha::solve_step(TransientSystem& sys, double t_new, Eigen::VectorXd& q_trial,
                                          LinearSolver& solver) {
  set_step(sys, t_new);
  const TransientState& s = state_;
  const double dt = step_.dt;
  const ConstraintSet& cs = sys.constraint_set();
  // Predictor for h_{n+1} (q is the free part of h).
  q_trial = control_.predictor_order > 0 ? cs.free_values(u_ref_ + dt * (s.v - g_old_[1]) + 0.5 * dt * dt * (s.a - g_old_[2]))
                                             : cs.free_values(u_ref_);
  const double alpha_f = options_.parameters.alpha_f;
  Eigen::VectorXd shift;
  if (alpha_f != 0.0) shift = alpha_f / (1.0 - alpha_f) * cs.restrict_vector(s.residual);
  StepSystem step_system(sys, std::move(shift));
  return newton_solve(step_system, q_trial, t_new, newton_, solver);
}

TransientState GeneralizedAlpha::advanced(TransientSystem& sys, double t_new) const {
  const GeneralizedAlphaParameters& p = options_.parameters;
  const double dt = step_.dt, a_m = options_.mass_damping;
  const TransientState& s = state_;
  TransientState next;
  next.t = t_new;
  next.u = sys.displacement();
  next.external_force = sys.external_force();
  const Eigen::VectorXd h = s.u - g_old_[0], h_rate = s.v - g_old_[1], h_second = s.a - g_old_[2];
  const Eigen::VectorXd h_new = next.u - g_new_[0];
  const Eigen::VectorXd h_second_new = newmark_acceleration<Eigen::VectorXd>(p, dt, h, h_rate, h_second, h_new);
  next.v = newmark_velocity<Eigen::VectorXd>(p, dt, h_rate, h_second, h_second_new) + g_new_[1];
  next.a = h_second_new + g_new_[2];
  // The system's full residual is r + M w(u_{n+1}) (TransientSystem); r alone enters the next step.
  next.residual = sys.full_residual() - sys.mass_times(step_.inertia(next.u));
  next.mass_velocity = sys.mass_times(next.v);
  const Eigen::VectorXd a_end = acceleration_at_end<Eigen::VectorXd>(p, h_second, h_second_new) + g_new_[2];
  next.reaction = sys.mass_times(a_end) + a_m * next.mass_velocity + next.residual;
  // Energy account: trapezoidal rule on the integrals of F . du (generalized_alpha.hpp).
  const Eigen::VectorXd du = next.u - s.u, dg = g_new_[0] - g_old_[0];
  next.energy = s.energy;
  next.energy.external_work += 0.5 * du.dot(s.external_force + next.external_force);
  next.energy.prescribed_work += 0.5 * dg.dot(s.reaction + next.reaction);
  next.energy.damping += 0.5 * a_m * du.dot(s.mass_velocity + next.mass_velocity);
  next.energy.kinetic = 0.5 * next.v.dot(next.mass_velocity);
  return next;
}

double GeneralizedAlpha::energy_balance(const TransientSystem& sys, const TransientState& s) {
  const EnergyReport& e = s.energy;
  return e.kinetic + sys.stored_energy() - e.external_work - e.prescribed_work + e.damping;
}

double GeneralizedAlpha::error_factor(const TransientState& next, double balance, double dt) const {
  // Both measures scale like dt^3 per step: eta with the third derivative of u, the balance's change with
  // the trapezoidal quadrature of the work integrals.
  const auto factor = [](double tol, double measure) {
    return measure > 0.0 ? 0.9 * std::cbrt(tol / measure) : std::numeric_limits<double>::infinity();
  };
  double f = 1.0;
  bool controlled = false;
  if (const double tol = options_.error_tolerance; tol > 0.0) {
    const double beta = options_.parameters.beta;
    const double error = std::abs(beta - 1.0 / 6.0) * dt * dt * (next.a - state_.a).norm();
    const double scale = std::max({next.u.norm(), largest_displacement_, std::numeric_limits<double>::min()});
    f = factor(tol, error / scale);
    controlled = true;
  }
  if (const double tol = options_.energy_tolerance; tol > 0.0 && std::isfinite(balance)) {
    const double g = factor(tol, std::abs(balance - balance_));
    f = controlled ? std::min(f, g) : g;
  }
  return f;
}

bool GeneralizedAlpha::prepare(NonlinearSystem& base, Eigen::VectorXd& q, LinearSolver& solver, std::string& failure) {
  prepared_ = true;
  if (restored_ || options_.start != TransientOptions::Start::static_equilibrium) return true;
  auto* sys = dynamic_cast<TransientSystem*>(&base);
  if (!sys) throw std::invalid_argument("generalized_alpha: the system has no inertia (not a TransientSystem)");
  sys->begin_step(nullptr);
  const NewtonReport statics = newton_solve(*sys, q, control_.t_start, newton_, solver);
  if (!statics.converged) {
    failure = "the static equilibrium at t = " + format_number(control_.t_start) +
              " (dynamics.start: static) was not found: " + statics.failure;
    return false;
  }
  sys->accept(q, control_.t_start);
  return true;
}

ContinuationResult GeneralizedAlpha::run(NonlinearSystem& base, Eigen::VectorXd& q, LinearSolver& solver,
                                         const StepCallback& on_step) {
  auto* sys = dynamic_cast<TransientSystem*>(&base);
  if (!sys) throw std::invalid_argument("generalized_alpha: the system has no inertia (not a TransientSystem)");
  if (q.size() != sys->size()) throw std::invalid_argument("generalized_alpha: q has the wrong size");
  const StepControl& sc = control_;
  if (!restored_) {
    if (std::string failure; !prepared_ && !prepare(*sys, q, solver, failure)) {
      ContinuationResult failed;
      failed.outcome = Outcome::failed;
      failed.t_reached = control_.t_start;
      failed.message = failure;
      return failed;
    }
    start(*sys, q);
    largest_displacement_ = state_.u.norm();
    balance_ = energy_balance(*sys, state_);
    dt_ = std::min(sc.dt_initial, sc.dt_max);
    steps_ = 0;
  } else if (state_.u.size() != sys->constraint_set().num_dofs()) {
    throw InputError("generalized-alpha: the restored state does not fit the model's DOFs");
  }
  restored_ = prepared_ = false;
  ContinuationResult res;
  res.t_reached = state_.t;
  res.steps = steps_;
  const double t_eps = 1e-12 * std::max(1.0, std::abs(sc.t_end));  // round-off in sums of dt
  while (sc.t_end - state_.t > t_eps) {
    if (res.steps >= sc.max_steps) {
      res.outcome = Outcome::max_steps;
      res.message = "stopped after max_steps = " + std::to_string(sc.max_steps) + " steps";
      return res;
    }
    double dt_try = std::min(dt_, sc.t_end - state_.t), t_new = state_.t;
    int cutbacks = 0;
    NewtonReport newton;
    Eigen::VectorXd q_trial;
    TransientState next;
    double error_growth = 1.0, next_balance = 0.0;
    for (;;) {
      t_new = (sc.t_end - (state_.t + dt_try) <= t_eps) ? sc.t_end : state_.t + dt_try;
      newton = solve_step(*sys, t_new, q_trial, solver);
      res.total_iterations += newton.iterations;
      double factor = sc.cutback;
      if (newton.converged) {
        next = advanced(*sys, t_new);
        next_balance = energy_balance(*sys, next);
        error_growth = error_factor(next, next_balance, step_.dt);
        if (error_growth >= 1.0 || dt_try <= sc.dt_min) break;
        factor = std::max(sc.cutback, error_growth);
        newton.failure = "local error estimate above error_tolerance";
      }
      if (newton_.verbose)
        std::fprintf(stderr, "step to t=%.6g dt=%.3g failed: %s; cutting back\n", t_new, dt_try, newton.failure.c_str());
      sys->reject();
      ++cutbacks;
      ++res.failed_attempts;
      dt_try = std::max(dt_try * factor, newton.converged ? sc.dt_min : 0.0);
      if (dt_try < sc.dt_min) {
        sys->begin_step(nullptr);
        res.outcome = Outcome::failed;
        res.message = "time step from t = " + format_number(state_.t) + " failed with dt below dt_min = " +
                      format_number(sc.dt_min) + ": " + newton.failure;
        if (const std::string hint = sys->failure_hint(); !hint.empty()) res.message += ". " + hint;
        return res;
      }
    }
    const double t_old = state_.t;
    state_ = std::move(next);
    largest_displacement_ = std::max(largest_displacement_, state_.u.norm());
    balance_ = next_balance;
    sys->begin_step(nullptr);
    q = q_trial;
    steps_ = ++res.steps;
    res.t_reached = state_.t;
    double growth = (cutbacks == 0 && newton.iterations <= sc.easy_iterations) ? sc.growth : 1.0;
    if (options_.error_tolerance > 0.0 || options_.energy_tolerance > 0.0) growth = std::min(sc.growth, error_growth);
    dt_ = std::min(dt_try * growth, sc.dt_max);
    sys->accept(q, state_.t);
    if (on_step && !on_step(step_report(res.steps, state_.t, state_.t - t_old, cutbacks, newton, state_.energy), q)) {
      res.outcome = Outcome::stopped;
      res.message = "stopped by the step callback at t = " + format_number(state_.t);
      return res;
    }
  }
  res.outcome = Outcome::reached_end;
  res.message = "reached t_end = " + format_number(sc.t_end);
  return res;
}

MethodState GeneralizedAlpha::save() const {
  const TransientState& s = state_;
  MethodState m;
  m["t"] = {s.t};
  m["dt"] = {dt_};
  m["largest_displacement"] = {largest_displacement_};
  m["balance"] = {balance_};
  m["steps"] = {static_cast<double>(steps_)};
  m["u"] = to_vector(s.u);
  m["v"] = to_vector(s.v);
  m["a"] = to_vector(s.a);
  m["residual"] = to_vector(s.residual);
  m["external_force"] = to_vector(s.external_force);
  m["reaction"] = to_vector(s.reaction);
  m["mass_velocity"] = to_vector(s.mass_velocity);
  m["energy"] = {s.energy.kinetic, s.energy.external_work, s.energy.prescribed_work, s.energy.damping};
  return m;
}

void GeneralizedAlpha::restore(const MethodState& m) {
  TransientState s;
  s.t = m.at("t").at(0);
  s.u = from_vector(m.at("u"));
  s.v = from_vector(m.at("v"));
  s.a = from_vector(m.at("a"));
  s.residual = from_vector(m.at("residual"));
  s.external_force = from_vector(m.at("external_force"));
  s.reaction = from_vector(m.at("reaction"));
  s.mass_velocity = from_vector(m.at("mass_velocity"));
  const std::vector<double>& e = m.at("energy");
  s.energy = EnergyReport{e.at(0), e.at(1), e.at(2), e.at(3)};
  for (const Eigen::VectorXd* x : {&s.v, &s.a, &s.residual, &s.external_force, &s.reaction, &s.mass_velocity})
    if (x->size() != s.u.size()) throw InputError("generalized-alpha: inconsistent restart state (vector sizes differ)");
  state_ = std::move(s);
  dt_ = m.at("dt").at(0);
  largest_displacement_ = m.count("largest_displacement") ? m.at("largest_displacement").at(0) : state_.u.norm();
  balance_ = m.count("balance") ? m.at("balance").at(0) : 0.0;
  steps_ = static_cast<int>(m.at("steps").at(0));
  restored_ = true;
}

}  // namespace fibrane::solve
