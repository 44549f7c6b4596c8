// set_thread_count: the thread pools of OpenMP and of OpenBLAS follow it.
#include <gtest/gtest.h>
#include <omp.h>

#include "linalg/linear_solver.hpp"

namespace fibrane::solve {
namespace {

// set_thread_count bounds OpenMP and OpenBLAS (the project links OpenBLAS: scripts/install-deps).
TEST(Threads, SetThreadCountBoundsOpenMpAndOpenBlas) {
  const int before = omp_get_max_threads();
  ASSERT_NE(blas_thread_count(), -1) << "the BLAS is not OpenBLAS";
  for (const int n : {1, 2, 1}) {
    set_thread_count(n);
    EXPECT_EQ(omp_get_max_threads(), n);
    EXPECT_EQ(blas_thread_count(), n);
  }
  set_thread_count(0);  // no change
  EXPECT_EQ(omp_get_max_threads(), 1);
  set_thread_count(before);
}

}  // namespace
}  // namespace fibrane::solve
