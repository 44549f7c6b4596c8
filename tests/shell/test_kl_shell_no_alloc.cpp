// The point kernel runs once per quadrature point in a parallel loop, so it must not touch the heap.
// This file interposes glibc's malloc for the whole test executable (forwarding to __libc_malloc) and
// counts calls while a kernel call is in flight. Eigen and operator new both end in malloc.
#include <gtest/gtest.h>

#include <atomic>
#include <cstddef>

#include "shell/bezier_patch.hpp"
#include "shell/material.hpp"

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

#ifdef FIBRANE_COUNT_MALLOC
// Counts the heap allocations of one kernel call with residual and tangent for `section`.
int allocations_of_one_point(const ShellSection& section) {
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
  EXPECT_GT(allocations.load(), 0);
  allocations = 0;
  counting = true;
  add_shell_point(section, R, X, x, 0.5, &energy, &r, &k);
  counting = false;
  EXPECT_GT(energy, 0.0);
  probe.setZero();
  return allocations.load();
}
#endif

TEST(ShellKernel, DoesNotAllocate) {
#ifndef FIBRANE_COUNT_MALLOC
  GTEST_SKIP() << "malloc interposition needs glibc and no AddressSanitizer";
#else
  const ShellSection svk = ShellSection::svk(1000.0, 0.3, 0.1);
  EXPECT_EQ(allocations_of_one_point(svk), 0);
  const ShellSection neo_hookean{0.1, std::make_shared<const NeoHookeanMaterial>(1000.0, 0.3, 4)};
  EXPECT_EQ(allocations_of_one_point(neo_hookean), 0);
  const ShellSection incompressible{0.1, std::make_shared<const IncompressibleNeoHookeanMaterial>(300.0, 4)};
  EXPECT_EQ(allocations_of_one_point(incompressible), 0);
#endif
}

}  // namespace
}  // namespace fibrane::shell
