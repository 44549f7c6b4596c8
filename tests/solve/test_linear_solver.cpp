// Every solver kind against a dense LU reference on SPD, symmetric indefinite and unsymmetric matrices.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <string_view>

#include "common/error.hpp"
#include "grid_matrix.hpp"
#include "linalg/direct_solvers.hpp"
#include "linalg/linear_solver.hpp"

namespace fibrane::solve {
namespace {

using SpMat = Eigen::SparseMatrix<double>;

double relative_error(const Eigen::VectorXd& x, const Eigen::VectorXd& ref) { return (x - ref).norm() / ref.norm(); }

// The fallback of "auto" after a failed LL^T: MUMPS where the build has it.
std::string auto_fallback(const char* without_mumps) {
  return mumps_available() ? "auto(mumps)" : std::string("auto(") + without_mumps + ")";
}

// The LU that "auto" takes for an unsymmetric matrix.
std::string lu_name() { return mumps_available() ? "mumps-lu" : "umfpack64"; }

// The symmetric kinds this build has, for the given list.
std::vector<const char*> available(std::vector<const char*> kinds) {
  if (!mumps_available()) std::erase(kinds, std::string_view("mumps"));
  return kinds;
}

struct Case {
  const char* label;
  SpMat a;
  bool symmetric;
  std::vector<const char*> kinds;  // kinds that must succeed
};

TEST(LinearSolver, AllKindsAgreeWithDenseLu) {
  const int m = 12;
  // Shift -1.3 makes the Laplacian indefinite; the eigenvalue gap to 1.3 is checked below so the
  // reference solve is well conditioned.
  std::vector<Case> cases = {
      {"spd", grid_matrix(m, 0.1, 0.0), true, available({"cholmod", "ldlt", "mumps", "umfpack", "auto"})},
      {"indefinite", grid_matrix(m, -1.3, 0.0), true, available({"ldlt", "mumps", "umfpack", "auto"})},
      {"unsymmetric", grid_matrix(m, 0.1, 0.7), false,
       mumps_available() ? std::vector<const char*>{"umfpack", "umfpack64", "mumps-lu", "auto"}
                         : std::vector<const char*>{"umfpack", "umfpack64", "auto"}},
  };
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(m * m, -1.0, 2.0);
  for (const Case& c : cases) {
    const Eigen::MatrixXd dense(c.a);
    if (c.symmetric) {
      const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(dense).eigenvalues();
      ASSERT_GT(ev.cwiseAbs().minCoeff(), 1e-3) << c.label;
    }
    const Eigen::VectorXd ref = dense.partialPivLu().solve(b);
    for (const char* kind : c.kinds) {
      auto solver = make_linear_solver(kind, c.symmetric);
      solver->analyze(c.a);
      ASSERT_TRUE(solver->factorize(c.a)) << c.label << " " << kind;
      // Condition numbers here are below 1e4, so direct solvers agree to ~1e-12; allow 1e-10.
      EXPECT_LT(relative_error(solver->solve(b), ref), 1e-10) << c.label << " " << kind;
      EXPECT_GE(solver->factor_nonzeros(), m * m) << c.label << " " << kind;  // at least the diagonal
    }
  }
}

// A new pattern after a factorisation: the analysis frees the last factor and hands the memory back
// (MUMPS through a fresh instance with the same settings), and the solver works on the new matrix.
TEST(LinearSolver, EveryKindSolvesAfterANewPattern) {
  const std::vector<std::pair<bool, std::vector<const char*>>> kinds = {
      {true, available({"cholmod", "ldlt", "mumps", "auto"})},
      {false, mumps_available() ? std::vector<const char*>{"umfpack", "umfpack64", "mumps-lu"}
                                : std::vector<const char*>{"umfpack", "umfpack64"}}};
  for (const auto& [symmetric, names] : kinds)
    for (const char* kind : names) {
      auto solver = make_linear_solver(kind, symmetric);
      for (int m : {10, 13}) {
        const Eigen::SparseMatrix<double> a = grid_matrix(m, 0.1, symmetric ? 0.0 : 0.7);
        const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(m * m, -1.0, 2.0);
        solver->analyze(a);
        ASSERT_TRUE(solver->factorize(a)) << kind << " at " << m;
        EXPECT_LT(relative_error(solver->solve(b), Eigen::MatrixXd(a).partialPivLu().solve(b)), 1e-10) << kind;
        if (symmetric && std::string(kind) != "cholmod") {
          EXPECT_EQ(solver->negative_eigenvalues(), 0) << kind;
        }
      }
    }
}

TEST(LinearSolver, CholeskyRejectsIndefiniteAndAutoFallsBack) {
  const SpMat a = grid_matrix(8, -1.3, 0.0);
  auto llt = make_linear_solver("cholmod", true);
  llt->analyze(a);
  EXPECT_FALSE(llt->factorize(a));
  auto automatic = make_linear_solver("auto", true);
  automatic->analyze(a);
  ASSERT_TRUE(automatic->factorize(a));
  EXPECT_EQ(automatic->name(), auto_fallback("ldlt"));
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(64);
  EXPECT_LT((a * automatic->solve(b) - b).norm(), 1e-10 * b.norm());
}

// One indefinite matrix (a wild Newton iterate) must not keep "auto" off the Cholesky factorisation: the
// next matrix goes to the indefinite solver first, and once that finds it positive definite, LL^T is first
// again. While matrices stay indefinite (past a limit point), they go to the indefinite solver directly.
TEST(LinearSolver, AutoReturnsToCholeskyAfterAnIndefiniteMatrix) {
  const SpMat indefinite = grid_matrix(8, -1.3, 0.0), spd = grid_matrix(8, 0.1, 0.0);  // same pattern
  const SpMat other_indefinite = grid_matrix(8, -2.1, 0.0);
  auto automatic = make_linear_solver("auto", true);
  automatic->analyze(spd);
  ASSERT_TRUE(automatic->factorize(indefinite));
  EXPECT_EQ(automatic->name(), auto_fallback("ldlt"));
  const int negative = automatic->negative_eigenvalues();
  EXPECT_GT(negative, 0);
  ASSERT_TRUE(automatic->factorize(other_indefinite));
  EXPECT_EQ(automatic->name(), auto_fallback("ldlt"));
  EXPECT_GT(automatic->negative_eigenvalues(), negative);  // a larger shift: more negative eigenvalues
  ASSERT_TRUE(automatic->factorize(spd));
  EXPECT_EQ(automatic->name(), auto_fallback("ldlt"));
  EXPECT_EQ(automatic->negative_eigenvalues(), 0);
  ASSERT_TRUE(automatic->factorize(spd));
  EXPECT_EQ(automatic->name(), "auto(cholmod)");
  EXPECT_EQ(automatic->negative_eigenvalues(), 0);
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(64);
  EXPECT_LT((spd * automatic->solve(b) - b).norm(), 1e-10 * b.norm());  // condition number < 1e3
}

// A step's first matrix goes to the indefinite solver first where the last step's first was indefinite (a
// predictor that overshoots at every step), and to LL^T again once such a matrix is positive definite; the
// matrices within a step keep the rule above.
TEST(LinearSolver, AutoStartsAStepWhereTheLastStepsFirstMatrixNeededTheFallback) {
  const SpMat indefinite = grid_matrix(8, -1.3, 0.0), spd = grid_matrix(8, 0.1, 0.0);  // same pattern
  auto automatic = make_linear_solver("auto", true);
  automatic->analyze(spd);
  auto factorize = [&](const SpMat& a) {
    EXPECT_TRUE(automatic->factorize(a));
    return automatic->name();
  };
  automatic->begin_step();
  EXPECT_EQ(factorize(indefinite), auto_fallback("ldlt"));  // LL^T failed first
  EXPECT_EQ(factorize(spd), auto_fallback("ldlt"));         // the rule within a step
  EXPECT_EQ(factorize(spd), "auto(cholmod)");
  automatic->begin_step();
  EXPECT_EQ(factorize(indefinite), auto_fallback("ldlt"));  // straight to the fallback
  EXPECT_GT(automatic->negative_eigenvalues(), 0);
  EXPECT_EQ(factorize(spd), auto_fallback("ldlt"));
  EXPECT_EQ(factorize(spd), "auto(cholmod)");
  EXPECT_EQ(factorize(spd), "auto(cholmod)");  // not a step's first: LL^T
  automatic->begin_step();
  EXPECT_EQ(factorize(spd), auto_fallback("ldlt"));  // predicted indefinite, found positive definite
  EXPECT_EQ(automatic->negative_eigenvalues(), 0);
  automatic->begin_step();
  EXPECT_EQ(factorize(spd), "auto(cholmod)");
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(64);
  EXPECT_LT((spd * automatic->solve(b) - b).norm(), 1e-10 * b.norm());
}

// "auto" holds one numeric factor at a time: the LL^T's values (of a failed attempt too) are freed before
// the fallback factorises, and the fallback goes before LL^T factorises; each solve is still exact. A
// released CHOLMOD factor keeps its analysis and factorises again.
TEST(LinearSolver, AutoHoldsOneFactorAtATime) {
  const SpMat indefinite = grid_matrix(30, -1.3, 0.0), spd = grid_matrix(30, 0.1, 0.0);  // same pattern
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(spd.rows());
  auto llt = make_cholmod_llt();
  llt->analyze(spd);
  ASSERT_TRUE(llt->factorize(spd));
  const long llt_entries = llt->held_factor_entries();
  ASSERT_GT(llt_entries, 0);
  llt->release_factor();
  EXPECT_EQ(llt->held_factor_entries(), 0);
  ASSERT_TRUE(llt->factorize(spd));
  EXPECT_EQ(llt->held_factor_entries(), llt_entries);
  EXPECT_LT((spd * llt->solve(b) - b).norm(), 1e-10 * b.norm());
  // CHOLMOD's simplicial LDL^T (the fallback of builds without MUMPS) likewise.
  auto ldlt = make_cholmod_ldlt();
  ldlt->analyze(indefinite);
  ASSERT_TRUE(ldlt->factorize(indefinite));
  const long ldlt_entries = ldlt->held_factor_entries();
  EXPECT_EQ(ldlt_entries, ldlt->factor_nonzeros());
  ldlt->release_factor();
  EXPECT_EQ(ldlt->held_factor_entries(), 0);
  ASSERT_TRUE(ldlt->factorize(indefinite));
  EXPECT_EQ(ldlt->held_factor_entries(), ldlt_entries);
  EXPECT_GT(ldlt->negative_eigenvalues(), 0);
  EXPECT_LT((indefinite * ldlt->solve(b) - b).norm(), 1e-8 * b.norm());

  auto automatic = make_linear_solver("auto", true);
  automatic->analyze(spd);
  ASSERT_TRUE(automatic->factorize(indefinite));  // LL^T fails, the fallback factorises
  EXPECT_EQ(automatic->name(), auto_fallback("ldlt"));
  EXPECT_GT(automatic->held_factor_entries(), 0);
  EXPECT_EQ(automatic->held_factor_entries(), automatic->factor_nonzeros());  // the fallback's alone
  EXPECT_LT((indefinite * automatic->solve(b) - b).norm(), 1e-8 * b.norm());
  ASSERT_TRUE(automatic->factorize(spd));  // the fallback again (the last was indefinite)
  ASSERT_TRUE(automatic->factorize(spd));  // LL^T
  EXPECT_EQ(automatic->name(), "auto(cholmod)");
  EXPECT_EQ(automatic->held_factor_entries(), llt_entries);  // LL^T's alone
  EXPECT_LT((spd * automatic->solve(b) - b).norm(), 1e-10 * b.norm());
  ASSERT_TRUE(automatic->factorize(indefinite));  // the fallback, analysed anew
  EXPECT_EQ(automatic->held_factor_entries(), automatic->factor_nonzeros());
  EXPECT_LT((indefinite * automatic->solve(b) - b).norm(), 1e-8 * b.norm());
}

// Above 20 000 unknowns an indefinite matrix goes to MUMPS where the build has it, otherwise it skips
// the simplicial LDL^T (too slow there) and goes to LU.
TEST(LinearSolver, AutoFallsBackForLargeIndefiniteMatrices) {
  const SpMat a = grid_matrix(150, -1.3, 0.0);  // 22 500 unknowns; shifted Laplacian, indefinite
  auto automatic = make_linear_solver("auto", true);
  automatic->analyze(a);
  ASSERT_TRUE(automatic->factorize(a));
  EXPECT_EQ(automatic->name(), auto_fallback("umfpack64"));
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(a.rows());
  // The smallest |eigenvalue| of this shift is ~1e-3 (eigenvalues 4 - 2cos - 2cos - 1.3 on a fine grid
  // pass close to 0), so allow 1e-8 relative residual; a wrong factorisation misses by O(1).
  EXPECT_LT((a * automatic->solve(b) - b).norm(), 1e-8 * b.norm());
}

// "auto" for a model that cannot promise symmetry: a symmetric matrix goes to the Cholesky chain, an
// unsymmetric one (or one that turns unsymmetric between factorisations, same pattern) to LU. Solutions
// are checked by their residual: condition numbers are below 1e3 here, so 1e-10 leaves a wide margin over
// round-off while a wrong factor (e.g. LL^T of the lower triangle of an unsymmetric matrix) misses by O(1).
TEST(LinearSolver, AutoProbesSymmetryOfUnpromisedMatrices) {
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(100, -1.0, 2.0);
  const SpMat symmetric = grid_matrix(10, 0.1, 0.0);
  const SpMat unsymmetric = grid_matrix(10, 0.1, 0.7);  // same pattern, convection part
  auto solver = make_linear_solver("auto", false);
  solver->analyze(symmetric);
  ASSERT_TRUE(solver->factorize(symmetric));
  EXPECT_EQ(solver->name(), "symmetric-auto(cholmod)");
  EXPECT_LT((symmetric * solver->solve(b) - b).norm(), 1e-10 * b.norm());
  ASSERT_TRUE(solver->factorize(unsymmetric));
  EXPECT_EQ(solver->name(), lu_name());
  EXPECT_LT((unsymmetric * solver->solve(b) - b).norm(), 1e-10 * b.norm());
  ASSERT_TRUE(solver->factorize(symmetric));
  EXPECT_EQ(solver->name(), "symmetric-auto(cholmod)");

  // Round-off-level asymmetry (1e-15 relative, what summation order leaves) still counts as symmetric.
  SpMat nearly = symmetric;
  nearly.coeffRef(3, 4) *= 1.0 + 1e-15;
  solver->analyze(nearly);
  ASSERT_TRUE(solver->factorize(nearly));
  EXPECT_EQ(solver->name(), "symmetric-auto(cholmod)");

  // A pattern that is not structurally symmetric goes to LU directly.
  SpMat lopsided = symmetric;
  lopsided.coeffRef(0, 50) = 0.3;
  lopsided.makeCompressed();
  solver->analyze(lopsided);
  ASSERT_TRUE(solver->factorize(lopsided));
  EXPECT_EQ(solver->name(), lu_name());
  EXPECT_LT((lopsided * solver->solve(b) - b).norm(), 1e-10 * b.norm());
}

TEST(LinearSolver, SymbolicAnalysisIsReusedForNewValues) {
  SpMat a = grid_matrix(10, 0.1, 0.0);
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(100);
  for (const char* kind : available({"cholmod", "ldlt", "mumps", "umfpack"})) {
    auto solver = make_linear_solver(kind, true);
    solver->analyze(a);
    for (double scale : {1.0, 3.0, 0.5}) {  // same pattern, new values: refactorize only
      const SpMat scaled = scale * a;
      ASSERT_TRUE(solver->factorize(scaled));
      EXPECT_LT((scaled * solver->solve(b) - b).norm(), 1e-12 * b.norm()) << kind << " " << scale;
    }
  }
}

// MUMPS takes the entries of its analysed pattern in a fixed order; a matrix of the same size and count of
// entries whose triangle holds another count (two diagonal entries traded for an off-diagonal pair) is
// analysed anew instead of being read past that pattern's end.
TEST(LinearSolver, MumpsAnalysesAgainWhereTheTriangleDiffers) {
  if (!mumps_available()) GTEST_SKIP() << "built without MUMPS";
  const int n = 6;
  std::vector<Eigen::Triplet<double>> ta, tb;
  for (int i = 0; i < n; ++i) {
    ta.emplace_back(i, i, 4.0);
    if (i >= 2) tb.emplace_back(i, i, 4.0);
    if (i + 1 < n) {
      for (auto* t : {&ta, &tb}) {
        t->emplace_back(i, i + 1, 1.0);
        t->emplace_back(i + 1, i, 1.0);
      }
    }
  }
  tb.emplace_back(0, 5, 0.5);
  tb.emplace_back(5, 0, 0.5);
  SpMat a(n, n), b(n, n);
  a.setFromTriplets(ta.begin(), ta.end());
  b.setFromTriplets(tb.begin(), tb.end());
  ASSERT_EQ(a.nonZeros(), b.nonZeros());
  const Eigen::VectorXd rhs = Eigen::VectorXd::LinSpaced(n, 1.0, 2.0);
  auto solver = make_linear_solver("mumps", true);
  solver->analyze(a);
  ASSERT_TRUE(solver->factorize(a));
  ASSERT_TRUE(solver->factorize(b));
  EXPECT_LT((b * solver->solve(rhs) - rhs).norm(), 1e-12 * rhs.norm());
}

TEST(LinearSolver, SingularMatrixIsReportedNotSolved) {
  SpMat a = grid_matrix(4, 0.1, 0.0);
  a.coeffRef(5, 5) = 0.0;
  for (int k = 0; k < a.outerSize(); ++k)  // zero row and column 5 (kept in the pattern)
    for (SpMat::InnerIterator it(a, k); it; ++it)
      if (it.row() == 5 || it.col() == 5) it.valueRef() = 0.0;
  for (const char* kind : available({"cholmod", "ldlt", "mumps", "umfpack", "auto"})) {
    auto solver = make_linear_solver(kind, true);
    solver->analyze(a);
    EXPECT_FALSE(solver->factorize(a)) << kind;
    EXPECT_EQ(solver->negative_eigenvalues(), -1) << kind;
  }
  // The LUs name the library's reason.
  auto umfpack = make_linear_solver("umfpack", false);
  umfpack->analyze(a);
  EXPECT_FALSE(umfpack->factorize(a));
  EXPECT_EQ(umfpack->failure_detail(), "UMFPACK: singular matrix (a zero pivot)");
  if (mumps_available()) {
    auto lu = make_linear_solver("mumps-lu", false);
    lu->analyze(a);
    EXPECT_FALSE(lu->factorize(a));
    EXPECT_EQ(lu->failure_detail().rfind("MUMPS INFOG(1) = -10", 0), 0u) << lu->failure_detail();
  }
}

TEST(LinearSolver, BadKindsAreInputErrors) {
  EXPECT_THROW(make_linear_solver("cholmod", false), InputError);
  EXPECT_THROW(make_linear_solver("ldlt", false), InputError);
  EXPECT_THROW(make_linear_solver("mumps", false), InputError);
  LinearSolverSettings single;
  single.kind = "cholmod";
  single.precision = "single";
  EXPECT_THROW(make_linear_solver(single, true), InputError);  // single precision is MUMPS's
  EXPECT_THROW(make_linear_solver("pardiso", true), InputError);
}

// A links matrix: the grid matrix plus springs between the given unknowns (diagonally dominant: SPD).
SpMat with_links(const SpMat& a, const std::vector<std::pair<int, int>>& links) {
  SpMat b = a;
  for (const auto& [i, j] : links) {
    b.coeffRef(i, j) -= 0.5;
    b.coeffRef(j, i) -= 0.5;
    b.coeffRef(i, i) += 0.5;
    b.coeffRef(j, j) += 0.5;
  }
  b.makeCompressed();
  return b;
}

// 27-point stencil on an m^3 grid (SPD: diagonal 27, off-diagonals -1). Its AMD fill is high enough
// (nnz(L) / nnz(A) >= 5, flops / nnz(L) >= 500) that CHOLMOD's default also tries METIS, and METIS wins
// (at m = 24; m = 18 stays with AMD). Whether later analyses really skip AMD shows only in their time
// (bench_linear_solver), not here.
SpMat cube_matrix(int m) {
  std::vector<Eigen::Triplet<double>> t;
  auto id = [m](int i, int j, int k) { return (i * m + j) * m + k; };
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j)
      for (int k = 0; k < m; ++k)
        for (int di = -1; di <= 1; ++di)
          for (int dj = -1; dj <= 1; ++dj)
            for (int dk = -1; dk <= 1; ++dk) {
              const int a = i + di, b = j + dj, c = k + dk;
              if (a < 0 || b < 0 || c < 0 || a >= m || b >= m || c >= m) continue;
              t.emplace_back(id(i, j, k), id(a, b, c), di == 0 && dj == 0 && dk == 0 ? 27.0 : -1.0);
            }
  SpMat a(m * m * m, m * m * m);
  a.setFromTriplets(t.begin(), t.end());
  return a;
}

// The first analysis lets CHOLMOD choose the ordering; later ones (new patterns) run only the method that
// won: AMD for a small 2-D grid, METIS for a 3-D one. The solutions stay right for every pattern, for
// the symmetric kind and for the probing one.
TEST(LinearSolver, AutoKeepsTheOrderingMethodOfItsFirstAnalysis) {
  const int m = 30;
  const SpMat base = grid_matrix(m, 0.1, 0.0);
  std::vector<std::pair<int, int>> far;
  for (int k = 0; k < 60; ++k) far.emplace_back((k * 37) % (m * m), (k * 37 + 450) % (m * m));
  const SpMat linked = with_links(base, far);
  const SpMat cube = cube_matrix(24), cube_linked = with_links(cube, far);
  for (const bool promised : {true, false}) {
    for (const auto& [sequence, method] :
         {std::pair{std::vector<const SpMat*>{&base, &linked, &base}, "AMD"},
          std::pair{std::vector<const SpMat*>{&cube, &cube_linked}, "METIS"}}) {
      auto solver = make_linear_solver("auto", promised);
      int k = 0;
      for (const SpMat* a : sequence) {
        const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(a->rows(), -1.0, 2.0);
        solver->analyze(*a);
        ASSERT_TRUE(solver->factorize(*a));
        const Eigen::VectorXd x = solver->solve(b);
        EXPECT_LT((*a * x - b).norm() / b.norm(), 1e-12);
        EXPECT_EQ(solver->analysis_summary(), std::to_string(++k) + " with " + method)
            << (promised ? "symmetric" : "probing");
      }
    }
  }
}

}  // namespace
}  // namespace fibrane::solve
