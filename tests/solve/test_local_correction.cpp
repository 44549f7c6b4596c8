// The local first update (path/local_correction.hpp): the rows it chooses, the update it solves, and
// Newton with it (NewtonOptions::local_share): the same solution as global Newton, one global
// factorisation fewer where the residual is local, and an update that raised |r| taken back; Newton's local
// solves (NewtonOptions::local_newton): the same solution with fewer global factorisations, and the
// global update after them a chord where the factorisation in hand was made near the solution.
#include <gtest/gtest.h>

#include <barrier>
#include <cmath>
#include <functional>
#include <thread>
#include <vector>

#include "path/local_correction.hpp"
#include "path/nonlinear.hpp"
#include "linalg/linear_solver.hpp"
#include "linalg/rank_one_terms.hpp"
#include "solve/grid_matrix.hpp"
#include "solve/toy_systems.hpp"

namespace fibrane::solve {
namespace {

// A chain of n unknowns: springs of stiffness 1 between neighbours (the two ends held), a soft ground of
// stiffness `ground` under every unknown (decay length of a point load's response 1 / sqrt(ground)), and
// at unknown `hard` a cubic spring beta q^3 loaded by t: r = (L + ground I) q + beta q_h^3 e_h - t e_h.
// The tangent is tridiagonal, so the local rows grow by one neighbour on each side per layer.
class Chain : public NonlinearSystem {
 public:
  Chain(int n, int hard, double ground, double beta) : n_(n), hard_(hard), ground_(ground), beta_(beta) {
    std::vector<Eigen::Triplet<double>> t;
    for (int i = 0; i < n; ++i) {
      t.emplace_back(i, i, 2.0 + ground);
      if (i > 0) t.emplace_back(i, i - 1, -1.0);
      if (i + 1 < n) t.emplace_back(i, i + 1, -1.0);
    }
    linear_.resize(n, n);
    linear_.setFromTriplets(t.begin(), t.end());
    k_ = linear_;
  }
  int size() const override { return n_; }
  void evaluate(const Eigen::VectorXd& q, double t, bool with_tangent) override {
    r_ = linear_ * q;
    r_[hard_] += beta_ * q[hard_] * q[hard_] * q[hard_] - t;
    if (with_tangent) k_.coeffRef(hard_, hard_) = linear_.coeff(hard_, hard_) + 3 * beta_ * q[hard_] * q[hard_];
  }
  const Eigen::VectorXd& residual() const override { return r_; }
  const Eigen::SparseMatrix<double>& tangent() const override { return k_; }
  int pattern_version() const override { return 0; }

 private:
  int n_, hard_;
  double ground_, beta_;
  Eigen::SparseMatrix<double> linear_, k_;
  Eigen::VectorXd r_;
};

Eigen::SparseMatrix<double> chain_tangent(int n) {
  Chain chain(n, n / 2, 0.01, 0.0);
  chain.evaluate(Eigen::VectorXd::Zero(n), 0.0, true);
  return chain.tangent();
}

TEST(LocalRows, SeedsGrowByLayersOfTheGraphUntilTheyHoldTheShare) {
  const Eigen::SparseMatrix<double> k = chain_tangent(400);
  Eigen::VectorXd r = Eigen::VectorXd::Zero(400);
  r[200] = 1.0;
  r[300] = 1e-4;  // below the seed level (1e-3 of the largest entry): no seed
  // 40 rows wanted: each layer adds one row on each side, so 20 layers give 200 +- 20 (41 rows).
  const std::vector<int> rows = local_rows(r, k, {.share = 0.1});
  ASSERT_EQ(rows.size(), 41u);
  for (int a = 0; a < 41; ++a) EXPECT_EQ(rows[static_cast<std::size_t>(a)], 180 + a);
  // A lower seed level takes row 300 as a seed too, whose layers grow beside the first ones.
  const std::vector<int> both = local_rows(r, k, {.share = 0.1, .seed_level = 1e-5});
  EXPECT_EQ(both.size(), 42u);  // 10 layers around each: 2 x 21
  EXPECT_TRUE(std::binary_search(both.begin(), both.end(), 300));
  // The layer cap ends the growth below the share.
  EXPECT_EQ(local_rows(r, k, {.share = 0.1, .max_layers = 3}).size(), 7u);
}

// Three "processes" (threads), each with a summand of the grid matrix (the entries of the rows each owns, and
// their transposes, so every summand's pattern is symmetric), grow the rows together through RowUnion: each
// gets the rows of the whole matrix, where one summand's graph alone gives fewer. The summands' principal
// submatrices sum to the whole one's.
TEST(LocalRows, SummandsOfSeveralProcessesGrowTheSumsLayers) {
  const int n = 900, processes = 3;
  const Eigen::SparseMatrix<double> k = grid_matrix(30, 0.1, 0.0, 0.2, 3);
  std::vector<std::vector<Eigen::Triplet<double>>> parts(processes);
  for (int j = 0; j < n; ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(k, j); it; ++it) {
      const int lower = std::min(static_cast<int>(it.row()), j);
      parts[static_cast<std::size_t>((lower / 7) % processes)].emplace_back(static_cast<int>(it.row()), j, it.value());
    }
  std::vector<Eigen::SparseMatrix<double>> summands(processes, Eigen::SparseMatrix<double>(n, n));
  for (int p = 0; p < processes; ++p)
    summands[static_cast<std::size_t>(p)].setFromTriplets(parts[static_cast<std::size_t>(p)].begin(), parts[static_cast<std::size_t>(p)].end());
  Eigen::VectorXd r = Eigen::VectorXd::Zero(n);
  r[433] = 1.0;
  r[95] = -0.5;
  const LocalRowsOptions options{.share = 0.2};
  const std::vector<int> whole = local_rows(r, k, options);
  ASSERT_GT(whole.size(), 150u);

  std::barrier sync(processes);
  std::vector<std::vector<char>*> slots(processes);
  std::vector<std::vector<int>> rows(processes), alone(processes);
  std::vector<std::thread> threads;
  for (int p = 0; p < processes; ++p)
    threads.emplace_back([&, p] {
      const auto unite = [&](std::vector<char>& added) {
        slots[static_cast<std::size_t>(p)] = &added;
        sync.arrive_and_wait();
        std::vector<char> any(added.size(), 0);
        for (const auto* s : slots)
          for (std::size_t i = 0; i < any.size(); ++i) any[i] = static_cast<char>(any[i] | (*s)[i]);
        sync.arrive_and_wait();  // everyone has read before anyone writes
        added = any;
      };
      rows[static_cast<std::size_t>(p)] = local_rows(r, summands[static_cast<std::size_t>(p)], options, unite);
      alone[static_cast<std::size_t>(p)] = local_rows(r, summands[static_cast<std::size_t>(p)], options);
    });
  for (auto& t : threads) t.join();
  Eigen::SparseMatrix<double> sum(whole.size(), whole.size());
  for (int p = 0; p < processes; ++p) {
    SCOPED_TRACE(p);
    EXPECT_EQ(rows[static_cast<std::size_t>(p)], whole);
    EXPECT_NE(alone[static_cast<std::size_t>(p)], whole);
    sum += principal_submatrix(summands[static_cast<std::size_t>(p)], whole);
  }
  const Eigen::SparseMatrix<double> direct = principal_submatrix(k, whole);
  EXPECT_EQ(sum.nonZeros(), direct.nonZeros());
  EXPECT_EQ((sum - direct).norm(), 0.0);  // each entry comes from exactly one summand
}

// K_SS dq_S = -r_S on the rows, zero elsewhere: symmetric (LL^T) and unsymmetric (LU) tangents.
TEST(LocalUpdate, SolvesThePrincipalSubmatrixOnTheRows) {
  for (const double convection : {0.0, 0.4}) {
    SCOPED_TRACE(convection);
    const Eigen::SparseMatrix<double> k = grid_matrix(30, 0.1, convection, 0.2, 3);
    Eigen::VectorXd r = Eigen::VectorXd::LinSpaced(900, -1.0, 2.0);
    std::vector<int> rows;
    for (int i = 0; i < 900; i += 3) rows.push_back(i);
    Eigen::VectorXd dq;
    ASSERT_TRUE(local_update(r, principal_submatrix(k, rows), {}, convection == 0.0, rows, dq));
    const Eigen::VectorXd kdq = k * dq;
    double largest = 0;
    for (int i = 0; i < 900; ++i) {
      const bool on = std::binary_search(rows.begin(), rows.end(), i);
      if (on)
        largest = std::max(largest, std::abs(kdq[i] + r[i]));
      else
        EXPECT_EQ(dq[i], 0.0);
    }
    // Backward error of a direct solve of a matrix of condition ~1e2 with entries of ~4: round-off.
    EXPECT_LT(largest, 1e-12 * r.cwiseAbs().maxCoeff());
  }
}

TEST(LocalUpdate, ASingularSubmatrixIsRefused) {
  Eigen::SparseMatrix<double> k = chain_tangent(50);
  for (int i = 10; i < 13; ++i)  // rows and columns 10..12 emptied: K_SS singular where S holds them
    for (int j = 0; j < 50; ++j)
      if (k.coeff(i, j) != 0.0) k.coeffRef(i, j) = k.coeffRef(j, i) = 0.0;
  Eigen::VectorXd dq = Eigen::VectorXd::Constant(50, 7.0);
  const std::vector<int> rows{9, 10, 11, 12, 13};
  EXPECT_FALSE(local_update(Eigen::VectorXd::Ones(50), principal_submatrix(k, rows), {}, true, rows, dq));
  EXPECT_EQ(dq, Eigen::VectorXd::Constant(50, 7.0));
}

// Rank-one terms held apart (RankOneTerms, local_matrix): a local update with the assembled part's
// submatrix and the terms is the one with the whole matrix's submatrix, for a symmetric and an unsymmetric
// matrix, rows that are not the first ones (every third left out), terms of either sign, a term that
// straddles the rows' end, one with no entry on the rows and one with coefficient zero (both left out of
// the correction); local_matrix drops the exact zeros among the terms' fill rows and keeps one elsewhere,
// and LocalFactorization gives the same update as local_update with the terms.
TEST(LocalUpdate, RankOneTermsHeldApartGiveTheWholeMatrixsUpdate) {
  const int n = 900;
  for (const double convection : {0.0, 0.4}) {
    SCOPED_TRACE(convection);
    const bool symmetric = convection == 0.0;
    Eigen::SparseMatrix<double> a = grid_matrix(30, 0.1, convection, 0.2, 3);
    RankOneTerms terms;
    const auto term = [&](double c, int first, int count) {
      Eigen::SparseVector<double> u(n);
      for (int i = first; i < first + count; ++i) {
        u.insert(i) = std::sin(1.0 + i);
        terms.fill_rows.push_back(i);
      }
      terms.add(c, u);
    };
    term(-3.0, 100, 60);  // K = A + U C U^T indefinite
    term(0.7, 130, 300);
    term(2.0, 580, 60);   // straddles the rows' end at 600
    term(5.0, 800, 50);   // no row of S
    term(0.0, 120, 30);
    std::vector<int> rows;
    for (int i = 0; i < 600; ++i)
      if (i % 3 != 1) rows.push_back(i);
    // The assembled part with explicit zeros where only the terms' fill would be, and one exact zero away
    // from the fill rows (the diagonal entry of row 3), which stays.
    a.coeffRef(3, 3) = 0.0;
    Eigen::SparseMatrix<double> with_zeros = a + 0.0 * terms.assembled(n);
    ASSERT_GT(with_zeros.nonZeros(), a.nonZeros());
    const Eigen::SparseMatrix<double> kss = local_matrix(with_zeros, rows, terms);
    EXPECT_EQ(kss.nonZeros(), principal_submatrix(a, rows).nonZeros());
    a.coeffRef(3, 3) = 4.1;
    const Eigen::SparseMatrix<double> kss_a = local_matrix(a + 0.0 * terms.assembled(n), rows, terms);
    Eigen::MatrixXd u;
    Eigen::VectorXd c;
    terms.on_rows(rows, u, c);
    EXPECT_EQ(u.cols(), 3);
    const Eigen::SparseMatrix<double> whole = a + terms.assembled(n);
    const Eigen::VectorXd r = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);
    Eigen::VectorXd apart, direct, kept;
    ASSERT_TRUE(local_update(r, kss_a, terms, symmetric, rows, apart));
    ASSERT_TRUE(local_update(r, principal_submatrix(whole, rows), {}, symmetric, rows, direct));
    EXPECT_LT((apart - direct).norm(), 1e-12 * direct.norm());
    LocalFactorization factor;
    for (int k = 0; k < 2; ++k) {
      ASSERT_TRUE(factor.update(r, kss_a, terms, symmetric, rows, 1, kept));
      EXPECT_EQ(kept, apart);
    }
    EXPECT_EQ(factor.analyses(), 1);
    // The terms matter: without them the update is another.
    Eigen::VectorXd without;
    ASSERT_TRUE(local_update(r, kss_a, {}, symmetric, rows, without));
    EXPECT_GT((without - direct).norm(), 1e-3 * direct.norm());
  }
}

// A sequence of updates as a local solve makes them: the same bits as local_update's, one analysis while
// the rows, the pattern's version and the symmetry stay, and a new one when any of them changes or after
// release().
TEST(LocalUpdate, AFactorizationKeepsItsAnalysisWhileRowsAndPatternStay) {
  for (const double convection : {0.0, 0.4}) {
    SCOPED_TRACE(convection);
    const bool symmetric = convection == 0.0;
    const Eigen::SparseMatrix<double> k = grid_matrix(30, 0.1, convection, 0.2, 3);
    std::vector<int> rows, other;
    for (int i = 0; i < 900; i += 3) rows.push_back(i);
    for (int i = 1; i < 900; i += 3) other.push_back(i);
    LocalFactorization factor;
    const auto same_as_alone = [&](const std::vector<int>& s, double scale, int version) {
      const Eigen::SparseMatrix<double> kss = principal_submatrix(scale * k, s);
      const Eigen::VectorXd r = Eigen::VectorXd::LinSpaced(900, -1.0, 2.0 * scale);
      Eigen::VectorXd kept, alone;
      ASSERT_TRUE(factor.update(r, kss, {}, symmetric, s, version, kept));
      ASSERT_TRUE(local_update(r, kss, {}, symmetric, s, alone));
      EXPECT_EQ(kept, alone);
    };
    same_as_alone(rows, 1.0, 1);
    same_as_alone(rows, 1.5, 1);  // other values, the same pattern
    EXPECT_EQ(factor.analyses(), 1);
    same_as_alone(rows, 2.0, 2);  // a new pattern version
    EXPECT_EQ(factor.analyses(), 2);
    same_as_alone(other, 2.0, 2);  // other rows of the same count
    EXPECT_EQ(factor.analyses(), 3);
    factor.release();
    same_as_alone(other, 2.0, 2);
    EXPECT_EQ(factor.analyses(), 4);
    EXPECT_EQ(factor.factorizations(), 5);
    // Patterns of one size and version that differ (an entry pair dropped here or there, as local_matrix
    // drops exact zeros): each is analysed.
    for (const int dropped : {0, 1}) {  // the pair (10, 0) or (11, 1): rows 1 and 31, or 4 and 34, of the grid
      Eigen::SparseMatrix<double> kss = principal_submatrix(k, other);
      ASSERT_NE(kss.coeff(10 + dropped, dropped), 0.0);
      kss.coeffRef(10 + dropped, dropped) = kss.coeffRef(dropped, 10 + dropped) = 0.0;
      kss.prune([](Eigen::Index, Eigen::Index, double v) { return v != 0.0; });
      const Eigen::VectorXd r = Eigen::VectorXd::LinSpaced(900, -1.0, 2.0);
      Eigen::VectorXd kept, alone;
      ASSERT_TRUE(factor.update(r, kss, {}, symmetric, other, 2, kept));
      ASSERT_TRUE(local_update(r, kss, {}, symmetric, other, alone));
      EXPECT_EQ(kept, alone);
    }
    EXPECT_EQ(factor.analyses(), 6);
  }
}

// A load step on `chain` from its converged state at t = 1 to t, with Newton's options as given (to 1e-12
// relative) and with `local` applied to them: the two reports and solutions, [0] without and [1] with.
struct PlainAndLocal {
  NewtonReport report[2];
  Eigen::VectorXd solution[2];
};
PlainAndLocal load_step_both_ways(NonlinearSystem& chain, double t, const std::function<void(NewtonOptions&)>& local) {
  NewtonOptions options;
  options.tol_relative = 1e-12;
  auto solver = make_linear_solver("auto", true);
  Eigen::VectorXd start = Eigen::VectorXd::Zero(chain.size());
  EXPECT_TRUE(newton_solve(chain, start, 1.0, options, *solver).converged);
  PlainAndLocal out;
  for (int with : {0, 1}) {
    NewtonOptions o = options;
    if (with) local(o);
    out.solution[with] = start;
    out.report[with] = newton_solve(chain, out.solution[with], t, o, *solver);
    EXPECT_TRUE(out.report[with].converged) << out.report[with].failure;
  }
  return out;
}

// A load step on the chain: from the converged state at t = 1 to t = 1.2. The step's residual is the load
// increment at the cubic spring, felt over ~1 / sqrt(0.04) = 5 unknowns: the local update on 200 +- 50 is
// Newton's first update but for e^-10 of its tails, so the solve then takes plain Newton's global updates:
// one factorisation fewer, the same solution to the tolerance.
TEST(NewtonLocalFirstUpdate, ReachesGlobalNewtonsSolutionWithOneFactorisationFewer) {
  Chain chain(401, 200, 0.04, 20.0);
  const PlainAndLocal both = load_step_both_ways(chain, 1.2, [](NewtonOptions& o) { o.local_share = 0.25; });
  const NewtonReport* reports = both.report;
  EXPECT_EQ(reports[0].local_updates, 0);
  EXPECT_EQ(reports[1].local_updates, 1);
  EXPECT_GE(reports[0].factorizations, 3);  // the cubic spring: a few updates to 1e-12
  EXPECT_EQ(reports[1].factorizations, reports[0].factorizations - 1);
  EXPECT_EQ(reports[1].iterations, reports[0].iterations);
  // Both stop at |r| <= 1e-12 |r_0| (|r_0| = 0.2) and the tangent's smallest eigenvalue is >= 0.04.
  EXPECT_LT((both.solution[1] - both.solution[0]).cwiseAbs().maxCoeff(), 1e-11);
}

// The chain with the unknowns around its cubic spring named as a local solve's set (local_solve_rows): after
// Newton's first global update the residual is the cubic spring's alone, which local solves on 200 +- 50
// remove to the tails' e^-10 without factorising the whole tangent again.
class ChainWithLocalPart : public Chain {
 public:
  using Chain::Chain;
  std::vector<int> local_solve_rows() const override {
    std::vector<int> rows(101);
    for (int i = 0; i <= 100; ++i) rows[static_cast<std::size_t>(i)] = 150 + i;
    return rows;
  }
};

TEST(NewtonLocalSolve, ReachesGlobalNewtonsSolutionWithFewerFactorisations) {
  ChainWithLocalPart chain(401, 200, 0.04, 20.0);
  const PlainAndLocal both = load_step_both_ways(chain, 1.5, [](NewtonOptions& o) { o.local_newton = 6; });
  const NewtonReport* reports = both.report;
  EXPECT_EQ(reports[0].local_updates, 0);
  EXPECT_GE(reports[1].local_updates, 1);
  EXPECT_GE(reports[0].factorizations, 4);  // the cubic spring: several global updates to 1e-12
  EXPECT_LT(reports[1].factorizations, reports[0].factorizations);
  // Both stop at |r| <= 1e-12 |r_0| and the tangent's smallest eigenvalue is >= 0.04.
  EXPECT_LT((both.solution[1] - both.solution[0]).cwiseAbs().maxCoeff(), 1e-10);
}

// The chain (no cubic spring) with a stiffening wall at `hard`, beta (e^(alpha q_h) - 1) = t, and a load
// t on each of its first 100 unknowns, a hundred unknowns from the wall (the response decays by e per ten
// unknowns at ground 0.01): a load step's residual is mostly that far load's, which the first global
// update removes exactly where the rest of the chain is linear (gamma = 0; gamma > 0 adds a cubic ground
// gamma q_i^3 under every unknown). The local solves' set: the wall's unknown and three on each side.
class ChainAtAWall : public Chain {
 public:
  ChainAtAWall(int n, int hard, double ground, double beta, double alpha, double gamma = 0.0)
      : Chain(n, hard, ground, 0.0), hard_(hard), beta_(beta), alpha_(alpha), gamma_(gamma) {}
  void evaluate(const Eigen::VectorXd& q, double t, bool with_tangent) override {
    Chain::evaluate(q, 0.0, with_tangent);
    const double wall = std::exp(alpha_ * q[hard_]);
    r_ = Chain::residual();
    r_.head(100).array() -= t;
    r_.array() += gamma_ * q.array().cube();
    r_[hard_] += beta_ * (wall - 1.0) - t;
    if (!with_tangent) return;
    k_ = Chain::tangent();
    k_.coeffRef(hard_, hard_) += beta_ * alpha_ * wall;
    for (int i = 0; gamma_ != 0.0 && i < k_.rows(); ++i) k_.coeffRef(i, i) += 3 * gamma_ * q[i] * q[i];
  }
  const Eigen::VectorXd& residual() const override { return r_; }
  const Eigen::SparseMatrix<double>& tangent() const override { return k_; }
  std::vector<int> local_solve_rows() const override {
    std::vector<int> rows;
    for (int i = hard_ - 3; i <= hard_ + 3; ++i) rows.push_back(i);
    return rows;
  }

 private:
  int hard_;
  double beta_, alpha_, gamma_;
  Eigen::VectorXd r_;
  Eigen::SparseMatrix<double> k_;
};

// A load step from t = 1 to 1.5 (|r_0| = 5.0): the first global update leaves 4.1e-2 on the wall, the
// local solve 1.2e-2 beside its set; the second global update (its own factorisation, made at 1.2e-2 <=
// 0.1 |r_0|) leaves 2.0e-5 on the wall, the second local solve 6.0e-6 beside the set. The update after it
// reuses the second factorisation (a chord), and so do the updates after that while each cuts |r| by 4:
// two factorisations, where without reuse the update after the second local solve factorises a third
// time. (The first local solve's contraction, 1.2e-2 / 4.1e-2 = 0.29, is above 0.25, so the reuse after a
// kept local update does not follow the second factorisation: the chord is this rule's.)
TEST(NewtonLocalSolve, AfterALocalSolveAFactorisationMadeNearTheSolutionIsReused) {
  ChainAtAWall chain(401, 200, 0.01, 1.0, 0.3);
  const PlainAndLocal chord = load_step_both_ways(chain, 1.5, [](NewtonOptions& o) {
    o.local_newton = 6;
    o.reuse_below = 0.1;
  });
  const PlainAndLocal fresh = load_step_both_ways(chain, 1.5, [](NewtonOptions& o) { o.local_newton = 6; });
  EXPECT_EQ(fresh.report[1].local_updates, 2);
  EXPECT_EQ(fresh.report[1].factorizations, 3);
  EXPECT_EQ(chord.report[1].local_updates, 2);
  EXPECT_EQ(chord.report[1].factorizations, 2);
  // Each run stops at |r| <= 1e-10 (the tolerance, or the round-off floor rule after an update below 1e-10
  // of |q|) and the tangent's smallest eigenvalue is >= 0.01: each within 1e-8 of the solution.
  for (const PlainAndLocal* both : {&chord, &fresh}) {
    for (const NewtonReport& r : both->report) EXPECT_LE(r.residual_norm, 1e-10);
    EXPECT_LT((both->solution[1] - both->solution[0]).cwiseAbs().maxCoeff(), 2e-8);
  }
}

// With the cubic ground (gamma = 0.01), from t = 1 to 5: after the first local solve the second
// factorisation (at |r| 1.2 <= 0.1 |r_0| = 4.0) is reused while the updates cut |r| by 4 (1.5e-2, 2.8e-3)
// until one does not (7.4e-4); the local solve after it leaves 1.8e-4, and its global update factorises
// again: a factorisation whose reuse has stalled is no chord after a local solve. Three factorisations
// and eight updates; chords with the stalled factorisation after each local solve instead took two and
// thirteen.
TEST(NewtonLocalSolve, AFactorisationWhoseReuseStalledIsNotReusedAfterALocalSolve) {
  ChainAtAWall chain(401, 200, 0.01, 1.0, 0.3, 0.01);
  const PlainAndLocal both = load_step_both_ways(chain, 5.0, [](NewtonOptions& o) {
    o.local_newton = 6;
    o.reuse_below = 0.1;
  });
  EXPECT_EQ(both.report[1].local_updates, 2);
  EXPECT_EQ(both.report[1].factorizations, 3);
  EXPECT_EQ(both.report[1].iterations, 8);
  for (const NewtonReport& r : both.report) EXPECT_LE(r.residual_norm, 1e-10);
  EXPECT_LT((both.solution[1] - both.solution[0]).cwiseAbs().maxCoeff(), 2e-8);
}

// K = [1 2; 2 5], r = K q - [1, 0] from q = 0: the seed is row 0 alone, whose local update (dq_0 = 1) leaves
// r = [0, 2]: |r| doubled. Newton takes it back and solves globally from q = 0 (exactly: the system is
// linear), with the one global factorisation.
TEST(NewtonLocalFirstUpdate, AnUpdateThatRaisesTheResidualIsTakenBack) {
  Eigen::Matrix2d k;
  k << 1, 2, 2, 5;
  testing::ToySystem linear(
      2, [&](const Eigen::VectorXd& q, double t) -> Eigen::VectorXd { return k * q - t * Eigen::Vector2d(1, 0); },
      [&](const Eigen::VectorXd&, double) -> Eigen::MatrixXd { return k; },
      [](const Eigen::VectorXd&, double) -> Eigen::VectorXd { return -Eigen::Vector2d(1, 0); });
  auto solver = make_linear_solver("auto", true);
  NewtonOptions options;
  options.local_share = 0.1;
  Eigen::VectorXd q = Eigen::VectorXd::Zero(2);
  const NewtonReport report = newton_solve(linear, q, 1.0, options, *solver);
  ASSERT_TRUE(report.converged);
  EXPECT_EQ(report.local_updates, 1);
  EXPECT_EQ(report.factorizations, 1);
  ASSERT_EQ(report.history.size(), 3u);  // |r_0| = 1, the same iterate evaluated again, then converged
  EXPECT_EQ(report.history[1], 1.0);
  EXPECT_LT((q - Eigen::Vector2d(5, -2)).norm(), 1e-12);
}

}  // namespace
}  // namespace fibrane::solve
