// Knot insertion, degree elevation and refine(): the geometry must not change. Tolerance 1e-12: the
// control points are O(1), refinement is a short chain of convex combinations (insertion) or a small
// well-conditioned solve (elevation), so differences stay within ~100 ulps of O(1) coordinates.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "spline/curve.hpp"
#include "spline/refinement.hpp"
#include "spline/shapes.hpp"
#include "spline/surface.hpp"
#include "test_helpers.hpp"

namespace fibrane::spline {
namespace {

constexpr double kTol = 1e-12;
constexpr int kSamples = 301;

double max_curve_distance(const NurbsCurve& a, const NurbsCurve& b) {
  double worst = 0.0;
  const double lo = a.knots().front(), hi = a.knots().back();
  for (int s = 0; s < kSamples; ++s) {
    const double u = lo + (hi - lo) * s / (kSamples - 1);
    worst = std::max(worst, (a.point(u) - b.point(u)).norm());
  }
  return worst;
}

double max_surface_distance(const NurbsSurface& a, const NurbsSurface& b) {
  double worst = 0.0;
  const int n = 41;
  for (int s = 0; s < n; ++s)
    for (int t = 0; t < n; ++t) {
      const double u = a.knots(0).front() + (a.knots(0).back() - a.knots(0).front()) * s / (n - 1);
      const double v = a.knots(1).front() + (a.knots(1).back() - a.knots(1).front()) * t / (n - 1);
      worst = std::max(worst, (a.point(u, v) - b.point(u, v)).norm());
    }
  return worst;
}

class CurveRefinement : public ::testing::TestWithParam<bool> {};  // parameter: rational

TEST_P(CurveRefinement, KnotInsertionKeepsGeometry) {
  std::mt19937 rng(10);
  const NurbsCurve original = testing::random_curve(rng, GetParam());
  NurbsCurve refined = original;
  refined.insert_knot(0.25);
  refined.insert_knot(0.5);      // existing double knot -> triple (C0)
  refined.insert_knot(1.7, 3);   // new knot to full multiplicity
  EXPECT_EQ(refined.num_control_points(), original.num_control_points() + 5);
  EXPECT_EQ(refined.knots().multiplicity(0.5), 3);
  EXPECT_EQ(refined.knots().multiplicity(1.7), 3);
  EXPECT_LE(max_curve_distance(original, refined), kTol);
  EXPECT_THROW(refined.insert_knot(0.5), std::invalid_argument);  // would exceed the degree
  EXPECT_THROW(refined.insert_knot(2.0), std::invalid_argument);  // not interior
}

TEST_P(CurveRefinement, DegreeElevationKeepsGeometryAndContinuity) {
  std::mt19937 rng(11);
  const NurbsCurve original = testing::random_curve(rng, GetParam());
  NurbsCurve elevated = original;
  elevated.elevate_degree(2);
  EXPECT_EQ(elevated.degree(), 5);
  for (double t : original.knots().unique_knots())
    EXPECT_EQ(elevated.knots().multiplicity(t), original.knots().multiplicity(t) + 2) << t;
  EXPECT_LE(max_curve_distance(original, elevated), kTol);
  EXPECT_EQ(elevated.is_rational(), original.is_rational());
}

TEST_P(CurveRefinement, RefineGivesDegreeContinuityAndElements) {
  std::mt19937 rng(12);
  const KnotVector single(2, {0, 0, 0, 1, 1, 1});
  const NurbsCurve original(single, testing::random_points(rng, 3),
                            GetParam() ? testing::random_weights(rng, 3) : std::vector<double>{});
  NurbsCurve refined = original;
  refined.refine(4, 2, 6);
  EXPECT_EQ(refined.degree(), 4);
  EXPECT_EQ(refined.knots().num_elements(), 6);
  for (int k = 1; k < 6; ++k) EXPECT_EQ(refined.knots().multiplicity(k / 6.0), 2) << k;  // p - C = 2
  EXPECT_EQ(refined.num_control_points(), 4 + 1 + 5 * 2);
  EXPECT_LE(max_curve_distance(original, refined), kTol);
  EXPECT_THROW(refined.refine(3, 1, 2), std::invalid_argument);  // degree reduction
  EXPECT_THROW(refined.refine(4, 4, 2), std::invalid_argument);  // continuity >= degree
}

INSTANTIATE_TEST_SUITE_P(Spline, CurveRefinement, ::testing::Values(false, true),
                         [](const auto& info) { return info.param ? "Rational" : "Polynomial"; });

TEST(CurveRefinement, RefineNeverRaisesMultiplicityAboveExisting) {
  // A full circle has C0 knots at 0.25, 0.5, 0.75; refining to C1 keeps them C0 and adds the grid knots.
  const NurbsCurve arc = make_arc({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 2.0, 0.0, 2 * std::numbers::pi);
  NurbsCurve refined = arc;
  refined.refine(3, 1, 8);
  EXPECT_EQ(refined.knots().multiplicity(0.5), 3);  // 2 from the arc + 1 from elevation: still C0
  EXPECT_EQ(refined.knots().multiplicity(0.125), 2);
  EXPECT_EQ(refined.knots().num_elements(), 8);
  EXPECT_LE(max_curve_distance(arc, refined), kTol);
}

// A geometric grid: interior knots (r^k - 1) / (r^n - 1) on [0, 1], consecutive element lengths in the
// ratio r (to 1e-12), and refining on it keeps the geometry.
TEST(CurveRefinement, GeometricGridMatchesTheSeries) {
  for (double r : {1.25, 0.8, 1.0}) {
    const int n = 7;
    const std::vector<double> grid = geometric_grid(0.0, 1.0, n, r);
    ASSERT_EQ(grid.size(), 6u);
    for (int k = 1; k < n; ++k)
      EXPECT_NEAR(grid[k - 1], r == 1.0 ? k / 7.0 : (std::pow(r, k) - 1) / (std::pow(r, n) - 1), 1e-15);
    std::vector<double> x{0.0};
    x.insert(x.end(), grid.begin(), grid.end());
    x.push_back(1.0);
    for (int k = 1; k < n; ++k) EXPECT_NEAR((x[k + 1] - x[k]) / (x[k] - x[k - 1]), r, 1e-12);
    // On another domain the grid is the same fractions of it.
    const std::vector<double> shifted = geometric_grid(2.0, 6.0, n, r);
    for (int k = 0; k < n - 1; ++k) EXPECT_NEAR(shifted[k], 2.0 + 4.0 * grid[k], 1e-14);
  }
  EXPECT_THROW(geometric_grid(0.0, 1.0, 4, 0.0), std::invalid_argument);
  EXPECT_THROW(geometric_grid(0.0, 1.0, 4, -2.0), std::invalid_argument);

  const NurbsCurve arc = make_arc({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 2.0, 0.0, 1.0);
  NurbsCurve graded = arc;
  const std::vector<double> grid = geometric_grid(0.0, 1.0, 5, 0.7);
  graded.refine(3, 2, grid);
  EXPECT_EQ(graded.knots().num_elements(), 5);
  for (double u : grid) EXPECT_EQ(graded.knots().multiplicity(u), 1);
  EXPECT_LE(max_curve_distance(arc, graded), kTol);
}

TEST(SurfaceRefinement, InsertionAndElevationKeepGeometry) {
  for (bool rational : {false, true}) {
    std::mt19937 rng(13);
    const NurbsSurface original = testing::random_surface(rng, rational);
    NurbsSurface refined = original;
    refined.insert_knot(0, 0.5, 2);
    refined.insert_knot(1, 0.5);
    refined.elevate_degree(0, 1);
    refined.elevate_degree(1, 2);
    EXPECT_EQ(refined.degree(0), 3);
    EXPECT_EQ(refined.degree(1), 5);
    EXPECT_EQ(refined.num_control_points(),
              refined.num_control_points(0) * refined.num_control_points(1));
    EXPECT_LE(max_surface_distance(original, refined), kTol) << "rational=" << rational;
  }
}

TEST(SurfaceRefinement, RefineSphereKeepsExactGeometry) {
  const NurbsSurface sphere = make_sphere_patch(3.0, 0.2, 2.0, -0.5, 0.9);  // 103 x 80 degrees
  NurbsSurface refined = sphere;
  refined.refine(0, 4, 3, 5);
  refined.refine(1, 3, 1, 3);
  EXPECT_EQ(refined.degree(0), 4);
  EXPECT_EQ(refined.degree(1), 3);
  EXPECT_EQ(refined.knots(0).num_elements(), 5);  // the 103-degree arc is one segment: no knot of its own
  EXPECT_EQ(refined.knots(1).num_elements(), 3);
  EXPECT_EQ(static_cast<int>(refined.elements().size()), 5 * 3);
  EXPECT_LE(max_surface_distance(sphere, refined), kTol);
}

TEST(Surface, ElementsAndEdgeIndicesOnSmallExample) {
  // u: quadratic, 2 elements (3 + 1 = 4 functions); v: linear, 3 elements (4 functions).
  const KnotVector ku(2, {0, 0, 0, 0.5, 1, 1, 1});
  const KnotVector kv(1, {0, 0, 0.25, 0.75, 1, 1});
  std::vector<Eigen::Vector3d> points;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) points.emplace_back(i, j, 0.0);
  const NurbsSurface s(ku, kv, points);
  EXPECT_EQ(s.index(1, 2), 1 + 4 * 2);
  const std::vector<SurfaceElement> els = s.elements();
  ASSERT_EQ(els.size(), 6u);
  EXPECT_EQ(els[0].span_u, 2);
  EXPECT_EQ(els[1].span_u, 3);  // u fastest
  EXPECT_EQ(els[1].span_v, 1);
  EXPECT_EQ(els[2].span_v, 2);
  EXPECT_DOUBLE_EQ(els[3].u0, 0.5);
  EXPECT_DOUBLE_EQ(els[3].v0, 0.25);
  EXPECT_DOUBLE_EQ(els[3].v1, 0.75);
  EXPECT_DOUBLE_EQ(els[5].u1, 1.0);
  EXPECT_EQ(s.edge_indices("u0"), (std::vector<int>{0, 4, 8, 12}));
  EXPECT_EQ(s.edge_indices("u1"), (std::vector<int>{3, 7, 11, 15}));
  EXPECT_EQ(s.edge_indices("v0"), (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(s.edge_indices("v1"), (std::vector<int>{12, 13, 14, 15}));
  EXPECT_EQ(s.edge_indices("u0", 1), (std::vector<int>{1, 5, 9, 13}));
  EXPECT_EQ(s.edge_indices("v1", 1), (std::vector<int>{8, 9, 10, 11}));
  EXPECT_THROW(s.edge_indices("x0"), std::invalid_argument);
  // Edge control points really lie on the edge: u = 0 maps to x = 0 (points i = 0).
  for (int idx : s.edge_indices("u0")) EXPECT_EQ(s.control_points()[idx].x(), 0.0);
  EXPECT_NEAR(s.point(0.0, 0.6).x(), 0.0, 1e-15);
}

}  // namespace
}  // namespace fibrane::spline
