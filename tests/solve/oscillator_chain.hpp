#pragma once
// Test model for time integration: a 1-D chain of DOFs joined by springs with the Duffing law
// N(e) = k e + k3 e^3 (energy k e^2/2 + k3 e^4/4), each spring carrying a bar mass (consistent mass
// m/6 [2 1; 1 2]) and each DOF a point mass; prescribed motion, multi-point constraints and point loads
// through the real ConstraintSet and SparseAssembler. It implements TransientSystem the way a model is
// meant to: per element, M_e w_e added to the residual and mass_factor M_e to the tangent.
// Also a reference solution: the reduced equations of motion integrated by classical Runge-Kutta.
#include <cmath>
#include <functional>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "linalg/assembler.hpp"
#include "linalg/constraints.hpp"
#include "path/generalized_alpha.hpp"
#include "linalg/linear_solver.hpp"

namespace fibrane::solve::testing {

// A load / prescribed-motion function of time and its first two derivatives.
struct TimeFunction {
  std::function<double(double)> value, rate, second;
};

struct ChainSpring {
  int a, b;
  double k = 1.0, k3 = 0.0;  // N(e) = k e + k3 e^3, e = u_b - u_a
  double mass = 0.0;         // bar mass, consistent
};

struct ChainLoad {
  int dof;
  double value;
  int curve = -1;  // -1: constant
};

class OscillatorChain : public TransientSystem {
 public:
  OscillatorChain(std::vector<double> point_masses, std::vector<ChainSpring> springs, ConstraintSet constraints,
                  std::vector<ChainLoad> loads = {}, std::vector<TimeFunction> curves = {})
      : point_masses_(std::move(point_masses)), springs_(std::move(springs)), constraints_(std::move(constraints)),
        loads_(std::move(loads)), curves_(std::move(curves)) {
    const int n = static_cast<int>(point_masses_.size());
    constraints_.finalize(n);
    std::vector<std::vector<int>> element_dofs;
    for (const ChainSpring& s : springs_) element_dofs.push_back({s.a, s.b});
    for (int d = 0; d < n; ++d) element_dofs.push_back({d});
    assembler_.set_pattern(constraints_, element_dofs);
  }

  // NonlinearSystem
  int size() const override { return constraints_.num_free(); }
  void evaluate(const Eigen::VectorXd& q, double t, bool with_tangent) override {
    u_ = constraints_.expand(q, t, curve_eval());
    assembler_.begin(with_tangent);
    for (int e = 0; e < num_elements(); ++e) {
      const std::vector<int> dofs = element_dofs(e);
      Eigen::VectorXd r;
      Eigen::MatrixXd k;
      element_response(e, u_, r, k);
      if (step_) {  // inertia: M_e w_e, tangent factor times M_e
        const Eigen::MatrixXd m = element_mass(e);
        Eigen::VectorXd w(static_cast<Eigen::Index>(dofs.size()));
        for (size_t i = 0; i < dofs.size(); ++i) w[static_cast<Eigen::Index>(i)] = step_->inertia(dofs[i], u_[dofs[i]]);
        r += m * w;
        k += step_->mass_factor * m;
      }
      assembler_.add(e, r, with_tangent ? &k : nullptr);
    }
    f_ext_ = external_force_at(t);
    for (const ChainLoad& load : loads_) {  // r = internal - external
      const int dof[1] = {load.dof};
      assembler_.add_vector(dof, Eigen::VectorXd::Constant(1, -load.value * curve(load.curve, t)));
    }
    assembler_.end();
    ++evaluations_;
  }
  const Eigen::VectorXd& residual() const override { return assembler_.reduced_residual(); }
  const Eigen::SparseMatrix<double>& tangent() const override { return assembler_.matrix(); }
  int pattern_version() const override { return assembler_.pattern_version(); }
  void accept(const Eigen::VectorXd&, double) override { ++accepted_; }
  void reject() override { ++rejected_; }

  // TransientSystem
  void begin_step(const StepKinematics* step) override { step_ = step; }
  const ConstraintSet& constraint_set() const override { return constraints_; }
  const Eigen::VectorXd& displacement() const override { return u_; }
  const Eigen::VectorXd& full_residual() const override { return assembler_.full_residual(); }
  const Eigen::VectorXd& external_force() const override { return f_ext_; }
  Eigen::VectorXd mass_times(const Eigen::VectorXd& x) const override { return dense_mass() * x; }
  // Spring energy k e^2 / 2 + k3 e^4 / 4 at the last evaluate().
  double stored_energy() const override {
    double energy = 0.0;
    for (const ChainSpring& sp : springs_) {
      const double e = u_[sp.b] - u_[sp.a];
      energy += 0.5 * sp.k * e * e + 0.25 * sp.k3 * e * e * e * e;
    }
    return energy;
  }
  const Eigen::SparseMatrix<double>& reduced_mass() override {
    assembler_.begin(true);
    for (int e = 0; e < num_elements(); ++e) {
      const Eigen::MatrixXd m = element_mass(e);
      assembler_.add(e, Eigen::VectorXd::Zero(m.rows()), &m);
    }
    assembler_.end();
    return assembler_.matrix();
  }

  // Test helpers.
  int num_dofs() const { return static_cast<int>(point_masses_.size()); }
  CurveEval curve_eval() const {
    return [this](int id, double t) { return curves_[static_cast<size_t>(id)].value(t); };
  }
  Eigen::MatrixXd dense_mass() const {
    Eigen::MatrixXd m = Eigen::MatrixXd::Zero(num_dofs(), num_dofs());
    for (int e = 0; e < num_elements(); ++e) {
      const std::vector<int> dofs = element_dofs(e);
      const Eigen::MatrixXd me = element_mass(e);
      for (size_t i = 0; i < dofs.size(); ++i)
        for (size_t j = 0; j < dofs.size(); ++j)
          m(dofs[i], dofs[j]) += me(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
    }
    return m;
  }
  // r(u, t) = f_int(u) - f_ext(t), full, without inertia.
  Eigen::VectorXd static_residual(const Eigen::VectorXd& u, double t) const {
    Eigen::VectorXd r = -external_force_at(t);
    for (size_t s = 0; s < springs_.size(); ++s) {
      const ChainSpring& sp = springs_[s];
      const double e = u[sp.b] - u[sp.a], force = sp.k * e + sp.k3 * e * e * e;
      r[sp.a] -= force;
      r[sp.b] += force;
    }
    return r;
  }
  double strain_energy(const Eigen::VectorXd& u) const {
    double w = 0.0;
    for (const ChainSpring& s : springs_) {
      const double e = u[s.b] - u[s.a];
      w += 0.5 * s.k * e * e + 0.25 * s.k3 * e * e * e * e;
    }
    return w;
  }
  Eigen::VectorXd prescribed_motion(double t, int order) const override {
    Eigen::VectorXd g = Eigen::VectorXd::Zero(num_dofs());
    for (int d : constraints_.constrained_dofs())
      for (const auto& [id, amplitude] : constraints_.prescribed_terms(d)) {
        if (id < 0) {
          g[d] += order == 0 ? amplitude : 0.0;
          continue;
        }
        const TimeFunction& f = curves_[static_cast<size_t>(id)];
        g[d] += amplitude * (order == 0 ? f.value(t) : order == 1 ? f.rate(t) : f.second(t));
      }
    return g;
  }
  Eigen::MatrixXd dense_t() const {
    Eigen::MatrixXd t = Eigen::MatrixXd::Zero(num_dofs(), size());
    for (int d = 0; d < num_dofs(); ++d)
      for (const auto& [i, c] : constraints_.expansion(d)) t(d, i) += c;
    return t;
  }
  int accepted() const { return accepted_; }
  int rejected() const { return rejected_; }
  int evaluations() const { return evaluations_; }

 private:
  int num_elements() const { return static_cast<int>(springs_.size()) + num_dofs(); }
  std::vector<int> element_dofs(int e) const {
    if (e < static_cast<int>(springs_.size())) return {springs_[static_cast<size_t>(e)].a, springs_[static_cast<size_t>(e)].b};
    return {e - static_cast<int>(springs_.size())};
  }
  Eigen::MatrixXd element_mass(int e) const {
    if (e < static_cast<int>(springs_.size())) {
      const double m = springs_[static_cast<size_t>(e)].mass;
      return (Eigen::Matrix2d() << m / 3, m / 6, m / 6, m / 3).finished();
    }
    return Eigen::MatrixXd::Constant(1, 1, point_masses_[static_cast<size_t>(e) - springs_.size()]);
  }
  void element_response(int e, const Eigen::VectorXd& u, Eigen::VectorXd& r, Eigen::MatrixXd& k) const {
    if (e >= static_cast<int>(springs_.size())) {
      r = Eigen::VectorXd::Zero(1);
      k = Eigen::MatrixXd::Zero(1, 1);
      return;
    }
    const ChainSpring& s = springs_[static_cast<size_t>(e)];
    const double d = u[s.b] - u[s.a], force = s.k * d + s.k3 * d * d * d, stiffness = s.k + 3 * s.k3 * d * d;
    r = (Eigen::Vector2d() << -force, force).finished();
    k = (Eigen::Matrix2d() << stiffness, -stiffness, -stiffness, stiffness).finished();
  }
  double curve(int id, double t) const { return id < 0 ? 1.0 : curves_[static_cast<size_t>(id)].value(t); }
  Eigen::VectorXd external_force_at(double t) const {
    Eigen::VectorXd f = Eigen::VectorXd::Zero(num_dofs());
    for (const ChainLoad& load : loads_) f[load.dof] += load.value * curve(load.curve, t);
    return f;
  }

  std::vector<double> point_masses_;
  std::vector<ChainSpring> springs_;
  ConstraintSet constraints_;
  std::vector<ChainLoad> loads_;
  std::vector<TimeFunction> curves_;
  SparseAssembler assembler_;
  const StepKinematics* step_ = nullptr;
  Eigen::VectorXd u_, f_ext_;
  int accepted_ = 0, rejected_ = 0, evaluations_ = 0;
};

// Exact-enough solution of the reduced equations of motion of a chain, for comparison:
// T^T M T q'' = -T^T (r(u, t) + M g'' + a_M M v), u = T q + g, v = T q' + g', by classical Runge-Kutta.
struct ReferenceState {
  Eigen::VectorXd qdd;                // reduced acceleration
  Eigen::VectorXd u, v, a, reaction;  // full; reaction = M a + a_M M v + r (at constrained DOFs: the supports)
};

class ChainReference {
 public:
  ChainReference(const OscillatorChain& chain, double mass_damping)
      : c_(chain), a_m_(mass_damping), m_(chain.dense_mass()), t_(chain.dense_t()),
        mff_(t_.transpose() * m_ * t_) {}

  // Full state at t for the reduced state (q, q').
  ReferenceState state(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, double t) const {
    ReferenceState s;
    s.u = t_ * q + c_.prescribed_motion(t, 0);
    s.v = t_ * qd + c_.prescribed_motion(t, 1);
    const Eigen::VectorXd r = c_.static_residual(s.u, t), g2 = c_.prescribed_motion(t, 2);
    s.qdd = mff_.ldlt().solve(-t_.transpose() * (r + m_ * g2 + a_m_ * m_ * s.v));
    s.a = t_ * s.qdd + g2;
    s.reaction = m_ * s.a + a_m_ * m_ * s.v + r;
    return s;
  }
  // Integrates from (q, q') at t0 to t1 in n steps of RK4; returns the full state at t1.
  ReferenceState integrate(Eigen::VectorXd q, Eigen::VectorXd qd, double t0, double t1, int n) const {
    const double h = (t1 - t0) / n;
    auto qdd = [&](const Eigen::VectorXd& x, const Eigen::VectorXd& xd, double t) { return state(x, xd, t).qdd; };
    for (int i = 0; i < n; ++i) {
      const double t = t0 + i * h;
      const Eigen::VectorXd k1 = qd, l1 = qdd(q, qd, t);
      const Eigen::VectorXd k2 = qd + 0.5 * h * l1, l2 = qdd(q + 0.5 * h * k1, k2, t + 0.5 * h);
      const Eigen::VectorXd k3 = qd + 0.5 * h * l2, l3 = qdd(q + 0.5 * h * k2, k3, t + 0.5 * h);
      const Eigen::VectorXd k4 = qd + h * l3, l4 = qdd(q + h * k3, k4, t + h);
      q += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
      qd += h / 6 * (l1 + 2 * l2 + 2 * l3 + l4);
    }
    return state(q, qd, t1);
  }

 private:
  const OscillatorChain& c_;
  double a_m_;
  Eigen::MatrixXd m_, t_, mff_;
};

// Single oscillator: DOF 0 fixed, DOF 1 with point mass m on a spring (k, k3) to it; optional load
// value * curve 0 on DOF 1.
inline OscillatorChain make_oscillator(double m, double k, double k3 = 0.0, double load = 0.0,
                                       TimeFunction curve = {}) {
  ConstraintSet cs;
  cs.fix(0);
  std::vector<ChainLoad> loads;
  std::vector<TimeFunction> curves;
  if (load != 0.0) {
    loads.push_back({1, load, 0});
    curves.push_back(std::move(curve));
  }
  return OscillatorChain({0.0, m}, {{0, 1, k, k3, 0.0}}, cs, loads, curves);
}

// Chain with a moving support (DOF 0, g = 0.2 motion(t)), a fixed one (DOF 4), a rigid link u3 = u2 (MPC),
// consistent bar masses, point masses and a load 0.5 cos(0.7 t) on DOF 1. Free unknowns: DOFs 1 and 2.
inline OscillatorChain make_support_chain(TimeFunction motion, double k3 = 0.0) {
  ConstraintSet cs;
  cs.fix(0, 0.2, 0);
  cs.add({3, {{2, 1.0}}, 0.0, -1});
  cs.fix(4);
  TimeFunction load{[](double t) { return std::cos(0.7 * t); }, [](double t) { return -0.7 * std::sin(0.7 * t); },
                    [](double t) { return -0.49 * std::cos(0.7 * t); }};
  return OscillatorChain({0.3, 1.0, 0.7, 0.5, 0.0},
                         {{0, 1, 3.0, 0.0, 0.4}, {1, 2, 2.0, k3, 0.3}, {3, 4, 1.5, 0.0, 0.2}}, cs,
                         {{1, 0.5, 1}}, {std::move(motion), std::move(load)});
}

inline TimeFunction sine_motion(double omega) {
  return {[omega](double t) { return std::sin(omega * t); }, [omega](double t) { return omega * std::cos(omega * t); },
          [omega](double t) { return -omega * omega * std::sin(omega * t); }};
}

inline NewtonOptions tight_newton() {
  NewtonOptions o;
  o.tol_relative = 1e-12;
  o.tol_absolute = 1e-14;
  return o;
}

// Fixed steps dt from 0 to t_end.
inline StepControl fixed_steps(double dt, double t_end) {
  StepControl sc;
  sc.t_start = 0.0;
  sc.t_end = t_end;
  sc.dt_initial = sc.dt_max = dt;
  sc.dt_min = 1e-6 * dt;
  sc.growth = 1.0;
  sc.max_steps = 1 << 24;
  return sc;
}

struct TransientRun {
  ContinuationResult result;
  Eigen::VectorXd q;                   // at the end
  TransientState state;                // at the end
  std::vector<StepReport> reports;
  std::vector<TransientState> states;  // after every step (keep_states)
};

inline TransientRun run_transient(OscillatorChain& chain, const StepControl& sc, const TransientOptions& options,
                                  Eigen::VectorXd q0, bool keep_states = false, NewtonOptions newton = tight_newton()) {
  auto solver = make_linear_solver("auto", true);
  GeneralizedAlpha method(sc, newton, options);
  TransientRun run;
  run.q = std::move(q0);
  run.result = method.run(chain, run.q, *solver, [&](const StepReport& r, const Eigen::VectorXd&) {
    run.reports.push_back(r);
    if (keep_states) run.states.push_back(method.state());
    return true;
  });
  run.state = method.state();
  return run;
}

}  // namespace fibrane::solve::testing
