// Generalized-alpha time integration: the parameter family, the spectral radius, the order of accuracy
// (forced linear oscillator against its closed form, Duffing oscillator and a chain with support motion,
// a rigid link and consistent masses against Runge-Kutta), the initial acceleration.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>

#include "common/error.hpp"
#include "oscillator_chain.hpp"

namespace fibrane::solve {
namespace {

using testing::ChainReference;
using testing::OscillatorChain;
using GA = GeneralizedAlphaParameters;

struct Scheme {
  std::string name;
  GA p;
  double rho_inf;
};

std::vector<Scheme> schemes() {
  return {{"trapezoidal", GA::trapezoidal(), 1.0},
          {"rho_inf=1", GA::chung_hulbert(1.0), 1.0},
          {"rho_inf=0.8", GA::chung_hulbert(0.8), 0.8},
          {"rho_inf=0.5", GA::chung_hulbert(0.5), 0.5}};
}

TEST(GeneralizedAlphaParameters, ChungHulbertFamilyAndItsChecks) {
  const GA one = GA::chung_hulbert(1.0), zero = GA::chung_hulbert(0.0), p8 = GA::chung_hulbert(0.8);
  EXPECT_DOUBLE_EQ(one.alpha_m, 0.5);
  EXPECT_DOUBLE_EQ(one.alpha_f, 0.5);
  EXPECT_DOUBLE_EQ(one.beta, 0.25);
  EXPECT_DOUBLE_EQ(one.gamma, 0.5);
  EXPECT_DOUBLE_EQ(zero.alpha_m, -1.0);
  EXPECT_DOUBLE_EQ(zero.alpha_f, 0.0);
  EXPECT_DOUBLE_EQ(zero.beta, 1.0);
  EXPECT_DOUBLE_EQ(zero.gamma, 1.5);
  EXPECT_DOUBLE_EQ(p8.alpha_m, 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(p8.alpha_f, 4.0 / 9.0);
  EXPECT_DOUBLE_EQ(p8.beta, 25.0 / 81.0);
  EXPECT_DOUBLE_EQ(p8.gamma, 0.5 - 1.0 / 3.0 + 4.0 / 9.0);
  const GA trap = GA::trapezoidal();
  EXPECT_EQ(trap.alpha_m, 0.0);
  EXPECT_EQ(trap.alpha_f, 0.0);
  EXPECT_EQ(trap.beta, 0.25);
  EXPECT_EQ(trap.gamma, 0.5);
  for (const GA& p : {one, zero, p8, trap}) EXPECT_NO_THROW(check_parameters(p));
  EXPECT_THROW(GA::chung_hulbert(1.1), InputError);
  EXPECT_THROW(GA::chung_hulbert(-0.1), InputError);
  EXPECT_THROW(GA::chung_hulbert(std::numeric_limits<double>::quiet_NaN()), InputError);
  GA first_order = trap;
  first_order.gamma = 0.6;  // Newmark with gamma > 1/2: first order
  EXPECT_THROW(check_parameters(first_order), InputError);
  EXPECT_THROW(check_parameters(GA{0.3, 0.1, 0.3, 0.3}), InputError);  // alpha_m > alpha_f
  GA small_beta = GA::chung_hulbert(0.5);
  small_beta.beta -= 0.05;  // 0.394 < 1/4 + (1/3 - 0)/2
  EXPECT_THROW(check_parameters(small_beta), InputError);
}

// One step of m a + k u = 0 (m = 1, dt = 1, k = omega_dt^2) from x = (u, v, a), written directly from the
// force-averaged balance (1 - am) a_{n+1} + am a_n + (1 - af) k u_{n+1} + af k u_n = 0, which is affine in
// u_{n+1}.
Eigen::Vector3d scalar_step(const GA& p, double omega_dt, const Eigen::Vector3d& x) {
  const double k = omega_dt * omega_dt;
  auto balance = [&](double u) {
    const double a = newmark_acceleration(p, 1.0, x[0], x[1], x[2], u);
    return (1 - p.alpha_m) * a + p.alpha_m * x[2] + (1 - p.alpha_f) * k * u + p.alpha_f * k * x[0];
  };
  const double slope = (1 - p.alpha_m) / p.beta + (1 - p.alpha_f) * k;
  const double u = x[0] - balance(x[0]) / slope;
  const double a = newmark_acceleration(p, 1.0, x[0], x[1], x[2], u);
  return {u, newmark_velocity(p, 1.0, x[1], x[2], a), a};
}

Eigen::Matrix3d kinematic_amplification(const GA& p, double omega_dt) {
  Eigen::Matrix3d amplification;
  for (int j = 0; j < 3; ++j) amplification.col(j) = scalar_step(p, omega_dt, Eigen::Vector3d::Unit(j));
  return amplification;
}

// Largest eigenvalue modulus, computed for the similar matrix in the state (u, v / omega, a / omega^2),
// whose entries are O(1): the three eigenvalues meet at -rho_inf for omega dt -> infinity, and in the
// unscaled matrix rounding moved them by up to 1e-5 (rho_inf = 1 appeared as 1 + 1.4e-5 at omega dt = 1e6).
double spectral_radius(const Eigen::Matrix3d& a, double omega_dt) {
  const Eigen::Vector3d d(1.0, 1.0 / omega_dt, 1.0 / (omega_dt * omega_dt));
  const Eigen::Matrix3d balanced = d.asDiagonal() * a * d.cwiseInverse().asDiagonal();
  return Eigen::EigenSolver<Eigen::Matrix3d>(balanced, false).eigenvalues().cwiseAbs().maxCoeff();
}

TEST(GeneralizedAlpha, AmplificationMatrixHasSpectralRadiusRhoInfAndNeverExceedsOne) {
  std::vector<Scheme> all = schemes();
  all.push_back({"rho_inf=0", GA::chung_hulbert(0.0), 0.0});
  for (const Scheme& s : all) {
    const double r4 = spectral_radius(kinematic_amplification(s.p, 1e4), 1e4);
    const double r5 = spectral_radius(kinematic_amplification(s.p, 1e5), 1e5);
    std::printf("  %-12s spectral radius at omega dt = 1e4: %.6f, 1e5: %.6f\n", s.name.c_str(), r4, r5);
    // The radius tends to rho_inf like (omega dt)^(-2/3) (three coalescing roots): measured 1.7e-3 above
    // it at omega dt = 1e4, 3.6e-4 at 1e5, 4e-11 at 1e9 (rho_inf = 0.8).
    EXPECT_NEAR(r5, s.rho_inf, 1e-3) << s.name;
    EXPECT_NEAR(spectral_radius(kinematic_amplification(s.p, 1e9), 1e9), s.rho_inf, 1e-5) << s.name;
    // Unconditional stability: radius <= 1 for omega dt from 1e-3 to 1e6; none below 1 for rho_inf = 1.
    for (double e = -3; e <= 6; e += 0.25) {
      const double omega_dt = std::pow(10.0, e), r = spectral_radius(kinematic_amplification(s.p, omega_dt), omega_dt);
      EXPECT_LE(r, 1 + 1e-10) << s.name << " at omega dt = 10^" << e;
      if (s.rho_inf == 1.0) {
        EXPECT_NEAR(r, 1.0, 1e-10) << s.name << " at omega dt = 10^" << e;
      }
    }
  }
}

// The method's own one-step map on m a + k u = 0 (dt = 1, k = omega_dt^2), column j from a restart state
// with unit (u, v, a)_j at the oscillator's DOF and the residual r = k u that belongs to it.
Eigen::Matrix3d method_amplification(const GA& p, double omega_dt) {
  const double k = omega_dt * omega_dt;
  auto solver = make_linear_solver("auto", true);
  Eigen::Matrix3d amplification;
  for (int j = 0; j < 3; ++j) {
    const Eigen::Vector3d x = Eigen::Vector3d::Unit(j);
    OscillatorChain osc = testing::make_oscillator(1.0, k);
    TransientOptions opt;
    opt.parameters = p;
    GeneralizedAlpha method(testing::fixed_steps(1.0, 1.0), testing::tight_newton(), opt);
    MethodState state{{"t", {0.0}}, {"dt", {1.0}}, {"steps", {0.0}}, {"u", {0.0, x[0]}}, {"v", {0.0, x[1]}},
                      {"a", {0.0, x[2]}}, {"residual", {-k * x[0], k * x[0]}}, {"external_force", {0.0, 0.0}},
                      {"reaction", {0.0, 0.0}}, {"mass_velocity", {0.0, x[1]}}, {"energy", {0.0, 0.0, 0.0, 0.0}}};
    method.restore(state);
    Eigen::VectorXd q = Eigen::VectorXd::Constant(1, x[0]);
    const ContinuationResult res = method.run(osc, q, *solver, nullptr);
    EXPECT_TRUE(res.completed()) << res.message;
    amplification.col(j) << method.state().u[1], method.state().v[1], method.state().a[1];
  }
  return amplification;
}

TEST(GeneralizedAlpha, TheMethodsOneStepMapIsTheAmplificationMatrix) {
  for (const Scheme& s : schemes()) {
    for (double omega_dt : {0.5, 1e5}) {
      const Eigen::Matrix3d method = method_amplification(s.p, omega_dt);
      const Eigen::Matrix3d kinematic = kinematic_amplification(s.p, omega_dt);
      // Newton converges to 1e-12 of the step's residual scale: each column agrees to ~1e-12 of its size.
      for (int j = 0; j < 3; ++j)
        EXPECT_LT((method.col(j) - kinematic.col(j)).cwiseAbs().maxCoeff(), 1e-9 * kinematic.col(j).cwiseAbs().maxCoeff())
            << s.name << " at omega dt = " << omega_dt << ", column " << j;
      if (omega_dt > 1) {
        EXPECT_NEAR(spectral_radius(method, omega_dt), s.rho_inf, 1e-3) << s.name;
      }
    }
  }
}

// Observed orders log2(e(dt) / e(dt/2)) of a sequence of errors for halved steps.
std::vector<double> orders(const std::vector<double>& errors) {
  std::vector<double> out;
  for (size_t i = 0; i + 1 < errors.size(); ++i) out.push_back(std::log2(errors[i] / errors[i + 1]));
  return out;
}

void expect_second_order(const std::string& what, const std::vector<double>& errors) {
  const std::vector<double> p = orders(errors);
  std::printf("  %-34s errors", what.c_str());
  for (double e : errors) std::printf(" %.3e", e);
  std::printf("  orders");
  for (double o : p) std::printf(" %.3f", o);
  std::printf("\n");
  // The finest three halvings: 2 +- 0.1.
  for (size_t i = p.size() - 3; i < p.size(); ++i) EXPECT_NEAR(p[i], 2.0, 0.1) << what << " halving " << i;
}

TEST(GeneralizedAlpha, SecondOrderOnAForcedLinearOscillator) {
  // u'' + 4 u = sin(1.3 t), u(0) = 0.5, u'(0) = -0.3; exact: A cos 2t + B sin 2t + F sin(1.3 t) / (4 - 1.69).
  const double w = 2.0, f = 1.3, u0 = 0.5, v0 = -0.3, t_end = 10.0;
  const double c = 1.0 / (w * w - f * f), b = (v0 - f * c) / w;
  const double u_exact = u0 * std::cos(w * t_end) + b * std::sin(w * t_end) + c * std::sin(f * t_end);
  const double v_exact = -w * u0 * std::sin(w * t_end) + w * b * std::cos(w * t_end) + f * c * std::cos(f * t_end);
  for (const Scheme& s : schemes()) {
    std::vector<double> errors;
    for (int n = 100; n <= 1600; n *= 2) {
      OscillatorChain osc = testing::make_oscillator(1.0, w * w, 0.0, 1.0, testing::sine_motion(f));
      TransientOptions opt;
      opt.parameters = s.p;
      opt.initial_velocity = Eigen::VectorXd::Constant(1, v0);
      const auto run = testing::run_transient(osc, testing::fixed_steps(t_end / n, t_end), opt, Eigen::VectorXd::Constant(1, u0));
      ASSERT_TRUE(run.result.completed()) << run.result.message;
      ASSERT_EQ(run.result.steps, n);
      errors.push_back(std::hypot(run.state.u[1] - u_exact, (run.state.v[1] - v_exact) / w));
    }
    expect_second_order("forced linear, " + s.name, errors);
  }
}

TEST(GeneralizedAlpha, SecondOrderOnADuffingOscillator) {
  // u'' + u + 2 u^3 = 0, u(0) = 1: the stiffness triples over the swing.
  const double t_end = 6.0;
  OscillatorChain ref_chain = testing::make_oscillator(1.0, 1.0, 2.0);
  const auto exact = ChainReference(ref_chain, 0.0).integrate(Eigen::VectorXd::Constant(1, 1.0), Eigen::VectorXd::Zero(1), 0.0, t_end, 60000);
  for (const Scheme& s : schemes()) {
    std::vector<double> errors;
    for (int n = 100; n <= 1600; n *= 2) {
      OscillatorChain osc = testing::make_oscillator(1.0, 1.0, 2.0);
      TransientOptions opt;
      opt.parameters = s.p;
      const auto run = testing::run_transient(osc, testing::fixed_steps(t_end / n, t_end), opt, Eigen::VectorXd::Constant(1, 1.0));
      ASSERT_TRUE(run.result.completed()) << run.result.message;
      errors.push_back(std::hypot(run.state.u[1] - exact.u[1], run.state.v[1] - exact.v[1]));
    }
    expect_second_order("Duffing, " + s.name, errors);
  }
}

TEST(GeneralizedAlpha, SecondOrderWithSupportMotionRigidLinkAndConsistentMassesIncludingReactions) {
  const double t_end = 5.0, damping = 0.05;
  OscillatorChain ref_chain = testing::make_support_chain(testing::sine_motion(1.1), 0.5);
  const Eigen::VectorXd q0 = Eigen::Vector2d(0.1, -0.05);
  const auto exact = ChainReference(ref_chain, damping).integrate(q0, Eigen::VectorXd::Zero(2), 0.0, t_end, 50000);
  for (const Scheme& s : schemes()) {
    std::vector<double> state_errors, reaction_errors;
    for (int n = 100; n <= 1600; n *= 2) {
      OscillatorChain chain = testing::make_support_chain(testing::sine_motion(1.1), 0.5);
      TransientOptions opt;
      opt.parameters = s.p;
      opt.mass_damping = damping;
      const auto run = testing::run_transient(chain, testing::fixed_steps(t_end / n, t_end), opt, q0);
      ASSERT_TRUE(run.result.completed()) << run.result.message;
      EXPECT_EQ(run.state.u[3], run.state.u[2]);  // the rigid link holds exactly
      state_errors.push_back(std::sqrt((run.state.u - exact.u).squaredNorm() + (run.state.v - exact.v).squaredNorm()));
      reaction_errors.push_back(std::hypot(run.state.reaction[0] - exact.reaction[0], run.state.reaction[4] - exact.reaction[4]));
    }
    expect_second_order("support chain state, " + s.name, state_errors);
    expect_second_order("support chain reactions, " + s.name, reaction_errors);
  }
}

TEST(GeneralizedAlpha, InitialAccelerationSatisfiesTheBalanceAtTheStart) {
  OscillatorChain chain = testing::make_support_chain(testing::sine_motion(1.1), 0.5);
  const Eigen::VectorXd q0 = Eigen::Vector2d(0.1, -0.05), qd0 = Eigen::Vector2d(0.3, 0.2);
  const auto exact = ChainReference(chain, 0.1).state(q0, qd0, 0.0);
  TransientOptions opt;
  opt.mass_damping = 0.1;
  opt.initial_velocity = qd0;
  const auto run = testing::run_transient(chain, testing::fixed_steps(0.1, 0.0), opt, q0);  // no step
  ASSERT_TRUE(run.result.completed());
  EXPECT_EQ(run.result.steps, 0);
  // Same equations solved by a sparse and a dense factorisation of a well-conditioned 2 x 2 mass.
  EXPECT_LT((run.state.a - exact.a).norm(), 1e-13 * exact.a.norm());
  EXPECT_LT((run.state.v - exact.v).norm(), 1e-15);
  EXPECT_LT((run.state.reaction - exact.reaction).norm(), 1e-13 * exact.reaction.norm());
  EXPECT_NEAR(run.state.energy.kinetic, 0.5 * exact.v.dot(chain.dense_mass() * exact.v), 1e-15);
  // At rest: the free part of the acceleration is zero, the prescribed part is g''(0) = 0.
  TransientOptions rest = opt;
  rest.start = TransientOptions::Start::rest;
  const auto run_rest = testing::run_transient(chain, testing::fixed_steps(0.1, 0.0), rest, q0);
  EXPECT_EQ(run_rest.state.a.norm(), 0.0);
}

// A static start finds the static equilibrium of a nonlinear spring under a constant load (k u + k3 u^3 = F)
// and the body stays there: without it the same start oscillates about that point with amplitude u*.
TEST(GeneralizedAlpha, StaticStartSolvesTheEquilibriumAndStaysThere) {
  const double k = 2.0, k3 = 0.5, load = 1.5;
  const testing::TimeFunction constant{[](double) { return 1.0; }, [](double) { return 0.0; }, [](double) { return 0.0; }};
  OscillatorChain spring = testing::make_oscillator(1.0, k, k3, load, constant);
  TransientOptions opt;
  opt.start = TransientOptions::Start::static_equilibrium;
  const auto run = testing::run_transient(spring, testing::fixed_steps(0.1, 3.0), opt, Eigen::VectorXd::Zero(1));
  ASSERT_TRUE(run.result.completed()) << run.result.message;
  const double u = run.q(0);
  EXPECT_NEAR(k * u + k3 * u * u * u, load, 1e-12);  // Newton's tolerance (tight_newton)
  EXPECT_LT(run.state.v.norm(), 1e-12);
  EXPECT_LT(run.state.energy.kinetic, 1e-24);
  // Released from u = 0 instead, the spring swings past the equilibrium.
  TransientOptions released;
  OscillatorChain again = testing::make_oscillator(1.0, k, k3, load, constant);
  const auto swing = testing::run_transient(again, testing::fixed_steps(0.1, 3.0), released, Eigen::VectorXd::Zero(1),
                                            true);
  double largest = 0;
  for (const auto& s : swing.states) largest = std::max(largest, s.u(1));
  EXPECT_GT(largest, 1.5 * u);
}

// Error-controlled steps on a hardening oscillator u'' + u + 200 u^3 = 0, u(0) = 1 (stiffness 601 at the turning
// points, 1 at the centre: short steps at the turns, long ones in between). The error against Runge-Kutta
// follows the tolerance: eta ~ dt^3 per step, so the global error ~ dt^2 ~ tol^(2/3): 8 times tighter
// gives about 4 times smaller (accepted: more than 2.5).
TEST(GeneralizedAlpha, LocalErrorControlAdaptsTheStepAndItsErrorFollowsTheTolerance) {
  const double t_end = 1.0;
  OscillatorChain ref_chain = testing::make_oscillator(1.0, 1.0, 200.0);
  const Eigen::VectorXd u0 = Eigen::VectorXd::Constant(1, 1.0), v0 = Eigen::VectorXd::Zero(1);
  const auto exact = ChainReference(ref_chain, 0.0).integrate(u0, v0, 0.0, t_end, 200000);
  StepControl sc = testing::fixed_steps(0.01, t_end);
  sc.dt_max = 0.2;
  sc.growth = 2.0;
  std::vector<double> errors;
  for (double tol : {8e-5, 1e-5}) {
    OscillatorChain osc = testing::make_oscillator(1.0, 1.0, 200.0);
    TransientOptions opt;
    opt.error_tolerance = tol;
    const auto run = testing::run_transient(osc, sc, opt, u0);
    ASSERT_TRUE(run.result.completed()) << run.result.message;
    double dt_small = 1e300, dt_large = 0;
    for (std::size_t i = 0; i + 1 < run.reports.size(); ++i) {  // the last step is cut to land on t_end
      dt_small = std::min(dt_small, run.reports[i].dt);
      dt_large = std::max(dt_large, run.reports[i].dt);
    }
    EXPECT_GT(dt_large, 3.0 * dt_small) << "tol " << tol;
    errors.push_back(std::abs(run.state.u[1] - exact.u[1]));
  }
  EXPECT_GT(errors[0] / errors[1], 2.5) << errors[0] << " " << errors[1];
  EXPECT_LT(errors[1], 1e-2);
}

// The energy-balance control on the same hardening oscillator with the trapezoidal rule: the balance
// (E_kin + spring energy, no loads) changes by at most energy_tolerance per accepted step, and in total by
// less than the uncontrolled run with the same initial step.
TEST(GeneralizedAlpha, EnergyToleranceBoundsTheBalanceChangePerStep) {
  const Eigen::VectorXd u0 = Eigen::VectorXd::Constant(1, 1.0);
  StepControl sc = testing::fixed_steps(0.02, 1.0);
  sc.dt_max = 0.2;
  sc.growth = 2.0;
  const auto drift_per_step = [](const testing::TransientRun& run, double& total) {
    double largest = 0.0, previous = 50.5;  // E_kin 0, spring energy at u = 1: 1/2 + 200/4
    total = 0.0;
    for (const TransientState& s : run.states) {
      const double e = s.u[1] - s.u[0];
      const double balance = s.energy.kinetic + 0.5 * e * e + 50.0 * e * e * e * e;
      largest = std::max(largest, std::abs(balance - previous));
      total = std::max(total, std::abs(balance - 50.5));
      previous = balance;
    }
    return largest;
  };
  const double tol = 1e-4;
  OscillatorChain osc = testing::make_oscillator(1.0, 1.0, 200.0);
  TransientOptions opt;
  opt.energy_tolerance = tol;
  const auto run = testing::run_transient(osc, sc, opt, u0, true);
  ASSERT_TRUE(run.result.completed()) << run.result.message;
  double total = 0.0, total_fixed = 0.0;
  EXPECT_LE(drift_per_step(run, total), tol * (1 + 1e-9));
  OscillatorChain fixed = testing::make_oscillator(1.0, 1.0, 200.0);
  const auto fixed_run = testing::run_transient(fixed, testing::fixed_steps(0.02, 1.0), TransientOptions{}, u0, true);
  drift_per_step(fixed_run, total_fixed);
  EXPECT_LT(total, total_fixed) << total << " vs " << total_fixed;
}

}  // namespace
}  // namespace fibrane::solve
