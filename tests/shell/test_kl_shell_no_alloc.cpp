// The point kernel runs once per quadrature point in a parallel loop, so it must not touch the heap.
// This file interposes glibc's malloc for the whole test executable (forwarding to __libc_malloc) and
// counts calls while a kernel call is in flight. Eigen and operator new both end in malloc.
#include <gtest/gtest.h>

#include <atomic>
#include <cstddef>

#include "shell/bezier_patch.hpp"

#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__)
#define FIBRANE_COUNT_MALLOC 1
namespace {
std::atomic<bool> counting{false};
std::atomic<int> allocations{0};
}  // namespace
extern "C" void* __libc_malloc(std::size_t);
extern "C" void* malloc(std::size_t size) {
  if (counting.load(std::memory_order_relaxed)) allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(size);
}
#endif

namespace fibrane::shell {
namespace {

TEST(ShellKernel, DoesNotAllocate) {
#ifndef FIBRANE_COUNT_MALLOC
  GTEST_SKIP() << "malloc interposition needs glibc and no AddressSanitizer";
#else
  std::mt19937 rng(5);
  const BasisDerivs R = testing::bezier_basis(4, 4, 0.3, 0.6, testing::random_weights(25, rng));
  const Eigen::Matrix3Xd X = testing::random_curved_patch(4, 4, rng);
  const Eigen::Matrix3Xd x = testing::random_deformation(X, 0.05, rng);
  Eigen::VectorXd r = Eigen::VectorXd::Zero(75);
  ElementTangent k;
  k.reset(25);  // once per element, outside the quadrature loop
  double energy = 0.0;
  // Sanity check that the counter sees Eigen's allocations at all (else the test could not fail).
  counting = true;
  Eigen::VectorXd probe(1000);
  counting = false;
  ASSERT_GT(allocations.load(), 0);
  allocations = 0;
  counting = true;
  add_shell_point({1000.0, 0.3, 0.1}, R, X, x, 0.5, &energy, &r, &k);
  counting = false;
  EXPECT_EQ(allocations.load(), 0);
  EXPECT_GT(energy, 0.0);
  probe.setZero();
#endif
}

}  // namespace
}  // namespace fibrane::shell
