// Refinement of a knot vector in one pass (insert_knots, used by refine()) against the reference, Boehm's
// insertion of one knot at a time (insert_knot): on random rational curves and surfaces of degrees 1 to 4
// the control points agree to 1e-13 relative (the largest coordinate or weight) and the geometry at random
// parameters to 1e-13.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <random>
#include <vector>

#include "spline/curve.hpp"
#include "spline/refinement.hpp"
#include "spline/surface.hpp"
#include "test_helpers.hpp"

namespace fibrane::spline {
namespace {

constexpr double kRelative = 1e-13;

// An open knot vector of `degree` on [a, b] with random interior knots, some repeated (up to the degree).
KnotVector random_knots(std::mt19937& rng, int degree, double a, double b) {
  std::uniform_real_distribution<double> inside(a, b);
  std::uniform_int_distribution<int> count(1, 5), times(1, degree);
  std::vector<double> interior;
  const int n = count(rng);
  for (int i = 0; i < n; ++i) {
    const double u = inside(rng);
    interior.insert(interior.end(), static_cast<std::size_t>(times(rng)), u);
  }
  std::sort(interior.begin(), interior.end());
  std::vector<double> knots(static_cast<std::size_t>(degree) + 1, a);
  knots.insert(knots.end(), interior.begin(), interior.end());
  knots.insert(knots.end(), static_cast<std::size_t>(degree) + 1, b);
  return KnotVector(degree, std::move(knots));
}

// Insertions (value, times) that keep every multiplicity within the degree: new random values and some of
// the existing interior knots raised.
std::vector<std::pair<double, int>> random_insertions(std::mt19937& rng, const KnotVector& kv) {
  std::uniform_real_distribution<double> inside(kv.front(), kv.back());
  std::uniform_int_distribution<int> times(1, kv.degree());
  std::vector<std::pair<double, int>> insertions;
  for (int i = 0; i < 12; ++i) insertions.emplace_back(inside(rng), times(rng));
  for (double u : kv.unique_knots())
    if (u > kv.front() && u < kv.back() && kv.multiplicity(u) < kv.degree())
      insertions.emplace_back(u, kv.degree() - kv.multiplicity(u));
  std::sort(insertions.begin(), insertions.end());
  return insertions;
}

// |a - b| over all control points and weights, relative to the largest of them.
double relative_difference(const std::vector<Eigen::Vector3d>& pa, const std::vector<double>& wa,
                           const std::vector<Eigen::Vector3d>& pb, const std::vector<double>& wb) {
  double largest = 0, difference = 0;
  for (std::size_t i = 0; i < pa.size(); ++i) {
    largest = std::max({largest, pa[i].cwiseAbs().maxCoeff(), std::abs(wa[i])});
    difference = std::max({difference, (pa[i] - pb[i]).cwiseAbs().maxCoeff(), std::abs(wa[i] - wb[i])});
  }
  return difference / largest;
}

class OnePassRefinement : public ::testing::TestWithParam<int> {};  // parameter: the degree

TEST_P(OnePassRefinement, CurveEqualsOneKnotAtATime) {
  const int degree = GetParam();
  std::mt19937 rng(100 + degree);
  for (int trial = 0; trial < 20; ++trial) {
    const KnotVector kv = random_knots(rng, degree, -1.0, 2.0);
    const NurbsCurve original(kv, testing::random_points(rng, kv.num_basis()),
                              testing::random_weights(rng, kv.num_basis()));
    const auto insertions = random_insertions(rng, kv);
    NurbsCurve reference = original, one_pass = original;
    for (const auto& [u, times] : insertions) reference.insert_knot(u, times);
    one_pass.insert_knots(expand_insertions(insertions));
    ASSERT_EQ(one_pass.knots().knots(), reference.knots().knots());
    EXPECT_LE(relative_difference(one_pass.control_points(), one_pass.weights(), reference.control_points(),
                                  reference.weights()),
              kRelative);
    std::uniform_real_distribution<double> param(kv.front(), kv.back());
    for (int s = 0; s < 50; ++s) {
      const double u = param(rng);
      EXPECT_LE((one_pass.point(u) - original.point(u)).norm(), kRelative * 10) << "u = " << u;
      EXPECT_LE((one_pass.point(u) - reference.point(u)).norm(), kRelative * 10) << "u = " << u;
    }
  }
}

TEST_P(OnePassRefinement, SurfaceEqualsOneKnotAtATimeInEachDirection) {
  const int degree = GetParam();
  std::mt19937 rng(200 + degree);
  for (int trial = 0; trial < 10; ++trial) {
    const KnotVector ku = random_knots(rng, degree, 0.0, 1.0);
    const KnotVector kv = random_knots(rng, std::max(1, 5 - degree), -2.0, 3.0);
    const int n = ku.num_basis() * kv.num_basis();
    const NurbsSurface original(ku, kv, testing::random_points(rng, n), testing::random_weights(rng, n));
    NurbsSurface reference = original, one_pass = original;
    for (int dir : {0, 1}) {
      const auto insertions = random_insertions(rng, reference.knots(dir));
      for (const auto& [u, times] : insertions) reference.insert_knot(dir, u, times);
      one_pass.insert_knots(dir, expand_insertions(insertions));
    }
    ASSERT_EQ(one_pass.knots(0).knots(), reference.knots(0).knots());
    ASSERT_EQ(one_pass.knots(1).knots(), reference.knots(1).knots());
    EXPECT_LE(relative_difference(one_pass.control_points(), one_pass.weights(), reference.control_points(),
                                  reference.weights()),
              kRelative);
    std::uniform_real_distribution<double> pu(0.0, 1.0), pv(-2.0, 3.0);
    for (int s = 0; s < 50; ++s) {
      const double u = pu(rng), v = pv(rng);
      EXPECT_LE((one_pass.point(u, v) - original.point(u, v)).norm(), kRelative * 10);
      EXPECT_LE((one_pass.point(u, v) - reference.point(u, v)).norm(), kRelative * 10);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Degrees, OnePassRefinement, ::testing::Values(1, 2, 3, 4),
                         [](const auto& info) { return "degree" + std::to_string(info.param); });

TEST(OnePassRefinement, RefusesWhatOneAtATimeRefuses) {
  std::mt19937 rng(7);
  const HomogeneousCurve curve{testing::sample_knots_cubic(),
                               to_homogeneous(testing::random_points(rng, 8), testing::random_weights(rng, 8))};
  EXPECT_THROW(insert_knots(curve, {0.5, 0.5}), std::invalid_argument);  // 0.5 is double: would be 4 > 3
  EXPECT_THROW(insert_knots(curve, {0.1, 2.0}), std::invalid_argument);  // 2 is the domain's end
  EXPECT_THROW(insert_knots(curve, {0.1, 0.1, 0.1, 0.1}), std::invalid_argument);
  // A value within the knot tolerance of an existing knot is snapped onto it, as insert_knot does.
  const HomogeneousCurve snapped = insert_knots(curve, {0.5 + 1e-14});
  EXPECT_EQ(snapped.knots.multiplicity(0.5), 3);
  EXPECT_EQ(std::count(snapped.knots.knots().begin(), snapped.knots.knots().end(), 0.5), 3);
}

// The one-pass refinement is linear in the number of knots: 2^17 elements of a cubic curve (the documented
// maximum is 65536 per direction) refine in milliseconds (bound: 5 s on a loaded machine); one knot at a time
// takes minutes.
TEST(OnePassRefinement, LargeRefinementIsFast) {
  std::mt19937 rng(3);
  NurbsCurve curve(testing::sample_knots_cubic(), testing::random_points(rng, 8), testing::random_weights(rng, 8));
  const NurbsCurve original = curve;
  const auto start = std::chrono::steady_clock::now();
  curve.refine(3, 2, 1 << 17);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0);
  EXPECT_GE(curve.knots().num_elements(), 1 << 17);
  std::uniform_real_distribution<double> param(-1.0, 2.0);
  for (int s = 0; s < 20; ++s) {
    const double u = param(rng);
    EXPECT_LE((curve.point(u) - original.point(u)).norm(), 1e-11);
  }
}

}  // namespace
}  // namespace fibrane::spline
