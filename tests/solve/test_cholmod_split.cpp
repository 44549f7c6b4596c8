// CHOLMOD's LL^T in two halves at METIS's separator (make_cholmod_split_llt) against the whole
// factorisation: the same solutions to round-off, for new values, after a released factor and a new
// pattern; a half whose pattern stayed keeping its analysis; indefinite matrices refused; the pivot order a
// permutation.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "grid_matrix.hpp"
#include "linalg/cholmod_split.hpp"
#include "linalg/direct_solvers.hpp"
#include "linalg/linear_solver.hpp"

namespace fibrane::solve {
namespace {

using SpMat = Eigen::SparseMatrix<double>;

// A shifted grid Laplacian with random diagonal scaling, 4 900 unknowns: SPD (diagonal >= 6 x 0.7 > 4,
// Gershgorin), condition ~ 5 (the solutions agree to a few ulps times that).
SpMat spd(unsigned seed) { return grid_matrix(70, 2.0, 0.0, 0.3, seed); }

// The split solver for matrices from 1 000 unknowns on, with two threads.
std::unique_ptr<LinearSolver> split_solver() {
  omp_set_num_threads(2);
  return make_cholmod_split_llt({.memory_limit_megabytes = kAvailableMemory, .min_unknowns = 1000, .max_separator = 5000});
}

Eigen::VectorXd whole_solve(const SpMat& a, const Eigen::VectorXd& b) {
  auto whole = make_cholmod_llt();
  whole->analyze(a);
  EXPECT_TRUE(whole->factorize(a));
  return whole->solve(b);
}

double relative(const Eigen::VectorXd& x, const Eigen::VectorXd& ref) { return (x - ref).norm() / ref.norm(); }

TEST(CholmodSplit, SolvesAsTheWholeFactorisation) {
  const SpMat a = spd(1), a2 = spd(2);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(a.rows(), -1.0, 2.0);
  auto solver = split_solver();
  solver->analyze(a);
  const long separator = cholmod_split_separator(*solver);
  EXPECT_GT(separator, 0);
  EXPECT_LT(separator, 200);  // a line of the 70 x 70 grid, give or take
  ASSERT_TRUE(solver->factorize(a));
  EXPECT_EQ(solver->negative_eigenvalues(), 0);
  EXPECT_EQ(solver->name(), "cholmod");
  const Eigen::VectorXd x = solver->solve(b);
  EXPECT_LT(relative(x, whole_solve(a, b)), 1e-14);
  EXPECT_LT((a.selfadjointView<Eigen::Lower>() * x - b).norm(), 1e-13 * b.norm());

  // new values of the pattern
  ASSERT_TRUE(solver->factorize(a2));
  const Eigen::VectorXd ref2 = whole_solve(a2, b);
  EXPECT_LT(relative(solver->solve(b), ref2), 1e-14);
  EXPECT_GT(relative(ref2, x), 1e-6);  // the values did change the solution

  // the factor handed back and made again
  EXPECT_GT(solver->held_factor_entries(), 0);
  solver->release_factor();
  EXPECT_EQ(solver->held_factor_entries(), 0);
  ASSERT_TRUE(solver->factorize(a2));
  EXPECT_LT(relative(solver->solve(b), ref2), 1e-14);

  // several right-hand sides
  Eigen::MatrixXd columns(a.rows(), 3);
  columns << b, b.reverse(), Eigen::VectorXd::Ones(a.rows());
  const Eigen::MatrixXd xs = solver->solve_columns(columns);
  for (int j = 0; j < 3; ++j) EXPECT_LT(relative(xs.col(j), whole_solve(a2, columns.col(j))), 1e-14);
}

TEST(CholmodSplit, ANewPatternIsSplitAfresh) {
  auto solver = split_solver();
  const SpMat a = spd(1);
  solver->analyze(a);
  ASSERT_TRUE(solver->factorize(a));
  SpMat wider = a;  // couplings at distance 2 within a grid row
  for (int i = 0; i + 2 < wider.rows(); i += 3) {
    wider.coeffRef(i + 2, i) = -0.05;
    wider.coeffRef(i, i + 2) = -0.05;
  }
  wider.makeCompressed();
  solver->analyze(wider);
  ASSERT_TRUE(solver->factorize(wider));
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(a.rows());
  EXPECT_LT(relative(solver->solve(b), whole_solve(wider, b)), 1e-14);
}

// The separator rows of the solver's last analysis, sorted.
std::vector<int> separator_rows(const LinearSolver& solver) {
  std::vector<int> order = cholmod_split_pivot_order(solver);
  const long s = cholmod_split_separator(solver);
  std::vector<int> rows(order.end() - s, order.end());
  std::sort(rows.begin(), rows.end());
  return rows;
}

// a with the symmetric entries (i, j) and (j, i) added (or changed) to `value`.
SpMat with_entry(SpMat a, int i, int j, double value) {
  a.coeffRef(i, j) = value;
  a.coeffRef(j, i) = value;
  a.makeCompressed();
  return a;
}

TEST(CholmodSplit, ANewPatternWithinTheHalvesKeepsTheSeparator) {
  auto solver = split_solver();
  const SpMat a = spd(1);
  solver->analyze(a);
  const std::vector<int> order = cholmod_split_pivot_order(*solver), separator = separator_rows(*solver);
  const long s = cholmod_split_separator(*solver);
  ASSERT_GT(s, 0);
  // an entry between two rows of the first half's interior (its first two pivots): the separator stays,
  // where METIS's bisection of the new pattern (a fresh solver's) is another one
  const SpMat within = with_entry(a, order[0], order[1], -0.05);
  ASSERT_GT(within.nonZeros(), a.nonZeros());
  auto fresh = split_solver();
  fresh->analyze(within);
  ASSERT_NE(separator_rows(*fresh), separator);
  solver->analyze(within);
  EXPECT_EQ(separator_rows(*solver), separator);
  ASSERT_TRUE(solver->factorize(within));
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(a.rows(), 1.0, -1.0);
  EXPECT_LT(relative(solver->solve(b), whole_solve(within, b)), 1e-14);
  // an entry joining the two interiors (the first half's first pivot, the second's last): bisected anew
  const SpMat across = with_entry(within, order[0], order[order.size() - static_cast<std::size_t>(s) - 1], -0.05);
  solver->analyze(across);
  EXPECT_GT(cholmod_split_separator(*solver), 0);
  EXPECT_NE(separator_rows(*solver), separator);
  ASSERT_TRUE(solver->factorize(across));
  EXPECT_LT(relative(solver->solve(b), whole_solve(across, b)), 1e-14);
}

// A new pattern within one half: the other half keeps its analysis (its rows and pattern stayed). What a
// factorisation left (an indefinite half's LDL^T, where the build has MUMPS) does not carry over an analysis:
// the solutions are the bits of a fresh solver's with the same separator.
TEST(CholmodSplit, AHalfWhosePatternStayedKeepsItsAnalysis) {
  auto solver = split_solver();
  const SpMat a = spd(1);
  solver->analyze(a);
  ASSERT_TRUE(solver->factorize(a));
  EXPECT_EQ(cholmod_split_kept_analyses(*solver), (std::pair<long, long>{0, 2}));
  const std::vector<int> order = cholmod_split_pivot_order(*solver);
  const int s = static_cast<int>(cholmod_split_separator(*solver));
  const SpMat within = with_entry(a, order[0], order[1], -0.05);  // in the first half's interior
  solver->analyze(within);
  EXPECT_EQ(cholmod_split_kept_analyses(*solver), (std::pair<long, long>{1, 4}));
  SpMat indefinite = within;  // the second half's last interior pivot made negative
  const int last_interior = order[order.size() - static_cast<std::size_t>(s) - 1];
  indefinite.coeffRef(last_interior, last_interior) = -10.0;
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(a.rows(), 1.0, -1.0);
  if (solver->factorize(indefinite)) {  // with MUMPS
    EXPECT_GT(solver->negative_eigenvalues(), 0);
    EXPECT_LT((indefinite.selfadjointView<Eigen::Lower>() * solver->solve(b) - b).norm(), 1e-12 * b.norm());
  }
  solver->analyze(within);  // the same pattern again: both halves kept
  EXPECT_EQ(cholmod_split_kept_analyses(*solver), (std::pair<long, long>{3, 6}));
  auto fresh = split_solver();  // `a` first, so that it keeps the same separator for `within`
  fresh->analyze(a);
  fresh->analyze(within);
  ASSERT_EQ(cholmod_split_separator(*fresh), s);
  ASSERT_TRUE(solver->factorize(within));
  ASSERT_TRUE(fresh->factorize(within));
  EXPECT_EQ(solver->negative_eigenvalues(), 0);
  const Eigen::VectorXd x = solver->solve(b);
  EXPECT_TRUE(x == fresh->solve(b));
  EXPECT_LT(relative(x, whole_solve(within, b)), 1e-14);
}

// An indefinite matrix takes the LDL^T in the halves and the separator's front where the build has MUMPS
// (test_separator_tree.cpp has the solutions), and is refused otherwise; the pattern serves again.
TEST(CholmodSplit, AnIndefiniteMatrixIsFactorisedByLdltOrRefused) {
  auto solver = split_solver();
  const SpMat a = grid_matrix(70, -1.3, 0.0);  // the Laplacian shifted below its smallest eigenvalues
  solver->analyze(a);
  ASSERT_GT(cholmod_split_separator(*solver), 0);
  if (mumps_available()) {
    ASSERT_TRUE(solver->factorize(a));
    EXPECT_EQ(solver->negative_eigenvalues(), grid_negative_eigenvalues(70, -1.3));
  } else {
    EXPECT_FALSE(solver->factorize(a));
    EXPECT_EQ(solver->negative_eigenvalues(), -1);
  }
  ASSERT_TRUE(solver->factorize(grid_matrix(70, 0.1, 0.0)));
  EXPECT_EQ(solver->negative_eigenvalues(), 0);
}

TEST(CholmodSplit, ThePivotOrderIsAPermutation) {
  auto solver = split_solver();
  const SpMat a = spd(1);
  solver->analyze(a);
  std::vector<int> order = cholmod_pivot_order(*solver);
  ASSERT_EQ(order.size(), static_cast<std::size_t>(a.rows()));
  std::sort(order.begin(), order.end());
  std::vector<int> identity(order.size());
  std::iota(identity.begin(), identity.end(), 0);
  EXPECT_EQ(order, identity);
}

// The solver factorises spd(1) whole: no separator, and the whole factorisation's solution to the last bit.
void expect_factorised_whole(LinearSolver& solver) {
  const SpMat a = spd(1);
  solver.analyze(a);
  EXPECT_EQ(cholmod_split_separator(solver), 0);
  EXPECT_EQ(solver.analysis_summary().find("two halves"), std::string::npos);
  ASSERT_TRUE(solver.factorize(a));
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(a.rows());
  EXPECT_EQ((solver.solve(b) - whole_solve(a, b)).cwiseAbs().maxCoeff(), 0.0);
}

TEST(CholmodSplit, SmallMatricesAreFactorisedWhole) {
  omp_set_num_threads(2);
  expect_factorised_whole(*make_cholmod_split_llt());  // from 100 000 unknowns on
}

TEST(CholmodSplit, AHalfWithMostOfTheWorkLeavesTheMatrixWhole) {
  omp_set_num_threads(2);
  // No split gives a half less than half of the flops: every matrix is factorised whole.
  expect_factorised_whole(*make_cholmod_split_llt({.memory_limit_megabytes = kAvailableMemory, .min_unknowns = 1000,
                                                   .max_separator = 5000, .max_work_share = 0.49}));
}

// "auto" at 100 489 unknowns: the split factorises an indefinite Laplacian (its LDL^T where the LL^T finds
// a domain or front not positive definite) and counts its negative eigenvalues, known in closed form.
TEST(CholmodSplit, AutoFactorisesAnIndefiniteMatrixInTheSplit) {
  if (!mumps_available()) GTEST_SKIP() << "built without MUMPS";
  omp_set_num_threads(2);
  const int m = 317;
  const double shift = -0.002;
  const SpMat a = grid_matrix(m, shift, 0.0);
  const int negative = grid_negative_eigenvalues(m, shift);
  ASSERT_GT(negative, 0);
  auto solver = make_linear_solver("auto", true, /*split=*/true);
  solver->analyze(a);
  EXPECT_NE(solver->analysis_summary().find("two halves"), std::string::npos) << solver->analysis_summary();
  ASSERT_TRUE(solver->factorize(a));
  EXPECT_EQ(solver->negative_eigenvalues(), negative);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(a.rows(), -1.0, 2.0);
  EXPECT_LT((a * solver->solve(b) - b).norm(), 1e-10 * b.norm());
  // and a positive definite matrix of the pattern goes back to the split LL^T
  const SpMat spd_a = grid_matrix(m, 0.1, 0.0);
  ASSERT_TRUE(solver->factorize(spd_a));
  EXPECT_EQ(solver->negative_eigenvalues(), 0);
  EXPECT_LT((spd_a * solver->solve(b) - b).norm(), 1e-12 * b.norm());
}

}  // namespace
}  // namespace fibrane::solve
