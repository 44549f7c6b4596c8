// Preconditioned CG and GMRES, and KrylovReuseSolver: factorisations reused as preconditioners across
// changed matrices, refined single-precision and low-rank factorisations, the staleness rule.
#include <gtest/gtest.h>


#include "grid_matrix.hpp"
#include "linalg/direct_solvers.hpp"
#include "linalg/krylov.hpp"
#include "linalg/krylov_reuse.hpp"
#include "linalg/linear_solver.hpp"

namespace fibrane::solve {
namespace {

using SpMat = Eigen::SparseMatrix<double>;

double relative_residual(const SpMat& a, const Eigen::VectorXd& x, const Eigen::VectorXd& b) {
  return (b - a * x).norm() / b.norm();
}

VectorOperator multiply(const SpMat& a) {
  return [&a](const Eigen::VectorXd& x, Eigen::VectorXd& y) { y = a * x; };
}

// Jacobi preconditioning of a Laplacian: CG and GMRES must reach 1e-10 within the iterations the
// condition number allows (kappa ~ 4 m^2 / pi^2 ~ 160 at m = 20: CG needs ~ sqrt(kappa) ln(2/tol) ~ 300 at
// worst, well under 400); GMRES on the unsymmetric one likewise with restarts.
TEST(Krylov, CgAndGmresSolveLaplacians) {
  const SpMat spd = grid_matrix(20, 0.0, 0.0), unsym = grid_matrix(20, 0.0, 0.8);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(400, -1, 3);
  const Eigen::VectorXd d = spd.diagonal();
  const VectorOperator jacobi = [&d](const Eigen::VectorXd& x, Eigen::VectorXd& y) { y = x.cwiseQuotient(d); };
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(400);
  const KrylovResult cg = preconditioned_cg(multiply(spd), jacobi, b, zero, 1e-10, 400);
  EXPECT_TRUE(cg.converged);
  EXPECT_LT(relative_residual(spd, cg.x, b), 1e-10);
  EXPECT_GT(cg.iterations, 10);  // a real iteration, not a lucky start
  const KrylovResult gm = preconditioned_gmres(multiply(unsym), jacobi, b, zero, 1e-10, 800, 30);
  EXPECT_TRUE(gm.converged);
  EXPECT_LT(relative_residual(unsym, gm.x, b), 1e-10);
  EXPECT_NEAR(gm.relative_residual, relative_residual(unsym, gm.x, b), 1e-14);
}

// CG reports an indefinite operator instead of returning garbage.
TEST(Krylov, CgDetectsIndefiniteOperators) {
  const SpMat a = grid_matrix(10, -3.0, 0.0);  // strongly indefinite
  const VectorOperator identity = [](const Eigen::VectorXd& x, Eigen::VectorXd& y) { y = x; };
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(100, -1, 3);
  const KrylovResult r = preconditioned_cg(multiply(a), identity, b, Eigen::VectorXd::Zero(100), 1e-10, 200);
  EXPECT_FALSE(r.converged);
  EXPECT_TRUE(r.breakdown);
}

TEST(Krylov, ParallelMultiplyEqualsEigensProduct) {
  const SpMat a = grid_matrix(400, 0.3, 0.7);  // 160 000 rows, 800 k entries: above the threading threshold
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(a.cols(), -2, 5);
  Eigen::VectorXd y;
  parallel_multiply(a, x, y);
  EXPECT_LT((y - a * x).norm(), 1e-13 * (a * x).norm());
}

// A factorisation of one matrix preconditions GMRES on others of the same pattern (a Newton sequence):
// every solve meets the tolerance, and a single factorisation serves them all while the changes are small.
TEST(KrylovReuse, OneFactorisationServesNearbyMatrices) {
  for (const bool symmetric : {true, false}) {
    KrylovReuseOptions o;
    o.tolerance = 1e-10;
    KrylovReuseSolver solver(make_linear_solver("auto", symmetric), o, symmetric);
    std::vector<SpMat> sequence;
    for (unsigned k = 0; k < 5; ++k) sequence.push_back(grid_matrix(30, 0.2, symmetric ? 0.0 : 0.5, 0.02 * k, k + 1));
    const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(900, -1, 3);
    solver.analyze(sequence[0]);
    for (const SpMat& a : sequence) {
      ASSERT_TRUE(solver.factorize(a));
      const Eigen::VectorXd x = solver.solve(b);
      EXPECT_LT(relative_residual(a, x, b), 1e-10) << symmetric;
    }
    EXPECT_EQ(solver.statistics().factorizations, 1) << symmetric;
    EXPECT_EQ(solver.factorizations(), 1) << symmetric;  // those made, not the five factorize() answered
    EXPECT_EQ(solver.statistics().krylov_solves, 4) << symmetric;  // the first solve was direct
    EXPECT_EQ(solver.negative_eigenvalues(), -1);  // the factorisation is another matrix's
    // factorize_exactly() factorises this matrix, and its inertia is known again.
    ASSERT_TRUE(solver.factorize_exactly(sequence.back()));
    EXPECT_EQ(solver.statistics().factorizations, 2);
    if (symmetric) {
      EXPECT_EQ(solver.negative_eigenvalues(), 0);
    }
  }
}

// A matrix far from the factorised one needs more than max_iterations: the solve still meets the
// tolerance (refactorising within the solve if needed), and the next factorize() renews the factorisation.
TEST(KrylovReuse, StaleFactorisationIsRenewed) {
  KrylovReuseOptions o;
  o.tolerance = 1e-10;
  o.max_iterations = 3;
  KrylovReuseSolver solver(make_linear_solver("auto", false), o, false);
  const SpMat first = grid_matrix(30, 0.2, 0.5), far = grid_matrix(30, 2.0, 0.1, 0.5, 7);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(900, -1, 3);
  solver.analyze(first);
  ASSERT_TRUE(solver.factorize(first));
  ASSERT_TRUE(solver.factorize(far));
  EXPECT_LT(relative_residual(far, solver.solve(b), b), 1e-10);
  const long after_far = solver.statistics().factorizations;
  ASSERT_TRUE(solver.factorize(far));  // marked stale (or already renewed inside the solve)
  EXPECT_LT(relative_residual(far, solver.solve(b), b), 1e-10);
  EXPECT_GE(solver.statistics().factorizations, 2);
  EXPECT_LE(solver.statistics().factorizations, after_far + 1);
}

// An inexact factorisation (here an exact one whose solutions are scaled by 0.999) of a matrix far from
// the current one: GMRES fails with it, the current matrix is factorised inside the solve and GMRES runs
// again. That is one solve, and the statistics count one Krylov solve for it.
class Scaled final : public LinearSolver {
 public:
  void analyze(const SpMat& a) override { inner_->analyze(a); }
  bool factorize_numeric(const SpMat& a) override { return inner_->factorize(a); }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const override { return 0.999 * inner_->solve(b); }
  std::string name() const override { return "scaled"; }
  long factor_nonzeros() const override { return inner_->factor_nonzeros(); }
  bool exact() const override { return false; }

 private:
  std::unique_ptr<LinearSolver> inner_ = make_linear_solver("auto", false);
};

TEST(KrylovReuse, ASolveThatRefactorisesCountsOnce) {
  KrylovReuseOptions o;
  o.tolerance = 1e-10;
  o.max_iterations = 3;
  KrylovReuseSolver solver(std::make_unique<Scaled>(), o, false);
  const SpMat first = grid_matrix(30, 0.2, 0.5), far = grid_matrix(30, 2.0, 0.1, 0.5, 7);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(900, -1, 3);
  solver.analyze(first);
  ASSERT_TRUE(solver.factorize(first));
  EXPECT_LT(relative_residual(first, solver.solve(b), b), 1e-10);
  ASSERT_TRUE(solver.factorize(far));
  EXPECT_LT(relative_residual(far, solver.solve(b), b), 1e-10);
  EXPECT_EQ(solver.statistics().factorizations, 2);  // the second inside the solve: the scaled preconditioner of
                                                     // `first` needs more than 3 x 3 iterations on `far`
  EXPECT_EQ(solver.statistics().solves, 2);
  EXPECT_EQ(solver.statistics().krylov_solves, 2);
  EXPECT_NE(solver.analysis_summary().find("in 2 of 2 solves"), std::string::npos) << solver.analysis_summary();
}

// A new sparsity pattern of the same size keeps the old factorisation as preconditioner until it goes
// stale: no analysis happens for it.
TEST(KrylovReuse, NewPatternOfTheSameSizeKeepsThePreconditioner) {
  KrylovReuseSolver solver(make_linear_solver("auto", true), {}, true);
  const SpMat a = grid_matrix(30, 0.2, 0.0);
  SpMat linked = a;
  linked.coeffRef(0, 450) = -0.1;
  linked.coeffRef(450, 0) = -0.1;
  linked.makeCompressed();
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(900, -1, 3);
  solver.analyze(a);
  ASSERT_TRUE(solver.factorize(a));
  solver.solve(b);
  solver.analyze(linked);
  ASSERT_TRUE(solver.factorize(linked));
  EXPECT_LT(relative_residual(linked, solver.solve(b), b), 1e-8);
  EXPECT_EQ(solver.statistics().analyses, 1);
  EXPECT_EQ(solver.statistics().factorizations, 1);
}

// Single-precision and block low-rank MUMPS factorisations are refined to double precision: relative
// residual 1e-12, far below what the single-precision factor alone gives (~1e-7 times the condition).
TEST(KrylovReuse, RefinesApproximateFactorisations) {
  if (!mumps_available()) GTEST_SKIP() << "built without MUMPS";
  const SpMat spd = grid_matrix(60, 0.05, 0.0), unsym = grid_matrix(60, 0.05, 0.6);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(3600, -1, 3);
  for (const auto& [kind, precision, low_rank, symmetric] :
       {std::tuple{"auto", "single", 0.0, true}, std::tuple{"auto", "single", 0.0, false},
        std::tuple{"mumps-lu", "double", 1e-3, false}, std::tuple{"mumps", "single", 1e-3, true}}) {
    LinearSolverSettings s;
    s.kind = kind;
    s.precision = precision;
    s.low_rank = low_rank;
    s.krylov_tolerance = 1e-12;
    const SpMat& a = symmetric ? spd : unsym;
    auto solver = make_linear_solver(s, symmetric);
    solver->analyze(a);
    ASSERT_TRUE(solver->factorize(a)) << kind << " " << precision;
    EXPECT_LT(relative_residual(a, solver->solve(b), b), 1e-12) << kind << " " << precision << " " << low_rank;
    EXPECT_EQ(solver->name().rfind("krylov(", 0), 0u) << solver->name();
  }
  // The single-precision factorisation alone is visibly inexact: the refinement above does real work.
  MumpsOptions single;
  single.single_precision = true;
  auto raw = make_mumps(single);
  raw->analyze(spd);
  ASSERT_TRUE(raw->factorize(spd));
  EXPECT_FALSE(raw->exact());
  EXPECT_GT(relative_residual(spd, raw->solve(b), b), 1e-9);
}

// An approximate factorisation that no Krylov method can refine within its iterations (its "solve" is a
// scaled identity: GMRES on the 900-unknown grid needs far more than 3 x 5 iterations) is replaced for good
// by the exact solver of the same path; the solve still meets the tolerance.
class Useless final : public LinearSolver {
 public:
  void analyze(const SpMat& a) override { inner_->analyze(a); }
  bool factorize_numeric(const SpMat& a) override { return inner_->factorize(a); }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const override { return 0.25 * b; }
  std::string name() const override { return "useless"; }
  long factor_nonzeros() const override { return inner_->factor_nonzeros(); }
  bool exact() const override { return false; }

 private:
  std::unique_ptr<LinearSolver> inner_ = make_linear_solver("auto", false);
};

TEST(KrylovReuse, UnrefinableApproximateFactorisationFallsBackToTheExactSolver) {
  KrylovReuseOptions o;
  o.tolerance = 1e-10;
  o.max_iterations = 5;
  KrylovReuseSolver solver(std::make_unique<Useless>(), o, false, [] { return make_linear_solver("auto", false); });
  const SpMat a = grid_matrix(30, 0.2, 0.5);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(900, -1, 3);
  solver.analyze(a);
  ASSERT_TRUE(solver.factorize(a));
  EXPECT_EQ(solver.name(), "krylov(useless)");
  EXPECT_LT(relative_residual(a, solver.solve(b), b), 1e-10);
  EXPECT_EQ(solver.statistics().exact_fallbacks, 1);
  EXPECT_NE(solver.name(), "krylov(useless)");
  // Without a fallback the solve fails visibly (NaN), never returning the unrefined solution.
  KrylovReuseSolver alone(std::make_unique<Useless>(), o, false);
  alone.analyze(a);
  ASSERT_TRUE(alone.factorize(a));
  EXPECT_FALSE(alone.solve(b).allFinite());
}

}  // namespace
}  // namespace fibrane::solve
