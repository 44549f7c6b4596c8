// solve::Distribution's split of the reduced unknowns into contiguous ranges (exact integer checks).
#include <gtest/gtest.h>

#include "linalg/distribution.hpp"

namespace fibrane::solve {
namespace {

// A distribution that reports `size` processes (no communication: only the ranges are tested).
class Processes final : public Distribution {
 public:
  explicit Processes(int size) : size_(size) {}
  int size() const override { return size_; }

 private:
  int size_;
};

TEST(Distribution, SerialOwnsEverything) {
  const Distribution serial;
  EXPECT_EQ(serial.range_begin(0, 17), 0);
  EXPECT_EQ(serial.range_begin(1, 17), 17);
  for (int i = 0; i < 17; ++i) EXPECT_EQ(serial.owner(i, 17), 0);
}

// Ranges cover 0..n without gaps, differ in length by at most one (the longer ones first, as PETSc's
// PETSC_DECIDE split), and owner() names the range that holds each unknown.
TEST(Distribution, RangesPartitionTheUnknownsAndOwnerAgrees) {
  for (int p_count : {1, 2, 3, 4, 7}) {
    const Processes d(p_count);
    for (int n : {0, 1, 2, 5, 6, 7, 100, 101}) {
      EXPECT_EQ(d.range_begin(0, n), 0);
      EXPECT_EQ(d.range_begin(p_count, n), n);
      for (int p = 0; p < p_count; ++p) {
        const int length = d.range_begin(p + 1, n) - d.range_begin(p, n);
        EXPECT_EQ(length, n / p_count + (p < n % p_count ? 1 : 0)) << p << " of " << p_count << ", n = " << n;
        for (int i = d.range_begin(p, n); i < d.range_begin(p + 1, n); ++i) EXPECT_EQ(d.owner(i, n), p);
      }
    }
  }
}

}  // namespace
}  // namespace fibrane::solve
