// Newton-Raphson on spring networks assembled through the real ConstraintSet/SparseAssembler.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <functional>

#include "path/nonlinear.hpp"
#include "spring_network.hpp"
#include "toy_systems.hpp"

namespace fibrane::solve {
namespace {

using testing::Bar;
using testing::PointLoad;
using testing::SpringNetwork;

// Chain of n saturating bars along x, node 0 fixed, all y fixed, end load F in x.
SpringNetwork make_chain(int n, double load, double saturation = 1.0) {
  std::vector<Eigen::Vector2d> nodes;
  for (int i = 0; i <= n; ++i) nodes.emplace_back(i, 0.0);
  std::vector<Bar> bars;
  for (int i = 0; i < n; ++i) bars.push_back({i, i + 1, 1.0 + 0.1 * i, saturation});
  ConstraintSet cs;
  cs.fix(0);
  for (int i = 0; i <= n; ++i) cs.fix(2 * i + 1);
  return SpringNetwork(nodes, bars, cs, {{2 * n, load, 0}});
}

// Analytical chain response: every bar carries the load, k d tanh(e/d) = F  =>  e = d atanh(F / (k d)).
double chain_tip_displacement(int n, double load, double saturation = 1.0) {
  double tip = 0;
  for (int i = 0; i < n; ++i) {
    const double k = 1.0 + 0.1 * i;
    tip += saturation * std::atanh(load / (k * saturation));
  }
  return tip;
}

TEST(SpringNetwork, TangentAndResidualMatchFiniteDifferences) {
  // A triangle with an MPC and a prescribed value so T and g are non-trivial; q is off-equilibrium.
  ConstraintSet cs;
  cs.fix(0);
  cs.fix(1, 0.2, 0);
  cs.add({5, {{2, 0.5}, {3, -0.3}}, 0.1, -1});
  SpringNetwork net({{0, 0}, {1, 0.1}, {0.4, 0.9}}, {{0, 1, 2.0, 0.3}, {1, 2, 1.0, 0.5}, {0, 2, 1.5, 0.0}}, cs,
                    {{2, 0.3, 0}});
  const Eigen::VectorXd q = Eigen::Vector3d(0.05, -0.1, 0.07);
  const double t = 0.8;
  net.evaluate(q, t, true);
  const Eigen::VectorXd r = net.residual();
  const Eigen::MatrixXd k(net.tangent());
  // Central differences with h = 1e-5: truncation O(h^2) ~ 1e-10 times third derivatives of O(10),
  // round-off ~ 1e-16 / 1e-5 ~ 1e-11; tolerance 1e-8 leaves margin and still catches any wrong term.
  const double h = 1e-5;
  for (int j = 0; j < 3; ++j) {
    Eigen::VectorXd qp = q, qm = q;
    qp[j] += h;
    qm[j] -= h;
    EXPECT_NEAR((net.energy(qp, t) - net.energy(qm, t)) / (2 * h), r[j], 1e-8) << "residual " << j;
    net.evaluate(qp, t, false);
    const Eigen::VectorXd rp = net.residual();
    net.evaluate(qm, t, false);
    const Eigen::VectorXd fd = (rp - net.residual()) / (2 * h);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(fd[i], k(i, j), 1e-8) << "tangent " << i << "," << j;
  }
}

TEST(Newton, ConvergesQuadraticallyToTheAnalyticalChain) {
  const int n = 6;
  const double load = 0.8;  // 80 % of the weakest bar's force limit k d = 1: strongly nonlinear
  SpringNetwork chain = make_chain(n, load);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(chain.size());
  auto solver = make_linear_solver("auto", true);
  NewtonOptions opt;
  opt.tol_relative = 1e-13;
  const NewtonReport rep = newton_solve(chain, q, 1.0, opt, *solver);
  ASSERT_TRUE(rep.converged) << rep.failure;
  // Converged to 1e-13 of the load: displacement error ~ 1e-13 / (min tangent 0.36): allow 1e-11.
  EXPECT_NEAR(chain.displacements()[2 * n], chain_tip_displacement(n, load), 1e-11);
  // Order estimate p = log(r_{k+1}/r_k) / log(r_k/r_{k-1}) on the last iterates above round-off (1e-12):
  // quadratic convergence gives p -> 2; a wrong tangent gives p ~ 1.
  const auto& h = rep.history;
  ASSERT_GE(h.size(), 4u);
  int checked = 0;
  for (size_t k = 1; k + 1 < h.size(); ++k) {
    if (h[k + 1] < 1e-12 || h[k] > 1e-2) continue;  // asymptotic regime only
    const double p = std::log(h[k + 1] / h[k]) / std::log(h[k] / h[k - 1]);
    EXPECT_GT(p, 1.8) << "iteration " << k;
    ++checked;
  }
  EXPECT_GE(checked, 1);
  EXPECT_EQ(static_cast<int>(h.size()), rep.iterations + 1);
}

// Factorisation reuse (reuse_below): the same root to the same tolerance, with fewer factorisations than
// updates once Newton is in its fast regime.
TEST(Newton, ReusedFactorisationsReachTheSameRootWithFewerFactorisations) {
  const int n = 6;
  const double load = 0.8;
  auto solve = [&](double reuse_below, bool reuse_first) {
    SpringNetwork chain = make_chain(n, load);
    Eigen::VectorXd q = Eigen::VectorXd::Zero(chain.size());
    auto solver = make_linear_solver("auto", true);
    NewtonOptions opt;
    opt.tol_relative = 1e-13;
    opt.reuse_below = reuse_below;
    opt.reuse_first = reuse_first;
    const NewtonReport rep = newton_solve(chain, q, 1.0, opt, *solver);
    EXPECT_TRUE(rep.converged) << rep.failure;
    EXPECT_NEAR(chain.displacements()[2 * n], chain_tip_displacement(n, load), 1e-11);
    return rep;
  };
  const NewtonReport full = solve(0.0, false), reused = solve(0.1, false), first = solve(0.1, true);
  EXPECT_EQ(full.factorizations, full.iterations);
  EXPECT_LT(reused.factorizations, full.factorizations);
  EXPECT_LT(reused.factorizations, reused.iterations);
  // reuse_first tries the first factorisation at once; on this chain an update with it stops cutting |r|
  // by 4 before the root (one factorisation would otherwise do), so the rule factorises again: the same
  // root, with no more factorisations than the plain reuse rule.
  EXPECT_GT(first.factorizations, 1);
  EXPECT_LE(first.factorizations, reused.factorizations);
}

// reuse_first where the first factorisation is good enough (r = K q + c q^3 - f with a small c: the
// tangent changes little): one factorisation for the whole solve, each update cutting |r| by 4 or more.
TEST(Newton, FirstFactorisationReusedWhereItContracts) {
  const Eigen::Vector3d f(1.0, -0.5, 0.25);
  Eigen::Matrix3d k;
  k << 4, -1, 0, -1, 4, -1, 0, -1, 4;
  const double c = 0.05;
  testing::ToySystem cubic(
      3, [&](const Eigen::VectorXd& q, double) -> Eigen::VectorXd { return k * q + c * q.array().cube().matrix() - f; },
      [&](const Eigen::VectorXd& q, double) -> Eigen::MatrixXd {
        return k + Eigen::MatrixXd((3 * c * q.array().square()).matrix().asDiagonal());
      },
      [&](const Eigen::VectorXd&, double) -> Eigen::VectorXd { return Eigen::VectorXd::Zero(3); });
  auto solve = [&](bool reuse_first) {
    Eigen::VectorXd q = Eigen::VectorXd::Constant(3, 1.0);
    auto solver = make_linear_solver("auto", true);
    NewtonOptions opt;
    opt.tol_relative = 1e-13;
    opt.reuse_below = 0.1;
    opt.reuse_first = reuse_first;
    const NewtonReport rep = newton_solve(cubic, q, 1.0, opt, *solver);
    EXPECT_TRUE(rep.converged) << rep.failure;
    EXPECT_LT((k * q + c * q.array().cube().matrix() - f).norm(), 1e-12);
    for (std::size_t i = 1; i < rep.history.size(); ++i)
      if (reuse_first) {
        EXPECT_LE(rep.history[i], 0.25 * rep.history[i - 1]) << i;
      }
    return rep;
  };
  const NewtonReport plain = solve(false), first = solve(true);
  EXPECT_GE(plain.factorizations, 2);
  EXPECT_EQ(first.factorizations, 1);
}

// r = K q + c q^3 - t f: the factorisation in hand from the converged solve at t = 1 (factor_in_hand)
// serves the first update of the solve at a nearby load without any factorisation of its own, and where
// the load is far (its chord no longer cuts |r| by 4) the solve factorises its own tangent after that
// update. Each reaches the root to the tolerance. Without reuse_below, or with a solver that holds no
// factor, factor_in_hand changes nothing.
TEST(Newton, AFactorisationInHandServesANearbySolve) {
  const Eigen::Vector3d f(1.0, -0.5, 0.25);
  Eigen::Matrix3d k;
  k << 4, -1, 0, -1, 4, -1, 0, -1, 4;
  const double c = 1.0;
  const auto residual = [&](const Eigen::VectorXd& q, double t) -> Eigen::VectorXd {
    return k * q + c * q.array().cube().matrix() - t * f;
  };
  testing::ToySystem cubic(
      3, residual,
      [&](const Eigen::VectorXd& q, double) -> Eigen::MatrixXd {
        return k + Eigen::MatrixXd((3 * c * q.array().square()).matrix().asDiagonal());
      },
      [&](const Eigen::VectorXd&, double) -> Eigen::VectorXd { return -f; });
  NewtonOptions opt;
  opt.tol_relative = 1e-13;
  opt.reuse_below = 0.1;
  // From the root at t = 1 with the solver as that solve left it, to t.
  const auto from_root = [&](double t, bool in_hand, const NewtonOptions& o, bool fresh_solver = false) {
    auto solver = make_linear_solver("auto", true);
    Eigen::VectorXd q = Eigen::VectorXd::Zero(3);
    EXPECT_TRUE(newton_solve(cubic, q, 1.0, o, *solver).converged);
    if (fresh_solver) solver = make_linear_solver("auto", true);
    const NewtonReport rep = newton_solve(cubic, q, t, o, *solver, in_hand);
    EXPECT_TRUE(rep.converged) << rep.failure;
    EXPECT_LT(residual(q, t).norm(), 1e-12 * t * f.norm());
    return rep;
  };
  const NewtonReport near = from_root(1.02, true, opt);
  EXPECT_EQ(near.factorizations, 0);
  EXPECT_GE(near.iterations, 2);  // chords, not one exact update
  EXPECT_GE(from_root(1.02, false, opt).factorizations, 1);
  const NewtonReport far = from_root(6.0, true, opt);
  EXPECT_GT(far.history[1], 0.25 * far.history[0]);  // the chord with the old factor: too far
  EXPECT_GE(far.factorizations, 1);
  NewtonOptions plain = opt;
  plain.reuse_below = 0;
  EXPECT_EQ(from_root(1.02, true, plain).factorizations, from_root(1.02, false, plain).factorizations);
  EXPECT_GE(from_root(1.02, true, opt, true).factorizations, 1);
}

TEST(Newton, ReactionsBalanceTheExternalLoad) {
  const double load = 0.5;
  SpringNetwork chain = make_chain(4, load);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(chain.size());
  auto solver = make_linear_solver("cholmod", true);
  NewtonOptions opt;
  opt.tol_relative = 1e-12;
  ASSERT_TRUE(newton_solve(chain, q, 1.0, opt, *solver).converged);
  chain.evaluate(q, 1.0, false);
  // r = f_int - f_ext; at a support it is the force the support must supply: -F in x at node 0,
  // zero in y. Tolerance: converged to 1e-12 * F.
  const Eigen::VectorXd& r = chain.assembler().full_residual();
  EXPECT_NEAR(r[0], -load, 1e-11);
  for (int dof : chain.constraints().constrained_dofs())
    if (dof != 0) {
      EXPECT_NEAR(r[dof], 0.0, 1e-11) << dof;
    }
}

// A system that returns NaN once q leaves a bounded region, to exercise the non-finite guard.
class PoisonedChain : public SpringNetwork {
 public:
  using SpringNetwork::SpringNetwork;
  void evaluate(const Eigen::VectorXd& q, double t, bool with_tangent) override {
    SpringNetwork::evaluate(q, t, with_tangent);
    nan_residual_ = SpringNetwork::residual();
    if (q.cwiseAbs().maxCoeff() > 0.1) nan_residual_[0] = std::nan("");
  }
  const Eigen::VectorXd& residual() const override { return nan_residual_; }

 private:
  Eigen::VectorXd nan_residual_;
};

TEST(Newton, ReportsFailuresInsteadOfReturningGarbage) {
  auto solver = make_linear_solver("auto", true);
  // Load above the force limit of the weakest bar (k d = 1): no equilibrium exists.
  SpringNetwork impossible = make_chain(3, 1.2);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(impossible.size());
  NewtonOptions opt;
  opt.max_iterations = 15;
  const NewtonReport rep = newton_solve(impossible, q, 1.0, opt, *solver);
  EXPECT_FALSE(rep.converged);
  EXPECT_FALSE(rep.failure.empty());

  std::vector<Eigen::Vector2d> nodes = {{0, 0}, {1, 0}};
  ConstraintSet cs;
  cs.fix(0);
  cs.fix(1);
  cs.fix(3);
  PoisonedChain poisoned(nodes, {{0, 1, 1.0, 0.0}}, cs, {{2, 0.5, 0}});
  Eigen::VectorXd q1 = Eigen::VectorXd::Zero(1);
  const NewtonReport bad = newton_solve(poisoned, q1, 1.0, NewtonOptions{}, *solver);
  EXPECT_FALSE(bad.converged);
  EXPECT_NE(bad.failure.find("non-finite"), std::string::npos) << bad.failure;
}

// A failed solve frees the solver's factor (every caller factorises before it solves again), so that a
// cut-back step does not evaluate and factorise beside it; a converged solve keeps it.
TEST(Newton, AFailedSolveFreesItsFactor) {
  auto solver = make_linear_solver("auto", true);
  SpringNetwork possible = make_chain(3, 0.5);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(possible.size());
  ASSERT_TRUE(newton_solve(possible, q, 1.0, NewtonOptions{}, *solver).converged);
  EXPECT_GT(solver->held_factor_entries(), 0);
  SpringNetwork impossible = make_chain(3, 1.2);  // above the weakest bar's force limit
  q.setZero();
  ASSERT_FALSE(newton_solve(impossible, q, 1.0, NewtonOptions{}, *solver).converged);
  EXPECT_EQ(solver->held_factor_entries(), 0);
  q.setZero();
  ASSERT_TRUE(newton_solve(possible, q, 1.0, NewtonOptions{}, *solver).converged);  // factorises again
  EXPECT_NEAR(possible.displacements()[6], chain_tip_displacement(3, 0.5), 1e-11);
}

// A linear system r = K q - f plus a residual "floor": noise of size 1e-6 that grows by 1 % at every
// evaluation, as summation round-off wanders when it dominates. The tolerances (1e-12) lie below the floor,
// so only the round-off-floor test can end the iteration. With the floor rising at every evaluation, a rule
// that needs the residual to fall there never converges; the accepted rule (a tiny update and at most
// twice the previous residual) must stop within two updates of reaching the floor, at a q within
// |K^-1| x floor ~ 1e-6 of the exact solution.
class NoisyLinearSystem final : public NonlinearSystem {
 public:
  NoisyLinearSystem() : k_(3, 3), f_(3), r_(3) {
    k_.insert(0, 0) = 4;
    k_.insert(1, 1) = 3;
    k_.insert(2, 2) = 2;
    k_.insert(0, 1) = k_.insert(1, 0) = 1;
    k_.makeCompressed();
    f_ << 1e3, -2e3, 5e2;  // |q| ~ 1e3, so tol_increment 1e-10 means |dq| <= ~1e-7
  }
  int size() const override { return 3; }
  void evaluate(const Eigen::VectorXd& q, double, bool) override {
    const double noise = 1e-6 * std::pow(1.01, evaluations++);
    r_ = k_ * q - f_ + Eigen::Vector3d(noise, -noise, noise);
  }
  const Eigen::VectorXd& residual() const override { return r_; }
  const Eigen::SparseMatrix<double>& tangent() const override { return k_; }
  int pattern_version() const override { return 1; }
  Eigen::VectorXd exact() const { return Eigen::MatrixXd(k_).ldlt().solve(f_); }
  int evaluations = 0;

 private:
  Eigen::SparseMatrix<double> k_;
  Eigen::VectorXd f_, r_;
};

TEST(Newton, StopsAtAWanderingRoundOffFloor) {
  NoisyLinearSystem sys;
  auto solver = make_linear_solver("auto", true);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(3);
  NewtonOptions opt;
  opt.tol_relative = opt.tol_absolute = 1e-12;
  opt.max_iterations = 10;
  const NewtonReport rep = newton_solve(sys, q, 1.0, opt, *solver);
  ASSERT_TRUE(rep.converged) << rep.failure;
  // Update 1 solves the linear part (residual = noise), update 2 is the first tiny one: converged at the
  // evaluation after it.
  EXPECT_LE(rep.iterations, 3);
  EXPECT_LT(rep.residual_norm, 1e-5);
  EXPECT_LT((q - sys.exact()).norm(), 1e-5);
}

// One unknown: r(q) and k(q) = dr/dq given as functions; counts its evaluations.
class ScalarSystem final : public NonlinearSystem {
 public:
  ScalarSystem(std::function<double(double)> r, std::function<double(double)> k)
      : r_of_(std::move(r)), k_of_(std::move(k)), k_(1, 1), r_(1) {
    k_.insert(0, 0) = 1;
  }
  int size() const override { return 1; }
  void evaluate(const Eigen::VectorXd& q, double, bool with_tangent) override {
    r_[0] = r_of_(q[0]);
    k_.coeffRef(0, 0) = with_tangent ? k_of_(q[0]) : std::numeric_limits<double>::quiet_NaN();
    ++evaluations;
    tangents += with_tangent;
  }
  const Eigen::VectorXd& residual() const override { return r_; }
  const Eigen::SparseMatrix<double>& tangent() const override { return k_; }
  int pattern_version() const override { return 1; }
  int evaluations = 0, tangents = 0;

 private:
  std::function<double(double)> r_of_, k_of_;
  Eigen::SparseMatrix<double> k_;
  Eigen::VectorXd r_;
};

// r(q) = atan(q - 1): from q0 with |q0 - 1| > 1.39 Newton's updates overshoot more each time and diverge
// (the classic example); halving an update whenever |r| rose makes it converge (to q = 1) from anywhere.
ScalarSystem arctan_system() {
  return ScalarSystem([](double q) { return std::atan(q - 1.0); },
                      [](double q) { return 1.0 / (1.0 + (q - 1.0) * (q - 1.0)); });
}

TEST(Newton, LineSearchTurnsADivergingIterationIntoAConvergingOne) {
  NewtonOptions opt;
  opt.tol_relative = 0;
  opt.tol_absolute = 1e-12;
  opt.max_iterations = 40;
  auto solver = make_linear_solver("auto", true);
  ScalarSystem plain = arctan_system();
  Eigen::VectorXd q = Eigen::VectorXd::Constant(1, 4.0);
  const NewtonReport diverged = newton_solve(plain, q, 1.0, opt, *solver);
  EXPECT_FALSE(diverged.converged) << q[0] << " after " << diverged.iterations << " " << ::testing::PrintToString(diverged.history);
  opt.line_search = 10;
  ScalarSystem damped = arctan_system();
  q.setConstant(4.0);
  const NewtonReport rep = newton_solve(damped, q, 1.0, opt, *solver);
  ASSERT_TRUE(rep.converged) << rep.failure;
  EXPECT_NEAR(q[0], 1.0, 1e-12);
  EXPECT_GT(rep.backtracks, 0);
  // every evaluation is either an iterate or a halving
  EXPECT_EQ(damped.evaluations, rep.iterations + rep.backtracks + 1);
}

// r(q) = q^3 + q - 2 (root 1) from q = 3: quadratic convergence, so once an update predicts the next
// residual below the tolerance that iterate is evaluated without a tangent, and every tangent assembled is
// factorised (a tangent of NaN would fail the factorisation if it were used). With the tolerance between
// the predicted and the actual residual of an iterate, the prediction fails: that iterate is evaluated
// again with its tangent, and Newton still reaches the root.
TEST(Newton, AssemblesNoTangentForAnIteratePredictedConverged) {
  auto cubic = [] { return ScalarSystem([](double q) { return q * q * q + q - 2; }, [](double q) { return 3 * q * q + 1; }); };
  auto solver = make_linear_solver("auto", true);
  NewtonOptions opt;
  opt.tol_relative = 0;
  opt.tol_absolute = 1e-12;
  ScalarSystem sys = cubic();
  Eigen::VectorXd q = Eigen::VectorXd::Constant(1, 3.0);
  const NewtonReport rep = newton_solve(sys, q, 1.0, opt, *solver);
  ASSERT_TRUE(rep.converged) << rep.failure;
  EXPECT_NEAR(q[0], 1.0, 1e-12);
  EXPECT_EQ(sys.tangents, rep.factorizations);
  EXPECT_EQ(sys.evaluations, rep.iterations + 1);
  // The residuals of that run: choose a tolerance that the prediction from iterate k claims for k + 1
  // but iterate k + 1 misses (its contraction is slower than squared).
  const auto& h = rep.history;
  bool tried = false;
  for (std::size_t k = 1; k + 1 < h.size() && !tried; ++k) {
    const double predicted = h[k] * (h[k] / h[k - 1]) * (h[k] / h[k - 1]);
    if (!(predicted < h[k + 1])) continue;
    opt.tol_absolute = std::sqrt(predicted * h[k + 1]);
    ScalarSystem missed = cubic();
    q.setConstant(3.0);
    const NewtonReport again = newton_solve(missed, q, 1.0, opt, *solver);
    ASSERT_TRUE(again.converged) << again.failure;
    EXPECT_EQ(missed.tangents, again.factorizations);
    EXPECT_EQ(missed.evaluations, again.iterations + 2);  // one iterate evaluated twice
    tried = true;
  }
  EXPECT_TRUE(tried) << "no iterate converged slower than its prediction: " << ::testing::PrintToString(h);
}

// r(q) = q^3 - 2 q + 2 from q = 0: Newton goes 0 -> 1 -> 0 -> ... for ever (the classic two-cycle).
TEST(Newton, StopsEarlyWhenTheIterationCycles) {
  ScalarSystem sys([](double q) { return q * q * q - 2 * q + 2; }, [](double q) { return 3 * q * q - 2; });
  auto solver = make_linear_solver("umfpack", false);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(1);
  NewtonOptions opt;
  opt.max_iterations = 40;
  const NewtonReport rep = newton_solve(sys, q, 1.0, opt, *solver);
  EXPECT_FALSE(rep.converged);
  EXPECT_NE(rep.failure.find("cycling"), std::string::npos) << rep.failure;
  EXPECT_EQ(rep.iterations, 4);  // |r| = 2, 1, 2, 1, 2: the cycle is certain at the fifth residual
}

// r(q) = cbrt(q) from q = 1: Newton's update is -3 q, so q goes 1, -2, 4, -8, ... and |r| grows by
// 2^(1/3) per update: no cycle, no tenfold rise within 8 updates (2^(8/3) = 6.3), and 1e8 (divergence) only
// after ~80 updates. With the stall rule the solve ends once stall_iterations updates have not halved
// |r| = 1 of iteration 0; without it, at max_iterations. (A first update that overshoots a hundredfold and
// then converges steadily is no stall: BeamBeamContact.CaseKeyAndHistoryColumn and
// InteractionOutputs.PointsBeyondThePatchAreCountedMarkedAndReported converge after such updates.)
TEST(Newton, StopsWhenUpdatesMakeNoProgress) {
  ScalarSystem sys([](double q) { return std::cbrt(q); },
                   [](double q) { return 1.0 / (3.0 * std::cbrt(q) * std::cbrt(q)); });
  auto solver = make_linear_solver("umfpack", false);
  NewtonOptions opt;
  opt.max_iterations = 40;
  for (const int stall : {8, 0}) {
    opt.stall_iterations = stall;
    Eigen::VectorXd q = Eigen::VectorXd::Ones(1);
    const NewtonReport rep = newton_solve(sys, q, 1.0, opt, *solver);
    EXPECT_FALSE(rep.converged);
    if (stall > 0) {
      EXPECT_EQ(rep.iterations, stall);
      EXPECT_NE(rep.failure.find("no progress in 8 iterations"), std::string::npos) << rep.failure;
      EXPECT_NE(rep.failure.find("none below half of 1 at iteration 0"), std::string::npos) << rep.failure;
    } else {
      EXPECT_EQ(rep.iterations, opt.max_iterations);
      EXPECT_NE(rep.failure.find("no convergence in 40 iterations"), std::string::npos) << rep.failure;
    }
  }
}

// A residual that halves only every few updates is progress: r(q) = q^2 from q = 1 (a double root:
// Newton halves q, |r| falls by 4 per update) converges with the rule on.
TEST(Newton, SlowButSteadyProgressIsNotAStall) {
  ScalarSystem sys([](double q) { return q * q; }, [](double q) { return 2 * q; });
  auto solver = make_linear_solver("umfpack", false);
  NewtonOptions opt;
  opt.max_iterations = 40;
  opt.tol_absolute = 1e-20;
  opt.tol_relative = 1e-20;
  Eigen::VectorXd q = Eigen::VectorXd::Ones(1);
  const NewtonReport rep = newton_solve(sys, q, 1.0, opt, *solver);
  EXPECT_TRUE(rep.converged) << rep.failure;
  EXPECT_EQ(rep.iterations, 34);  // 4^-34 < 1e-20 < 4^-33
}

// A finite residual with a NaN in the tangent: reported before any factorisation is tried.
TEST(Newton, NonFiniteTangentIsReportedBeforeFactorising) {
  ScalarSystem sys([](double q) { return q - 1.0; }, [](double) { return std::nan(""); });
  auto solver = make_linear_solver("auto", true);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(1);
  const NewtonReport rep = newton_solve(sys, q, 1.0, NewtonOptions{}, *solver);
  EXPECT_FALSE(rep.converged);
  EXPECT_EQ(rep.failure, "non-finite tangent at iteration 0");
}

// A solve that fails inside (a Krylov solver whose renewed factorisation ran out of memory) returns NaN:
// Newton names the solver's failure with the non-finite update.
class FailingSolve final : public LinearSolver {
 public:
  void analyze(const Eigen::SparseMatrix<double>&) override {}
  bool factorize_numeric(const Eigen::SparseMatrix<double>&) override { return true; }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const override {
    return Eigen::VectorXd::Constant(b.size(), std::numeric_limits<double>::quiet_NaN());
  }
  std::string name() const override { return "failing"; }
  long factor_nonzeros() const override { return 0; }
  std::string failure_detail() const override { return "out of memory"; }
};

TEST(Newton, ASolveThatFailsInsideIsReportedWithItsCause) {
  ScalarSystem sys([](double q) { return q - 1.0; }, [](double) { return 1.0; });
  FailingSolve solver;
  Eigen::VectorXd q = Eigen::VectorXd::Zero(1);
  const NewtonReport rep = newton_solve(sys, q, 1.0, NewtonOptions{}, solver);
  EXPECT_FALSE(rep.converged);
  EXPECT_EQ(rep.failure, "non-finite Newton update at iteration 0 (failing: out of memory)");
}

}  // namespace
}  // namespace fibrane::solve
