// Generalized-alpha time integration: energy conservation and the energy account, Rayleigh damping,
// restart, step-size control and refused input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "oscillator_chain.hpp"
#include "spring_network.hpp"

namespace fibrane::solve {
namespace {

using testing::OscillatorChain;
using testing::TransientRun;
using GA = GeneralizedAlphaParameters;

// E_kin + E_strain - W_ext - W_prescribed + D: constant up to the scheme's algorithmic dissipation.
double balance(const OscillatorChain& chain, const TransientState& s) {
  const EnergyReport& e = s.energy;
  return e.kinetic + chain.strain_energy(s.u) - e.external_work - e.prescribed_work + e.damping;
}

double mechanical_energy(const OscillatorChain& chain, const TransientState& s) {
  return s.energy.kinetic + chain.strain_energy(s.u);
}

TransientState initial_state(OscillatorChain& chain, const TransientOptions& opt, const Eigen::VectorXd& q0) {
  return testing::run_transient(chain, testing::fixed_steps(1.0, 0.0), opt, q0).state;
}

TEST(GeneralizedAlphaEnergy, TrapezoidalRuleConservesTheEnergyOfALinearOscillator) {
  const double omega = 2.0, period = 2 * std::numbers::pi / omega;
  for (const GA& p : {GA::trapezoidal(), GA::chung_hulbert(1.0)}) {
    OscillatorChain osc = testing::make_oscillator(1.0, omega * omega);
    TransientOptions opt;
    opt.parameters = p;
    const Eigen::VectorXd q0 = Eigen::VectorXd::Constant(1, 1.0);
    const double e0 = mechanical_energy(osc, initial_state(osc, opt, q0));
    const TransientRun run = testing::run_transient(osc, testing::fixed_steps(period / 20, 10 * period), opt, q0, true);
    ASSERT_TRUE(run.result.completed());
    double drift = 0;
    for (const TransientState& s : run.states) drift = std::max(drift, std::abs(mechanical_energy(osc, s) - e0) / e0);
    std::printf("  alpha_f = %.1f: largest |E - E0| / E0 over 10 periods at 20 steps per period: %.2e\n", p.alpha_f, drift);
    // Exact conservation for a linear model: only rounding (the brief's bound was 1e-6 per period).
    EXPECT_LT(drift, 1e-12);
  }
  // rho_inf = 0.8 dissipates at omega dt = 1 as its amplification matrix says: principal roots
  // 0.602556 +- 0.797419 i, modulus 0.999475, so E(40 dt) / E(0) ~ 0.999475^80 = 0.95883 (E is not the
  // modal norm: it oscillates about that by O(1 - |lambda|)).
  OscillatorChain osc = testing::make_oscillator(1.0, omega * omega);
  TransientOptions opt;
  opt.parameters = GA::chung_hulbert(0.8);
  const TransientRun run = testing::run_transient(osc, testing::fixed_steps(0.5, 20.0), opt, Eigen::VectorXd::Constant(1, 1.0));
  const double ratio = mechanical_energy(osc, run.state) / (0.5 * omega * omega);
  std::printf("  rho_inf = 0.8, omega dt = 1: E(40 dt) / E(0) = %.4f\n", ratio);
  EXPECT_NEAR(ratio, 0.95883, 0.005);
}

TEST(GeneralizedAlphaEnergy, AccountClosesExactlyForTheTrapezoidalRuleOnALinearModel) {
  // Support moving at constant velocity (g = 0.2 t), time-varying load, damping, rigid link, consistent masses.
  const testing::TimeFunction ramp{[](double t) { return t; }, [](double) { return 1.0; }, [](double) { return 0.0; }};
  for (const GA& p : {GA::trapezoidal(), GA::chung_hulbert(1.0)}) {
    OscillatorChain chain = testing::make_support_chain(ramp);
    TransientOptions opt;
    opt.parameters = p;
    opt.mass_damping = 0.1;
    const Eigen::VectorXd q0 = Eigen::Vector2d(0.1, -0.05);
    const double b0 = balance(chain, initial_state(chain, opt, q0));
    const TransientRun run = testing::run_transient(chain, testing::fixed_steps(0.05, 10.0), opt, q0, true);
    ASSERT_TRUE(run.result.completed());
    double scale = 0, defect = 0;
    for (const TransientState& s : run.states) {
      scale = std::max({scale, mechanical_energy(chain, s), std::abs(s.energy.external_work),
                        std::abs(s.energy.prescribed_work), s.energy.damping});
      defect = std::max(defect, std::abs(balance(chain, s) - b0));
    }
    const EnergyReport& e = run.state.energy;
    std::printf("  alpha_f = %.1f: W_ext %.4f, W_prescribed %.4f, D %.4f, largest balance defect %.2e\n", p.alpha_f,
                e.external_work, e.prescribed_work, e.damping, defect);
    // Every term is at work (so a missing or mis-signed one would show) ...
    EXPECT_GT(std::abs(e.external_work), 0.01);
    EXPECT_GT(std::abs(e.prescribed_work), 0.01);
    EXPECT_GT(e.damping, 0.01);
    // ... and the balance holds to rounding (Newton solves these linear steps to ~1e-16).
    EXPECT_LT(defect, 1e-12 * scale);
  }
}

TEST(GeneralizedAlphaEnergy, AccountDefectIsSecondOrderForNonlinearModelsAndDissipativeSchemes) {
  const double t_end = 5.0;
  for (const GA& p : {GA::trapezoidal(), GA::chung_hulbert(1.0), GA::chung_hulbert(0.8), GA::chung_hulbert(0.5)}) {
    std::vector<double> defects;
    for (int n = 100; n <= 800; n *= 2) {
      OscillatorChain chain = testing::make_support_chain(testing::sine_motion(1.1), 0.5);
      TransientOptions opt;
      opt.parameters = p;
      opt.mass_damping = 0.05;
      const Eigen::VectorXd q0 = Eigen::Vector2d(0.1, -0.05);
      const double b0 = balance(chain, initial_state(chain, opt, q0));
      const TransientRun run = testing::run_transient(chain, testing::fixed_steps(t_end / n, t_end), opt, q0);
      defects.push_back(std::abs(balance(chain, run.state) - b0));
    }
    std::printf("  alpha_m = %5.2f alpha_f = %.2f balance defects", p.alpha_m, p.alpha_f);
    for (double d : defects) std::printf(" %.3e", d);
    std::printf("\n");
    for (size_t i = 0; i + 1 < defects.size(); ++i) EXPECT_GT(std::log2(defects[i] / defects[i + 1]), 1.8);
  }
}

TEST(GeneralizedAlphaEnergy, TrapezoidalEnergyErrorOnTheDuffingOscillatorIsBoundedAndSecondOrder) {
  // u'' + u + 2 u^3 = 0 from u = 1 (period ~3.7) over ~20 periods: the trapezoidal rule does not conserve
  // a non-quadratic energy; its error must stay bounded (no drift) and shrink like dt^2.
  std::vector<double> errors;
  for (double dt : {0.05, 0.025}) {
    OscillatorChain osc = testing::make_oscillator(1.0, 1.0, 2.0);
    const double e0 = 0.5 + 0.5;  // u^2/2 + u^4/2 at u = 1
    const TransientRun run = testing::run_transient(osc, testing::fixed_steps(dt, 75.0), TransientOptions{},
                                                    Eigen::VectorXd::Constant(1, 1.0), true);
    double first = 0, second = 0;
    for (const TransientState& s : run.states) {
      const double error = std::abs(mechanical_energy(osc, s) - e0) / e0;
      (s.t < 37.5 ? first : second) = std::max(s.t < 37.5 ? first : second, error);
    }
    std::printf("  Duffing, trapezoidal, dt = %.3f: largest |E - E0| / E0 first half %.3e, second half %.3e\n", dt,
                first, second);
    EXPECT_LT(second, 1.05 * first);  // no drift: the error oscillates with the swing
    errors.push_back(std::max(first, second));
  }
  EXPECT_LT(errors[0], 1e-2);
  EXPECT_NEAR(std::log2(errors[0] / errors[1]), 2.0, 0.2);
}

TEST(GeneralizedAlphaEnergy, RayleighDampingDecaysAtTheRateZetaOmega) {
  // u'' + a_M u' + 4 u = 0: zeta = a_M / (2 omega) = 0.05. The amplitude A = sqrt(u^2 + ((v + zeta omega u)
  // / omega_d)^2) decays exactly like exp(-zeta omega t).
  const double omega = 2.0, a_m = 0.2, zeta = a_m / (2 * omega), omega_d = omega * std::sqrt(1 - zeta * zeta);
  const double period = 2 * std::numbers::pi / omega, t_end = 10 * period;
  for (const GA& p : {GA::trapezoidal(), GA::chung_hulbert(0.8)}) {
    OscillatorChain osc = testing::make_oscillator(1.0, omega * omega);
    TransientOptions opt;
    opt.parameters = p;
    opt.mass_damping = a_m;
    const TransientRun run = testing::run_transient(osc, testing::fixed_steps(period / 200, t_end), opt,
                                                    Eigen::VectorXd::Constant(1, 1.0));
    const double u = run.state.u[1], v = run.state.v[1];
    const double amplitude = std::hypot(u, (v + zeta * omega * u) / omega_d);
    const double rate = -std::log(amplitude) / t_end;
    std::printf("  alpha_f = %.2f: decay rate %.7f, zeta omega %.7f, relative error %.2e; D = %.6f\n", p.alpha_f, rate,
                zeta * omega, rate / (zeta * omega) - 1, run.state.energy.damping);
    // omega dt = 0.031: the scheme's errors in the decay rate are O((omega dt)^2) ~ 1e-3 relative at most.
    EXPECT_NEAR(rate / (zeta * omega), 1.0, 1e-3);
    // All of the lost energy went into the damping account (exact for the trapezoidal rule).
    const double lost = 0.5 * omega * omega - mechanical_energy(osc, run.state);
    EXPECT_NEAR(run.state.energy.damping, lost, p.alpha_f == 0 ? 1e-12 : 1e-4 * lost);
  }
}

TEST(GeneralizedAlphaEnergy, SaveAndRestoreMidRunReproducesTheUninterruptedRun) {
  StepControl sc;
  sc.t_end = 3.0;
  sc.dt_initial = 0.01;
  sc.dt_max = 0.1;
  sc.growth = 1.5;
  TransientOptions opt;
  opt.parameters = GA::chung_hulbert(0.8);
  opt.mass_damping = 0.05;
  const Eigen::VectorXd q0 = Eigen::Vector2d(0.1, -0.05);
  auto solver = make_linear_solver("auto", true);
  OscillatorChain chain_a = testing::make_support_chain(testing::sine_motion(1.1), 0.5);
  const TransientRun straight = testing::run_transient(chain_a, sc, opt, q0);
  ASSERT_TRUE(straight.result.completed());
  // Stopped after 7 steps; the state goes through a copy into a new method object.
  OscillatorChain chain_b = testing::make_support_chain(testing::sine_motion(1.1), 0.5);
  Eigen::VectorXd q = q0;
  MethodState saved;
  {
    GeneralizedAlpha first(sc, testing::tight_newton(), opt);
    const ContinuationResult r = first.run(chain_b, q, *solver, [](const StepReport& rep, const Eigen::VectorXd&) { return rep.step < 7; });
    ASSERT_EQ(r.outcome, Outcome::stopped);
    saved = first.save();
  }
  GeneralizedAlpha second(sc, testing::tight_newton(), opt);
  second.restore(saved);
  std::vector<StepReport> reports;
  const ContinuationResult r = second.run(chain_b, q, *solver, [&](const StepReport& rep, const Eigen::VectorXd&) {
    reports.push_back(rep);
    return true;
  });
  ASSERT_TRUE(r.completed());
  ASSERT_FALSE(reports.empty());
  EXPECT_EQ(reports.front().step, 8);
  EXPECT_EQ(r.steps, straight.result.steps);
  EXPECT_EQ(reports.back().dt, straight.reports.back().dt);
  const TransientState& a = straight.state;
  const TransientState& b = second.state();
  EXPECT_LE((q - straight.q).norm(), 1e-12);
  EXPECT_LE((a.u - b.u).norm(), 1e-12);
  EXPECT_LE((a.v - b.v).norm(), 1e-12);
  EXPECT_LE((a.a - b.a).norm(), 1e-12);
  EXPECT_LE((a.reaction - b.reaction).norm(), 1e-12);
  EXPECT_NEAR(a.energy.prescribed_work, b.energy.prescribed_work, 1e-12);
  EXPECT_NEAR(a.energy.damping, b.energy.damping, 1e-12);
  EXPECT_NEAR(a.energy.kinetic, b.energy.kinetic, 1e-12);
}

TEST(GeneralizedAlphaEnergy, CutsBackWhenNewtonFailsAndGrowsAgain) {
  // Stiff Duffing spring (omega dt ~ 5 at the start): 3 Newton iterations are not enough at dt = 0.4.
  StepControl sc;
  sc.t_end = 4.0;
  sc.dt_initial = sc.dt_max = 0.4;
  sc.growth = 1.25;
  NewtonOptions newton = testing::tight_newton();
  newton.max_iterations = 3;
  OscillatorChain osc = testing::make_oscillator(1.0, 1.0, 20.0);
  TransientOptions opt;
  opt.parameters = GA::chung_hulbert(0.8);
  const TransientRun run = testing::run_transient(osc, sc, opt, Eigen::VectorXd::Constant(1, 1.5), false, newton);
  ASSERT_TRUE(run.result.completed()) << run.result.message;
  EXPECT_EQ(run.state.t, 4.0);
  int cutbacks = 0;
  double smallest = sc.dt_max;
  for (const StepReport& r : run.reports) {
    cutbacks += r.cutbacks;
    smallest = std::min(smallest, r.dt);
    EXPECT_TRUE(r.energy.has_value());
  }
  EXPECT_GT(cutbacks, 0);
  EXPECT_EQ(osc.rejected(), cutbacks);  // every failed attempt is reported to the system
  EXPECT_EQ(run.result.failed_attempts, cutbacks);
  EXPECT_LT(smallest, 0.4 * sc.cutback + 1e-12);
  EXPECT_GT(run.reports.back().dt, smallest);  // grew again after the hard part
  EXPECT_EQ(osc.accepted(), run.result.steps);
  // No energy bound is asserted: at omega dt ~ 5 on this hardening spring the force-averaged scheme gains
  // energy (measured E(4) / E(0) = 1.41 for rho_inf = 0.8); generalized-alpha is energy-stable only for
  // linear problems.
  const double e0 = 0.5 * 2.25 + 0.25 * 20.0 * std::pow(1.5, 4);
  std::printf("  stiff Duffing, rho_inf = 0.8, coarse adaptive steps: E(4) / E(0) = %.3f\n", mechanical_energy(osc, run.state) / e0);
  EXPECT_TRUE(run.state.u.allFinite());
  // Below dt_min the run stops with the last converged state.
  OscillatorChain osc2 = testing::make_oscillator(1.0, 1.0, 20.0);
  sc.dt_min = 0.3;
  const TransientRun failed = testing::run_transient(osc2, sc, opt, Eigen::VectorXd::Constant(1, 1.5), false, newton);
  EXPECT_EQ(failed.result.outcome, Outcome::failed);
  EXPECT_NE(failed.result.message.find("dt_min"), std::string::npos) << failed.result.message;
  EXPECT_EQ(failed.q[0], failed.state.u[1]);
  EXPECT_EQ(failed.result.t_reached, failed.state.t);
}

TEST(GeneralizedAlphaEnergy, StepsLandExactlyOnTEnd) {
  OscillatorChain osc = testing::make_oscillator(1.0, 4.0);
  const TransientRun run = testing::run_transient(osc, testing::fixed_steps(0.3, 1.0), TransientOptions{}, Eigen::VectorXd::Constant(1, 1.0));
  ASSERT_EQ(run.reports.size(), 4u);
  const double expected[] = {0.3, 0.3, 0.3, 0.1};
  for (size_t i = 0; i < 4; ++i) EXPECT_NEAR(run.reports[i].dt, expected[i], 1e-12);
  EXPECT_EQ(run.reports.back().t, 1.0);
}

TEST(GeneralizedAlphaEnergy, RefusesSystemsWithoutInertiaAndInvalidOptions) {
  ConstraintSet cs;
  cs.fix(0);
  cs.fix(1);
  cs.fix(3);
  testing::SpringNetwork statics({{0, 0}, {1, 0}}, {{0, 1, 1.0, 0.0}}, cs, {{2, 1.0, 0}});
  auto solver = make_linear_solver("auto", true);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(1);
  GeneralizedAlpha method(testing::fixed_steps(0.1, 1.0), NewtonOptions{}, TransientOptions{});
  EXPECT_THROW(method.run(statics, q, *solver, nullptr), std::invalid_argument);
  TransientOptions negative_damping;
  negative_damping.mass_damping = -0.1;
  EXPECT_THROW(GeneralizedAlpha(testing::fixed_steps(0.1, 1.0), NewtonOptions{}, negative_damping), InputError);
  TransientOptions first_order;
  first_order.parameters.gamma = 0.6;
  EXPECT_THROW(GeneralizedAlpha(testing::fixed_steps(0.1, 1.0), NewtonOptions{}, first_order), InputError);
  TransientOptions wrong_velocity;
  wrong_velocity.initial_velocity = Eigen::VectorXd::Zero(2);  // the oscillator has one free unknown
  OscillatorChain osc = testing::make_oscillator(1.0, 4.0);
  GeneralizedAlpha bad_start(testing::fixed_steps(0.1, 1.0), NewtonOptions{}, wrong_velocity);
  EXPECT_THROW(bad_start.run(osc, q, *solver, nullptr), InputError);
  // A free DOF without mass cannot start with the initial acceleration solve.
  OscillatorChain massless = testing::make_oscillator(0.0, 4.0);
  GeneralizedAlpha no_mass(testing::fixed_steps(0.1, 1.0), NewtonOptions{}, TransientOptions{});
  EXPECT_THROW(no_mass.run(massless, q, *solver, nullptr), InputError);
}

}  // namespace
}  // namespace fibrane::solve
