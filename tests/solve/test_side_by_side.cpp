// side_by_side (the split Cholesky's domains and fronts on threads) and the bits of its results: a body
// keeps one BLAS thread to its end unless it is asked to share, and a split factorisation and its solves
// give the same bits every time.
#include <gtest/gtest.h>
#include <omp.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <utility>
#include <vector>

#include "grid_matrix.hpp"
#include "linalg/cholmod_split.hpp"
#include "linalg/direct_solvers.hpp"
#include "linalg/linear_solver.hpp"
#include "linalg/side_by_side.hpp"

namespace fibrane::solve {
namespace {

// The BLAS threads each of two bodies sees at its end, the second body reading its count only once the
// first has ended: 50 ms after that without sharing; with sharing, as soon as the count has been raised
// (or after 5 s, when the test fails).
std::pair<int, int> blas_threads_at_the_end(bool share) {
  std::vector<int> seen(2, 0);
  std::atomic<bool> first_ended{false};
  side_by_side({0, 1}, 2, [&](int k) {
    if (k == 0) {
      seen[0] = blas_thread_count();
      first_ended = true;
      return true;
    }
    while (!first_ended) std::this_thread::yield();
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(share ? 5 : 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    while (share && blas_thread_count() == 1 && std::chrono::steady_clock::now() < until)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    seen[1] = blas_thread_count();
    return true;
  }, share);
  return {seen[0], seen[1]};
}

TEST(SideBySide, ABodyKeepsOneBlasThreadUnlessItShares) {
  const int before = omp_get_max_threads();
  set_thread_count(2);
  ASSERT_EQ(blas_thread_count(), 2) << "the BLAS is not OpenBLAS";
  EXPECT_EQ(blas_threads_at_the_end(false), std::make_pair(1, 1));
  EXPECT_EQ(blas_threads_at_the_end(true), std::make_pair(1, 2));  // the last body got the idle core
  EXPECT_EQ(blas_thread_count(), 2);                               // and the count is restored after
  set_thread_count(before);
}

// The split factorisation and its solves repeated on 4 threads (4 domains below 3 fronts, two of one
// height): the same bits each time. The matrix is a 3-D grid Laplacian, so that the domains' last
// supernodes and the fronts are dense blocks large enough for OpenBLAS to thread; its results then depend
// on its thread count (a front of 700 + 500 rows factorised on 1 and on 2 BLAS threads differs by 2e-13),
// which a body given the idle cores of finished ones would change at a moment set by timing.
TEST(SideBySide, ASplitFactorisationAndSolveAreTheSameBitsEveryTime) {
  const int before = omp_get_max_threads();
  set_thread_count(4);
  const Eigen::SparseMatrix<double> a = grid_matrix_3d(22, 3.0, 7);
  const Eigen::VectorXd rhs = Eigen::VectorXd::LinSpaced(a.rows(), -1.0, 2.0);
  auto solver = make_cholmod_split_llt({.memory_limit_megabytes = kAvailableMemory, .min_unknowns = 1000,
                                        .max_separator = 5000});
  solver->analyze(a);
  ASSERT_EQ(cholmod_split_domains(*solver), 4);
  ASSERT_TRUE(solver->factorize(a));
  const Eigen::VectorXd first = solver->solve(rhs);
  for (int round = 0; round < 20; ++round) {
    if (round % 5 == 4) {
      ASSERT_TRUE(solver->factorize(a));
    }
    EXPECT_EQ((solver->solve(rhs) - first).cwiseAbs().maxCoeff(), 0.0) << "round " << round;
  }
  set_thread_count(before);
}

}  // namespace
}  // namespace fibrane::solve
