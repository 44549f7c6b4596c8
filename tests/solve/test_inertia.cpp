// LinearSolver::negative_eigenvalues() on matrices of known inertia, for every kind that reports it, and
// MUMPS's solutions against dense solves.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <algorithm>
#include <vector>

#include "linalg/direct_solvers.hpp"
#include "linalg/linear_solver.hpp"

namespace fibrane::solve {
namespace {

using SpMat = Eigen::SparseMatrix<double>;

// tridiag(-1, 2 - s, -1) of size n: eigenvalues 2 - 2 cos(k pi / (n + 1)) - s, k = 1..n.
SpMat shifted_laplacian(int n, double s) {
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, 2.0 - s);
    if (i + 1 < n) {
      t.emplace_back(i + 1, i, -1.0);
      t.emplace_back(i, i + 1, -1.0);
    }
  }
  SpMat a(n, n);
  a.setFromTriplets(t.begin(), t.end());
  return a;
}

double laplacian_eigenvalue(int n, int k) { return 2.0 - 2.0 * std::cos(k * std::numbers::pi / (n + 1)); }

// The 5-point Laplacian on an m x m grid minus s I: eigenvalues lambda_i + lambda_j - s with lambda_k the
// 1-D ones above (n = m). Returns the matrix and the number of its negative eigenvalues.
std::pair<SpMat, int> shifted_grid(int m, double s) {
  std::vector<Eigen::Triplet<double>> t;
  auto id = [m](int i, int j) { return i * m + j; };
  int negative = 0;
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) {
      if (laplacian_eigenvalue(m, i + 1) + laplacian_eigenvalue(m, j + 1) - s < 0) ++negative;
      t.emplace_back(id(i, j), id(i, j), 4.0 - s);
      if (i > 0) t.emplace_back(id(i, j), id(i - 1, j), -1.0);
      if (i + 1 < m) t.emplace_back(id(i, j), id(i + 1, j), -1.0);
      if (j > 0) t.emplace_back(id(i, j), id(i, j - 1), -1.0);
      if (j + 1 < m) t.emplace_back(id(i, j), id(i, j + 1), -1.0);
    }
  SpMat a(m * m, m * m);
  a.setFromTriplets(t.begin(), t.end());
  return {a, negative};
}

// The kinds that report the inertia of an indefinite symmetric matrix in this build.
std::vector<std::string> indefinite_kinds() {
  std::vector<std::string> kinds = {"ldlt", "auto"};
  if (mumps_available()) kinds.push_back("mumps");
  return kinds;
}

// Factorises `a` with `kind` (for "auto" with `probing`: as for a model that does not promise symmetry)
// and returns the negative count, or -2 if the factorisation failed.
int count_negative(const std::string& kind, const SpMat& a, bool probing = false) {
  auto solver = make_linear_solver(kind, !probing);
  solver->analyze(a);
  if (!solver->factorize(a)) return -2;
  return solver->negative_eigenvalues();
}

// Shifts midway between consecutive eigenvalues (k = 0: below the first, positive definite): the count
// is k, and the nearest eigenvalue is half a gap away (>= 1e-4 at n = 200), far above the factorisations'
// backward error (~1e-15 relative), so every kind must get it exactly.
TEST(Inertia, ShiftedLaplacianBetweenEigenvalues) {
  const int n = 200;
  for (const int k : {0, 1, 2, 17, 100, 199}) {
    const double s = k == 0 ? 0.5 * laplacian_eigenvalue(n, 1)
                            : 0.5 * (laplacian_eigenvalue(n, k) + laplacian_eigenvalue(n, k + 1));
    const SpMat a = shifted_laplacian(n, s);
    for (const std::string& kind : indefinite_kinds()) {
      EXPECT_EQ(count_negative(kind, a), k) << kind << " k = " << k;
    }
    EXPECT_EQ(count_negative("auto", a, true), k) << "auto (probing) k = " << k;
    // LL^T reports 0 for the definite matrix and fails (-1: unknown) for the others; LU never tells.
    auto llt = make_linear_solver("cholmod", true);
    llt->analyze(a);
    EXPECT_EQ(llt->factorize(a), k == 0) << k;
    EXPECT_EQ(llt->negative_eigenvalues(), k == 0 ? 0 : -1) << k;
    EXPECT_EQ(count_negative("umfpack", a), -1) << k;
  }
}

// Next to singular: the shift is the k-th eigenvalue times (1 -+ 1e-8), so one eigenvalue is +-1e-8
// lambda_k (>= 2.4e-12 at k = 1, n = 200) and the count is k - 1 or k. The factorisations' backward error
// (a few eps times |A| = 4 for a tridiagonal matrix, ~1e-15) is three orders below that gap. With the shift
// at an eigenvalue exactly (tridiag(-1, 0, -1) of odd size has the eigenvalue 0, and its entries are
// exact) the factorisation must fail: its sign pattern would be round-off.
TEST(Inertia, ShiftedLaplacianNextToSingular) {
  const int n = 200;
  for (const int k : {1, 50, 100}) {
    const double lambda = laplacian_eigenvalue(n, k);
    for (const std::string& kind : indefinite_kinds()) {
      EXPECT_EQ(count_negative(kind, shifted_laplacian(n, lambda * (1 - 1e-8))), k - 1) << kind << " k = " << k;
      EXPECT_EQ(count_negative(kind, shifted_laplacian(n, lambda * (1 + 1e-8))), k) << kind << " k = " << k;
    }
  }
  const SpMat singular = shifted_laplacian(201, 2.0);
  for (const std::string& kind : indefinite_kinds()) EXPECT_EQ(count_negative(kind, singular), -2) << kind;
}

// A = P^T D P with D diagonal of chosen signs and P sparse and nonsingular: by Sylvester's law of inertia
// A has as many negative eigenvalues as D has negative entries. P = (I + L) Q: L strictly lower with two
// random entries in [-0.5, 0.5] per row, Q a random permutation, so A is sparse but far from its LDL^T in
// the natural order. The expected count is checked against a dense eigensolver, as is the gap of the
// spectrum to 0 (that the count cannot depend on round-off).
TEST(Inertia, RandomCongruenceOfSignedDiagonal) {
  const int n = 300;
  std::mt19937 random(12345);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const int negatives : {0, 1, 37, 150, 299}) {
    std::vector<int> order(n);
    for (int i = 0; i < n; ++i) order[i] = i;
    std::shuffle(order.begin(), order.end(), random);
    std::vector<Eigen::Triplet<double>> t;
    for (int i = 0; i < n; ++i) {
      t.emplace_back(i, order[i], 1.0);
      for (int e = 0; e < 2 && i > 0; ++e) t.emplace_back(i, order[random() % i], unit(random) - 0.5);
    }
    SpMat p(n, n);
    p.setFromTriplets(t.begin(), t.end());
    Eigen::VectorXd d(n);
    for (int i = 0; i < n; ++i) d[i] = (i < negatives ? -1.0 : 1.0) * (0.5 + 1.5 * unit(random));
    const SpMat a = SpMat(p.transpose() * d.asDiagonal() * p).pruned();
    const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Eigen::MatrixXd(a)).eigenvalues();
    ASSERT_EQ((ev.array() < 0).count(), negatives);
    ASSERT_GT(ev.cwiseAbs().minCoeff(), 1e-8 * ev.cwiseAbs().maxCoeff());
    std::vector<std::string> kinds = {"auto", "ldlt"};
    if (mumps_available()) kinds.push_back("mumps");
    for (const std::string& kind : kinds) EXPECT_EQ(count_negative(kind, a), negatives) << kind << " " << negatives;
  }
}

// The 5-point Laplacian on a 150 x 150 grid shifted by 1.3 (22 500 unknowns, above the size where "auto"
// without MUMPS leaves the simplicial LDL^T). Its smallest |eigenvalue| is ~1e-4, far above the backward
// error of a factorisation (~1e-13), so the count is exact.
TEST(Inertia, LargeGridThroughAuto) {
  if (!mumps_available()) GTEST_SKIP() << "without MUMPS, auto uses LU here (no inertia)";
  const auto [a, negative] = shifted_grid(150, 1.3);
  EXPECT_GT(negative, 1000);
  EXPECT_EQ(count_negative("auto", a), negative);
}

// MUMPS's solution against a dense LU solve, on indefinite matrices of bounded condition number
// kappa (checked): both are backward stable, so they differ by ~kappa eps relative; kappa <= 1e4 here and
// 1e-10 leaves a margin of 50 over kappa eps, while a wrong factor or a lost entry misses by O(1). The
// same pattern is factorised again with new values (analysis reused) and the count follows.
TEST(Inertia, MumpsSolvesLikeADenseSolver) {
  if (!mumps_available()) GTEST_SKIP() << "built without MUMPS";
  const int m = 11, n = m * m;
  auto solver = make_mumps();
  for (const double s : {-0.5, 1.37, 3.11, 5.93}) {
    const auto [a, negative] = shifted_grid(m, s);
    const Eigen::MatrixXd dense(a);
    const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(dense).eigenvalues();
    ASSERT_LT(ev.cwiseAbs().maxCoeff() / ev.cwiseAbs().minCoeff(), 1e4) << s;
    if (s == -0.5) solver->analyze(a);
    ASSERT_TRUE(solver->factorize(a)) << s;
    EXPECT_EQ(solver->negative_eigenvalues(), negative) << s;
    EXPECT_EQ((ev.array() < 0).count(), negative) << s;
    const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);
    const Eigen::VectorXd ref = dense.partialPivLu().solve(b);
    EXPECT_LT((solver->solve(b) - ref).norm() / ref.norm(), 1e-10) << s;
  }
  EXPECT_EQ(solver->analysis_summary().substr(0, 7), "1 with ");
  EXPECT_GT(solver->factor_nonzeros(), n - 1);
}

// MUMPS analysed with CHOLMOD's pivot order (as "auto" does) solves as well, and reports the order as
// given, in every analysis; an order of the wrong size is ignored (MUMPS's own ordering).
TEST(Inertia, MumpsTakesCholmodsPivotOrder) {
  if (!mumps_available()) GTEST_SKIP() << "built without MUMPS";
  const auto [a, negative] = shifted_grid(30, 2.2);
  auto llt = make_cholmod_llt();
  llt->analyze(a);
  std::vector<int> order = cholmod_pivot_order(*llt);
  ASSERT_EQ(static_cast<Eigen::Index>(order.size()), a.rows());
  EXPECT_TRUE(cholmod_pivot_order(*make_umfpack()).empty());
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(a.rows(), -1.0, 2.0);
  for (const bool wrong_size : {false, true}) {
    MumpsOptions options;
    options.pivot_order = order;
    if (wrong_size) options.pivot_order.pop_back();
    auto solver = make_mumps(options);
    solver->analyze(a);
    solver->analyze(a);  // the order is kept for later analyses
    ASSERT_TRUE(solver->factorize(a));
    EXPECT_EQ(solver->negative_eigenvalues(), negative);
    EXPECT_EQ(solver->analysis_summary().find("the given order") != std::string::npos, !wrong_size);
    // Condition number of this shifted grid < 1e3 (eigenvalue gap to 2.2 > 6e-3 at m = 30): 1e-10 as above.
    EXPECT_LT((a * solver->solve(b) - b).norm() / b.norm(), 1e-10);
  }
}

}  // namespace
}  // namespace fibrane::solve
