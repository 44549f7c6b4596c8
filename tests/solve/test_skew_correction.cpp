// Unsymmetric matrices whose skew part lives on a few rows (fibrane's tangents with point moments on beam
// ends): "auto" solves them through a symmetric factorisation and SkewCorrection's exact low-rank term, and
// takes the LU for a skew part on more rows.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "grid_matrix.hpp"
#include "linalg/direct_solvers.hpp"
#include "linalg/linear_solver.hpp"
#include "linalg/skew_correction.hpp"
#include "linalg/symmetry_probe.hpp"

namespace fibrane::solve {
namespace {

using SpMat = Eigen::SparseMatrix<double>;

// The symmetric grid matrix (m x m points, positive definite: its smallest eigenvalue is above 0.5 - 0.23)
// with an unsymmetric coupling added between each grid point of `rows` and the next: entries (i, i + 1) and
// (i + 1, i) get w and -0.9 w, w in [1, 3] (the symmetric part changes by 0.05 w, keeping it definite).
SpMat with_skew_rows(int m, const std::vector<int>& rows, unsigned seed) {
  SpMat a = grid_matrix(m, 0.5, 0.0, 0.05, seed);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.5, 1.5);
  for (int i : rows) {
    const double w = 2.0 * u(rng);
    a.coeffRef(i, i + 1) += w;
    a.coeffRef(i + 1, i) -= 0.9 * w;
  }
  a.makeCompressed();
  return a;
}

// (a + a^T) / 2 with each diagonal entry of `rows` raised to its row's sum of off-diagonal magnitudes where
// that is larger, from dense matrices.
Eigen::MatrixXd dominated_symmetric_part(const SpMat& a, const std::vector<int>& rows) {
  Eigen::MatrixXd s = 0.5 * (Eigen::MatrixXd(a) + Eigen::MatrixXd(a).transpose());
  for (int i : rows) {
    const double off = s.row(i).cwiseAbs().sum() - std::abs(s(i, i));
    s(i, i) = std::max(s(i, i), off);
  }
  return s;
}

TEST(SkewCorrection, ProbeFindsTheSkewRowsAndSymmetrizeWritesTheSymmetricPartInPlace) {
  const SpMat a = with_skew_rows(20, {5, 47, 203}, 1);
  SymmetryProbe probe;
  probe.build(a);
  EXPECT_FALSE(probe.symmetric(a));
  const std::vector<int> support = probe.skew_support(a);
  EXPECT_EQ(support, (std::vector<int>{5, 6, 47, 48, 203, 204}));
  SpMat k = a;
  SkewCorrection correction;
  ASSERT_TRUE(correction.symmetrize(k, support));
  EXPECT_EQ(correction.rank(), 6);
  // The block's entries are averages of two values and the diagonals sums of a row: 1e-15 relative.
  EXPECT_LT((Eigen::MatrixXd(k) - dominated_symmetric_part(a, support)).norm(), 1e-14 * a.norm());
  EXPECT_TRUE(probe.symmetric(k));
  correction.restore(k);
  EXPECT_TRUE(std::equal(k.valuePtr(), k.valuePtr() + k.nonZeros(), a.valuePtr()));  // to the last bit

  SpMat unmatched = a;
  unmatched.coeffRef(48, 5) = 1.0;  // no (5, 48): the block's pattern is unsymmetric
  unmatched.makeCompressed();
  const SpMat before = unmatched;
  EXPECT_FALSE(correction.symmetrize(unmatched, support));
  EXPECT_EQ(correction.rank(), 0);
  EXPECT_TRUE(std::equal(unmatched.valuePtr(), unmatched.valuePtr() + unmatched.nonZeros(), before.valuePtr()));
}

// The probe of some rows compares only the entries whose row and column are both among them: where they
// hold the skew part it agrees with the whole probe; a skew part outside them is not seen (the caller's
// promise that there is none); a missing mirror inside them makes the pattern unsymmetric.
TEST(SkewCorrection, ProbeOfSomeRowsComparesOnlyThem) {
  const SpMat a = with_skew_rows(20, {5, 47, 203}, 1);
  SymmetryProbe whole, rows;
  whole.build(a);
  rows.build(a, {4, 5, 6, 46, 47, 48, 49, 203, 204, 399});
  EXPECT_TRUE(rows.structurally_symmetric());
  EXPECT_EQ(rows.size(), a.nonZeros());
  EXPECT_FALSE(rows.symmetric(a));
  EXPECT_EQ(rows.skew_support(a), whole.skew_support(a));
  SpMat s = a;
  SkewCorrection correction;
  ASSERT_TRUE(correction.symmetrize(s, rows.skew_support(a)));
  EXPECT_TRUE(rows.symmetric(s));
  EXPECT_TRUE(whole.symmetric(s));

  SymmetryProbe some;
  some.build(a, {5, 6, 47, 48});
  EXPECT_EQ(some.skew_support(a), (std::vector<int>{5, 6, 47, 48}));

  SpMat b = a;
  b.coeffRef(399, 4) = 1.0;  // no (4, 399)
  b.makeCompressed();
  SymmetryProbe block;
  block.build(b, {4, 5, 6, 399});
  EXPECT_FALSE(block.structurally_symmetric());
  EXPECT_FALSE(block.symmetric(b));
  block.build(b, {5, 6});
  EXPECT_TRUE(block.structurally_symmetric());
}

TEST(SkewCorrection, ProbeSharesTheColumnsAmongThreads) {
  // A 300 x 300 grid (90 000 unknowns, ~450 000 entries: above the probe's serial limit) with skew rows at
  // both ends of the column range, where two threads' shares begin and end; the support must be the same
  // at 1 and 2 threads, and a symmetric matrix's empty.
  const SpMat a = with_skew_rows(300, {0, 44998, 89998}, 3);
  SymmetryProbe probe;
  probe.build(a);
  const std::vector<int> expected{0, 1, 44998, 44999, 89998, 89999};
  for (int threads : {1, 2}) {
    set_thread_count(threads);
    EXPECT_EQ(probe.skew_support(a), expected) << threads << " threads";
    EXPECT_FALSE(probe.symmetric(a));
    SpMat s = a;
    SkewCorrection correction;
    ASSERT_TRUE(correction.symmetrize(s, expected));
    EXPECT_TRUE(probe.skew_support(s).empty());
    EXPECT_TRUE(probe.symmetric(s));
  }
}

TEST(SkewCorrection, AutoSolvesThroughTheSymmetricPartAsTheLuDoes) {
  // 40 x 40 grid (1 600 unknowns) with a skew part on 8 rows; two matrices of the same pattern.
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(1600, -1.0, 2.0);
  auto solver = make_linear_solver("auto", false);
  for (unsigned seed : {1u, 2u}) {
    const SpMat a = with_skew_rows(40, {100, 101 + static_cast<int>(seed), 700, 1200}, seed);
    if (seed == 1) solver->analyze(a);
    const SpMat given = a;
    ASSERT_TRUE(solver->factorize(a)) << solver->failure_detail();
    EXPECT_EQ(solver->name(), "symmetric-part(auto(cholmod))+rank-8");
    // S was factorised in a's storage, and a's values are back to the last bit.
    EXPECT_TRUE(std::equal(a.valuePtr(), a.valuePtr() + a.nonZeros(), given.valuePtr()));
    EXPECT_EQ(solver->negative_eigenvalues(), -1);  // the symmetric part's inertia is not a's
    const Eigen::VectorXd x = solver->solve(b);
    const Eigen::VectorXd reference = Eigen::MatrixXd(a).partialPivLu().solve(b);
    // Both are backward-stable solves of a matrix of condition ~10: they agree to ~1e-14; a missing or
    // wrong correction term misses by O(1).
    EXPECT_LT((x - reference).norm() / reference.norm(), 1e-11);
    EXPECT_LT((a * x - b).norm() / b.norm(), 1e-12);
    const Eigen::MatrixXd columns = solver->solve_columns(Eigen::MatrixXd(b.replicate(1, 2)));
    EXPECT_LT((columns.col(1) - x).norm() / x.norm(), 1e-14);
  }
}

// "auto" compares only the rows its caller names (LinearSolver::set_skew_candidates): with the skew rows
// among them it solves as the LU does; told that no row can be unsymmetric, it takes the symmetric chain
// (the caller's promise, which it does not check).
TEST(SkewCorrection, AutoProbesOnlyTheNamedRows) {
  const SpMat a = with_skew_rows(40, {100, 700, 1200}, 1);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(1600, -1.0, 2.0);
  auto named = make_linear_solver("auto", false);
  named->set_skew_candidates(std::vector<int>{99, 100, 101, 102, 699, 700, 701, 1200, 1201});
  named->analyze(a);
  ASSERT_TRUE(named->factorize(a)) << named->failure_detail();
  EXPECT_EQ(named->name(), "symmetric-part(auto(cholmod))+rank-6");
  const Eigen::VectorXd x = named->solve(b);
  const Eigen::VectorXd reference = Eigen::MatrixXd(a).partialPivLu().solve(b);
  EXPECT_LT((x - reference).norm() / reference.norm(), 1e-11);  // as in the test above

  auto promised = make_linear_solver("auto", false);
  promised->set_skew_candidates(std::vector<int>{});
  promised->analyze(a);
  // The chain reads a's lower triangle alone, which need not be definite: its LL^T or LDL^T.
  ASSERT_TRUE(promised->factorize(a));
  EXPECT_EQ(promised->name().rfind("symmetric-auto(", 0), 0u) << promised->name();
}

TEST(SkewCorrection, IndefinitenessInTheSkewRowsStaysWithTheCorrection) {
  // The diagonal of the skew rows lowered by 10 (far below the grid's smallest eigenvalue): the symmetric
  // part is indefinite there, as a point moment's load stiffness makes it. Made diagonally dominant in
  // those rows, it is positive definite again, and the correction takes the difference back.
  SpMat a = with_skew_rows(40, {300, 900}, 4);
  for (int i : {300, 301, 900, 901}) a.coeffRef(i, i) -= 10.0;
  auto solver = make_linear_solver("auto", false);
  solver->analyze(a);
  ASSERT_TRUE(solver->factorize(a)) << solver->failure_detail();
  EXPECT_EQ(solver->name(), "symmetric-part(auto(cholmod))+rank-4");
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(a.rows(), 1.0, -1.0);
  const Eigen::VectorXd reference = Eigen::MatrixXd(a).partialPivLu().solve(b);
  EXPECT_LT((solver->solve(b) - reference).norm() / reference.norm(), 1e-11);
}

TEST(SkewCorrection, ANewPatternOfTheSameSizeIsSolvedWithItsOwnSymmetricPart) {
  // Rows 39 and 79 end a grid row, so the coupling to the next point adds two entries outside the grid's
  // pattern: the two matrices have as many entries but different patterns.
  const SpMat first = with_skew_rows(40, {39, 500}, 5), second = with_skew_rows(40, {79, 500}, 5);
  ASSERT_EQ(first.nonZeros(), second.nonZeros());
  ASSERT_NE(SpMat(first - second).norm(), 0.0);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(first.rows(), 1.0, 3.0);
  auto solver = make_linear_solver("auto", false);
  for (const SpMat* a : {&first, &second}) {
    solver->analyze(*a);
    ASSERT_TRUE(solver->factorize(*a)) << solver->failure_detail();
    EXPECT_EQ(solver->name(), "symmetric-part(auto(cholmod))+rank-4");
    EXPECT_LT((*a * solver->solve(b) - b).norm() / b.norm(), 1e-12);
  }
}

TEST(SkewCorrection, SkewOnManyRowsTakesTheLu) {
  std::vector<int> rows;
  for (int i = 0; i < 30; ++i) rows.push_back(40 * i + 3);  // 60 skew rows, above the limit of 48
  const SpMat a = with_skew_rows(40, rows, 3);
  auto solver = make_linear_solver("auto", false);
  solver->analyze(a);
  ASSERT_TRUE(solver->factorize(a));
  EXPECT_EQ(solver->name(), mumps_available() ? "mumps-lu" : "umfpack64");
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(a.rows());
  EXPECT_LT((a * solver->solve(b) - b).norm() / b.norm(), 1e-12);
}

// One factor at a time on the skew path too: while the LU serves, the symmetric chain's factor is freed
// (its analysis kept); when the chain serves again, the LU is gone. A held factor beside the other is what
// pushed the 1.1 M membrane beyond 24 GiB (docs/performance.md, "The memory estimate").
TEST(SkewCorrection, SwitchingToTheLuAndBackHoldsOneFactor) {
  std::vector<int> wide_rows;
  for (int i = 0; i < 30; ++i) wide_rows.push_back(40 * i + 3);  // 60 skew rows: the LU
  const SpMat narrow = with_skew_rows(40, {100, 700}, 1), wide = with_skew_rows(40, wide_rows, 3);
  ASSERT_EQ(narrow.nonZeros(), wide.nonZeros());  // the same pattern: no new analysis between them
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(narrow.rows(), -1.0, 1.0);
  auto solver = make_linear_solver("auto", false);
  solver->analyze(narrow);
  ASSERT_TRUE(solver->factorize(narrow)) << solver->failure_detail();
  EXPECT_EQ(solver->name(), "symmetric-part(auto(cholmod))+rank-4");
  const long chain_entries = solver->held_factor_entries();
  ASSERT_GT(chain_entries, 0);
  for (int round = 0; round < 2; ++round) {
    ASSERT_TRUE(solver->factorize(wide)) << solver->failure_detail();
    EXPECT_EQ(solver->name(), mumps_available() ? "mumps-lu" : "umfpack64");
    EXPECT_EQ(solver->held_factor_entries(), solver->factor_nonzeros());  // the LU's alone
    EXPECT_LT((wide * solver->solve(b) - b).norm() / b.norm(), 1e-12);
    ASSERT_TRUE(solver->factorize(narrow)) << solver->failure_detail();
    EXPECT_EQ(solver->name(), "symmetric-part(auto(cholmod))+rank-4");
    EXPECT_EQ(solver->held_factor_entries(), chain_entries);  // the chain's alone
    EXPECT_LT((narrow * solver->solve(b) - b).norm() / b.norm(), 1e-12);
  }
  solver->release_factor();
  EXPECT_EQ(solver->held_factor_entries(), 0);
  ASSERT_TRUE(solver->factorize(narrow));
  EXPECT_LT((narrow * solver->solve(b) - b).norm() / b.norm(), 1e-12);
}

// Newton marks a step's first matrix before the first analysis; the skew path passes the mark on to the
// symmetric chain with that matrix, so its step rule (LinearSolver.AutoStartsAStep...) holds from the first
// step on: after a first step that started indefinite, the second step's first matrix goes to the LDL^T.
TEST(SkewCorrection, StepMarksReachTheSymmetricChain) {
  const SpMat spd = with_skew_rows(8, {5, 20}, 1);
  SpMat indefinite = spd;
  for (int i = 0; i < indefinite.rows(); ++i) indefinite.coeffRef(i, i) -= 1.8;
  auto solver = make_linear_solver("auto", false);
  auto factorize = [&](const SpMat& a) {
    EXPECT_TRUE(solver->factorize(a)) << solver->failure_detail();
    return solver->name();
  };
  solver->begin_step();
  solver->analyze(spd);
  EXPECT_EQ(factorize(indefinite).find("cholmod"), std::string::npos);
  EXPECT_EQ(factorize(spd).find("cholmod"), std::string::npos);  // the rule within a step
  EXPECT_NE(factorize(spd).find("symmetric-part(auto(cholmod))"), std::string::npos);
  solver->begin_step();
  EXPECT_EQ(factorize(spd).find("cholmod"), std::string::npos);  // the last step's first was indefinite
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(64, -1.0, 2.0);
  EXPECT_LT((spd * solver->solve(b) - b).norm(), 1e-10 * b.norm());
}

}  // namespace
}  // namespace fibrane::solve
