// CHOLMOD's supernodal LL^T from the kept permuted lower triangle (CholmodPermutedLower) against
// cholmod_factorize's own path (Eigen's CholmodSupernodalLLT): the same factor, so the same solution to the
// last bit, for a first factorisation, for new values of the pattern, and after the factor was released.
#include <gtest/gtest.h>

#include <Eigen/CholmodSupport>

#include "grid_matrix.hpp"
#include "linalg/direct_solvers.hpp"
#include "linalg/linear_solver.hpp"

namespace fibrane::solve {
namespace {

using SpMat = Eigen::SparseMatrix<double>;

// The solution through cholmod_factorize (two permuted transposes of the lower triangle per factorisation),
// with the BLAS threads that fibrane's solver takes for a factor of this size (one), as the threads split the
// BLAS calls' sums differently.
Eigen::VectorXd reference_solve(const SpMat& a, const Eigen::VectorXd& b) {
  const BlasThreadsForFactor threads(0);
  Eigen::CholmodSupernodalLLT<SpMat, Eigen::Lower> llt;
  llt.compute(a);
  EXPECT_EQ(llt.info(), Eigen::Success);
  return llt.solve(b);
}

// Largest entry of |x - y|: 0 where the two factors are the same.
double difference(const Eigen::VectorXd& x, const Eigen::VectorXd& y) { return (x - y).cwiseAbs().maxCoeff(); }

// A shifted grid Laplacian with random diagonal scaling, 2 500 unknowns: supernodes of several columns, so
// the supernodal path (not the simplicial one) factorises it.
SpMat spd(unsigned seed, bool lower_only) {
  SpMat a = grid_matrix(50, 2.0, 0.0, 0.3, seed);  // diagonal >= 6 x 0.7 > 4: SPD by Gershgorin
  if (lower_only) a = SpMat(a.triangularView<Eigen::Lower>());
  return a;
}

TEST(CholmodPermutedLower, GivesCholmodFactorizesFactorToTheLastBit) {
  for (const bool lower_only : {false, true}) {
    SCOPED_TRACE(lower_only ? "lower triangle stored" : "both triangles stored");
    const SpMat a = spd(1, lower_only), a2 = spd(2, lower_only);
    const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(a.rows(), -1.0, 2.0);
    auto solver = make_cholmod_llt();
    solver->analyze(a);
    ASSERT_TRUE(solver->factorize(a));
    const Eigen::VectorXd x = solver->solve(b);
    EXPECT_EQ(difference(x, reference_solve(a, b)), 0.0);
    EXPECT_LT((a.selfadjointView<Eigen::Lower>() * x - b).norm(), 1e-12 * b.norm());

    // New values on the same pattern: the kept pattern and map, refilled.
    ASSERT_TRUE(solver->factorize(a2));
    const Eigen::VectorXd ref2 = reference_solve(a2, b);
    EXPECT_EQ(difference(solver->solve(b), ref2), 0.0);
    EXPECT_GT(difference(ref2, x), 1e-6);  // the values did change the solution

    // After the factor's values were handed back (one factor at a time).
    solver->release_factor();
    ASSERT_TRUE(solver->factorize(a2));
    EXPECT_EQ(difference(solver->solve(b), ref2), 0.0);
  }
}

TEST(CholmodPermutedLower, ANewPatternIsMappedAfresh) {
  auto solver = make_cholmod_llt();
  const SpMat a = spd(1, true);
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(a.rows());
  solver->analyze(a);
  ASSERT_TRUE(solver->factorize(a));
  // Another pattern: the grid's long-range couplings within a row of 50 grid points, at distance 2.
  SpMat wider = a;
  for (int i = 0; i + 2 < wider.rows(); i += 3) wider.coeffRef(i + 2, i) = -0.05;
  wider.makeCompressed();
  solver->analyze(wider);
  ASSERT_TRUE(solver->factorize(wider));
  EXPECT_EQ(difference(solver->solve(b), reference_solve(wider, b)), 0.0);
}

TEST(CholmodPermutedLower, AnIndefiniteMatrixIsRejected) {
  // A shift of -1.3 makes the Laplacian indefinite: the LL^T stops at a non-positive pivot.
  const SpMat a = grid_matrix(50, -1.3, 0.0);
  auto solver = make_cholmod_llt();
  solver->analyze(a);
  EXPECT_FALSE(solver->factorize(a));
  // and a positive definite matrix of the same pattern factorises afterwards
  ASSERT_TRUE(solver->factorize(grid_matrix(50, 0.1, 0.0)));
}

}  // namespace
}  // namespace fibrane::solve
