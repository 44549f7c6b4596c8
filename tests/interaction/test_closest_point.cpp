// Closest-point projection (Eqs. 62-64) on curved NURBS patches: interior points, points on element
// edges and on the patch boundary, points whose projection leaves the patch, comparison with a brute-force
// search, and the warm start.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <vector>

#include "interaction/closest_point.hpp"
#include "test_geometry.hpp"

namespace fibrane::interaction {
namespace {

using Where = ShellProximity::Projection::Where;

// Parameters are recovered to the Newton tolerance (|h_a| ~ 1e-13 |g_a| L, C_ab = O(|g|^2)), i.e. ~1e-12
// in parameter units of these O(1) patches; 1e-10 leaves room for the conditioning of C_ab.
constexpr double kParamTol = 1e-10;

void expect_projects_to(const ShellProximity& prox, const Eigen::Vector3d& p, double u, double v,
                        double distance) {
  const auto r = prox.project(p);
  ASSERT_EQ(r.where, Where::interior) << p.transpose();
  EXPECT_NEAR(r.u, u, kParamTol);
  EXPECT_NEAR(r.v, v, kParamTol);
  EXPECT_NEAR(r.distance, distance, 1e-12 * (1 + distance));
  EXPECT_NEAR((r.point + r.distance * r.normal - p).norm(), 0.0, 1e-12);
  const auto& e = prox.elements()[r.element];
  EXPECT_TRUE(r.u >= e.u0 && r.u <= e.u1 && r.v >= e.v0 && r.v <= e.v1);
}

TEST(ClosestPoint, CylinderInteriorEdgeAndBoundaryPoints) {
  const spline::NurbsSurface s = test::cylinder();
  const ShellProximity prox(s);
  const double edge_u = s.knots(0).unique_knots()[2], edge_v = s.knots(1).unique_knots()[1];
  // (u, v): interior, on an element edge in u, on an element corner, on the patch boundary u = 0, v = 1.
  const std::vector<Eigen::Vector2d> params = {{0.37, 0.61}, {edge_u, 0.42}, {edge_u, edge_v},
                                               {0.0, 0.5},   {0.8, 1.0},   {1.0, 0.0}};
  for (const Eigen::Vector2d& t : params) {
    for (double offset : {-0.7, 0.05, 0.9}) {  // inside and outside the cylinder (R = 2)
      const Eigen::Vector3d p = s.point(t[0], t[1]) + offset * test::unit_normal(s, t[0], t[1]);
      expect_projects_to(prox, p, t[0], t[1], std::abs(offset));
    }
  }
}

TEST(ClosestPoint, SpherePointsProjectRadially) {
  const spline::NurbsSurface s = test::sphere();
  const ShellProximity prox(s);
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int k = 0; k < 50; ++k) {
    const double u = unit(gen), v = unit(gen), c = k % 2 ? 1.4 : 0.55;
    expect_projects_to(prox, c * s.point(u, v), u, v, std::abs(c - 1) * 1.5);
  }
  // Exactly on the element edges of the refined sphere.
  const double eu = s.knots(0).unique_knots()[3], ev = s.knots(1).unique_knots()[2];
  expect_projects_to(prox, 1.2 * s.point(eu, ev), eu, ev, 0.3);
}

TEST(ClosestPoint, OutsideThePatchIsReportedOutside) {
  const spline::NurbsSurface s = test::cylinder();
  const ShellProximity prox(s);
  // Beyond the axial end x = 0 and beyond the angular edge theta = 0.3 (R = 2 cylinder about x).
  const Eigen::Vector3d beyond_end(-0.5, 2.3 * std::cos(0.8), 2.3 * std::sin(0.8));
  const Eigen::Vector3d beyond_edge(1.7, 2.2 * std::cos(0.1), 2.2 * std::sin(0.1));
  auto r = prox.project(beyond_end);
  EXPECT_EQ(r.where, Where::outside);
  EXPECT_NEAR(r.v, 0.0, 1e-15);  // clamped onto the boundary v = 0
  r = prox.project(beyond_edge);
  EXPECT_EQ(r.where, Where::outside);
  EXPECT_NEAR(r.u, 0.0, 1e-15);
  // Just inside the end the projection is interior again.
  EXPECT_EQ(prox.project(Eigen::Vector3d(0.01, 2.3 * std::cos(0.8), 2.3 * std::sin(0.8))).where,
            Where::interior);
}

// On every curved patch: a point along the normal of an element-edge point, of a patch-boundary point
// (both stationary points of the distance: interior), and the boundary point pushed further out beyond
// the edge (the stationary point leaves the patch: outside, clamped onto the edge).
TEST(ClosestPoint, EdgesBoundariesAndOutsideOnAllCurvedPatches) {
  const std::vector<spline::NurbsSurface> surfaces = {test::cylinder(), test::sphere(), test::random_patch(5, 7)};
  for (const spline::NurbsSurface& s : surfaces) {
    const ShellProximity prox(s);
    const double knot_u = s.knots(0).unique_knots()[2], knot_v = s.knots(1).unique_knots()[1];
    for (const Eigen::Vector2d& t : {Eigen::Vector2d(knot_u, 0.43), Eigen::Vector2d(0.61, knot_v),
                                     Eigen::Vector2d(0.0, 0.55), Eigen::Vector2d(0.35, 1.0)}) {
      const Eigen::Vector3d p = s.point(t[0], t[1]) + 0.1 * test::unit_normal(s, t[0], t[1]);
      expect_projects_to(prox, p, t[0], t[1], 0.1);
    }
    // Beyond the edge u = 0 (against g_1) and beyond v = 1 (along g_2).
    const spline::SurfaceBasis b0 = s.basis(0.0, 0.55), b1 = s.basis(0.35, 1.0);
    Eigen::Vector3d g1 = Eigen::Vector3d::Zero(), g2 = Eigen::Vector3d::Zero();
    for (std::size_t a = 0; a < b0.indices.size(); ++a) g1 += b0.R(1, a) * s.control_points()[b0.indices[a]];
    for (std::size_t a = 0; a < b1.indices.size(); ++a) g2 += b1.R(2, a) * s.control_points()[b1.indices[a]];
    auto r = prox.project(s.point(0.0, 0.55) + 0.1 * test::unit_normal(s, 0.0, 0.55) - 0.2 * g1.normalized());
    EXPECT_EQ(r.where, Where::outside);
    EXPECT_EQ(r.u, 0.0);
    r = prox.project(s.point(0.35, 1.0) + 0.1 * test::unit_normal(s, 0.35, 1.0) + 0.2 * g2.normalized());
    EXPECT_EQ(r.where, Where::outside);
    EXPECT_EQ(r.v, 1.0);
  }
}

TEST(ClosestPoint, CentreOfTheSphereIsDegenerate) {
  // Every point of the sphere patch is at distance R from the centre: C_ab = g_ab - R b_ab = 0.
  const ShellProximity prox(spline::make_sphere_patch(1.5, 0.2, 1.6, -0.6, 0.8));
  EXPECT_EQ(prox.project(Eigen::Vector3d::Zero()).where, Where::failed);
}

// A groove z = x^2 (kappa = 2) over x, y in [0, 1], its edge x = 0 a mirror plane, as under a fiber that
// indents a symmetric shell. From p = (0, y, h) the distance along the mirror edge is stationary in x by
// symmetry; it is a minimum for h < 1/kappa and a maximum for h > 1/kappa, where the closest point is
// x^2 = h - 1/2 (f = x^2 + (h - x^2)^2). Quadratic in x, so the B-spline holds the parabola exactly.
TEST(ClosestPoint, SaddleOnAMirrorEdgeMovesToTheGroovesMinimum) {
  const spline::KnotVector ku = spline::KnotVector::open_uniform(2, 1, 1);
  const spline::KnotVector kv = spline::KnotVector::open_uniform(1, 1, 0);
  std::vector<Eigen::Vector3d> points;
  for (int j = 0; j < 2; ++j)
    for (const Eigen::Vector2d& xz : {Eigen::Vector2d(0, 0), Eigen::Vector2d(0.5, 0), Eigen::Vector2d(1, 1)})
      points.emplace_back(xz[0], j, xz[1]);
  const spline::NurbsSurface groove(ku, kv, points);
  const ShellProximity prox(groove);
  ASSERT_NEAR(groove.point(0.3, 0.4)[2], 0.09, 1e-15);
  // Shallow point: the mirror edge itself.
  expect_projects_to(prox, Eigen::Vector3d(0, 0.4, 0.3), 0.0, 0.4, 0.3);
  // At the centre of curvature (h = 1/kappa): f = 1/4 + x^4, a minimum flat to fourth order. Kept (interior),
  // not dropped: u to the quartic's accuracy (h_1 = 4 x^3 <= 1e-13 -> x ~ 5e-5), distance to round-off.
  const auto flat = prox.project(Eigen::Vector3d(0, 0.4, 0.5), Eigen::Vector2d(0.0, 0.4));
  ASSERT_EQ(flat.where, Where::interior);
  EXPECT_NEAR(flat.u, 0.0, 1e-4);
  EXPECT_NEAR(flat.distance, 0.5, 1e-12);
  // Deep points: the minimum beside the edge, from a cold start and from a warm start on the edge (the
  // previous step's projection when the groove deepens).
  for (double h : {0.55, 0.75, 1.0}) {
    const double x = std::sqrt(h - 0.5), d = std::sqrt(x * x + 0.25);
    expect_projects_to(prox, Eigen::Vector3d(0, 0.4, h), x, 0.4, d);
    const auto warm = prox.project(Eigen::Vector3d(0, 0.4, h), Eigen::Vector2d(0.0, 0.4));
    ASSERT_EQ(warm.where, Where::interior) << h;
    EXPECT_NEAR(warm.u, x, kParamTol);
    EXPECT_NEAR(warm.distance, d, 1e-12);
  }
}

// Two nearly equally close minima: the parabola z = x^2 over x in [-1, 1] (40 elements) seen from
// p = (delta, 0.5, 1) has minima near x = +-0.707 (f = d^2 = (x - delta)^2 + (1 - x^2)^2), the one at +x
// closer by 2.8 delta in d^2, i.e. by 1.9e-3 of d for delta = 1e-3. From a start at the -x minimum, margin 0
// moves to the closer +x one (the global check finds a closer sample there); a margin of 1e-2 of d keeps
// the -x branch (a point stays on its branch), and a start at +x stays there anyway.
TEST(ClosestPoint, KeepMarginKeepsANearlyEquallyCloseBranch) {
  const spline::KnotVector ku = spline::KnotVector::open_uniform(2, 1, 1);
  const spline::KnotVector kv = spline::KnotVector::open_uniform(1, 1, 0);
  std::vector<Eigen::Vector3d> points;
  for (int j = 0; j < 2; ++j)
    for (const Eigen::Vector2d& xz : {Eigen::Vector2d(-1, 1), Eigen::Vector2d(0, -1), Eigen::Vector2d(1, 1)})
      points.emplace_back(xz[0], j, xz[1]);
  spline::NurbsSurface parabola(ku, kv, points);
  parabola.refine(0, 2, 1, 40);
  const ShellProximity prox(parabola);
  // y = 0.5: on the middle row of the 3 x 3 samples by which the global check finds the other branch (it
  // switches only where a sample beats the bound, i.e. to a branch closer by more than the sampling error)
  const Eigen::Vector3d p(1e-3, 0.5, 1.0);
  const Eigen::Vector2d left(0.5 * (1 - std::sqrt(0.5)), 0.5), right(0.5 * (1 + std::sqrt(0.5)), 0.5);
  const auto switched = prox.project(p, left);
  const auto kept = prox.project(p, left, 1e-2);
  ASSERT_EQ(switched.where, Where::interior);
  ASSERT_EQ(kept.where, Where::interior);
  EXPECT_GT(switched.u, 0.5);  // the closer, +x minimum
  EXPECT_LT(kept.u, 0.5);      // still the -x branch
  EXPECT_GT(kept.distance, switched.distance);
  EXPECT_LT(kept.distance - switched.distance, 1e-2 * switched.distance);
  EXPECT_GT(prox.project(p, right, 1e-2).u, 0.5);
}

// Brute force: dense 200 x 200 sampling, then a pattern search (coordinate steps halved until 1e-12) that
// shares nothing with the Newton iteration under test.
Eigen::Vector3d brute_force(const spline::NurbsSurface& s, const Eigen::Vector3d& p) {
  double best = 1e300, bu = 0, bv = 0;
  for (int j = 0; j <= 200; ++j)
    for (int i = 0; i <= 200; ++i) {
      const double f = (s.point(i / 200.0, j / 200.0) - p).squaredNorm();
      if (f < best) best = f, bu = i / 200.0, bv = j / 200.0;
    }
  for (double h = 1.0 / 200; h > 1e-12;) {
    bool moved = false;
    for (auto [du, dv] : {std::pair{h, 0.0}, {-h, 0.0}, {0.0, h}, {0.0, -h}}) {
      const double u = std::clamp(bu + du, 0.0, 1.0), v = std::clamp(bv + dv, 0.0, 1.0);
      const double f = (s.point(u, v) - p).squaredNorm();
      if (f < best) best = f, bu = u, bv = v, moved = true;
    }
    if (!moved) h *= 0.5;
  }
  return {bu, bv, std::sqrt(best)};
}

TEST(ClosestPoint, RandomPatchMatchesBruteForce) {
  const spline::NurbsSurface s = test::random_patch(6, 11);
  const ShellProximity prox(s);
  std::mt19937 gen(5);
  std::uniform_real_distribution<double> unit(0.05, 0.95), height(-0.6, 0.6);
  for (int k = 0; k < 15; ++k) {
    const double u = unit(gen), v = unit(gen);
    const Eigen::Vector3d p = s.point(u, v) + height(gen) * test::unit_normal(s, u, v) +
                              Eigen::Vector3d(0.1 * height(gen), 0.1 * height(gen), 0);
    const auto r = prox.project(p);
    const Eigen::Vector3d ref = brute_force(s, p);
    ASSERT_EQ(r.where, Where::interior);
    // Distance: both are minima of the same function; the pattern search stops at step 1e-12, so its
    // distance is exact to ~1e-14 (quadratic minimum). Parameters: a flat minimum only fixes them to
    // ~sqrt(eps / curvature) in the pattern search, hence 1e-6.
    EXPECT_NEAR(r.distance, ref[2], 1e-11 * (1 + ref[2]));
    EXPECT_LE(r.distance, ref[2] + 1e-13);
    EXPECT_NEAR(r.u, ref[0], 1e-6);
    EXPECT_NEAR(r.v, ref[1], 1e-6);
  }
}

TEST(ClosestPoint, FollowsTheDeformedSurfaceAfterUpdate) {
  const spline::NurbsSurface s = test::random_patch(5, 2);
  ShellProximity prox(s);
  std::vector<Eigen::Vector3d> moved = s.control_points();
  for (Eigen::Vector3d& x : moved) x += Eigen::Vector3d(0.3, -0.2, 0.5 + 0.1 * x.x());
  prox.update(moved);
  const spline::NurbsSurface deformed(s.knots(0), s.knots(1), moved);
  const Eigen::Vector3d p = deformed.point(0.4, 0.7) + 0.3 * test::unit_normal(deformed, 0.4, 0.7);
  expect_projects_to(prox, p, 0.4, 0.7, 0.3);
}

TEST(ClosestPoint, WarmStartNeedsFewerIterations) {
  const spline::NurbsSurface s = test::random_patch(6, 4);
  const ShellProximity prox(s);
  std::mt19937 gen(9);
  std::uniform_real_distribution<double> unit(0.1, 0.9);
  int cold = 0, warm = 0;
  for (int k = 0; k < 40; ++k) {
    const double u = unit(gen), v = unit(gen);
    const Eigen::Vector3d p = s.point(u, v) + 0.4 * test::unit_normal(s, u, v);
    const auto previous = prox.project(p);
    const Eigen::Vector3d q = p + Eigen::Vector3d(1e-4, -2e-4, 1e-4);  // next Newton iterate's point
    const auto c = prox.project(q);
    const auto w = prox.project(q, Eigen::Vector2d(previous.u, previous.v));
    ASSERT_EQ(w.where, Where::interior);
    EXPECT_NEAR(w.distance, c.distance, 1e-13);
    cold += c.iterations;
    warm += w.iterations;
  }
  EXPECT_LT(warm, cold * 3 / 4) << "warm " << warm << " cold " << cold;
  std::printf("    Newton iterations over 40 points: cold %d, warm %d\n", cold, warm);
}

// A point that is not finite, or so far away that squared distances overflow (an overflowing time step puts
// beam points there), has no projection: the result is `failed` (the coupling then reports the point as
// lost, or the model the state as invalid), never an exception from the parameter search.
TEST(ClosestPoint, NonFiniteOrOverflowingPointsHaveNoProjection) {
  const spline::NurbsSurface s = test::cylinder();
  ShellProximity prox(s);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  const std::vector<Eigen::Vector3d> points = {{nan, 0, 0}, {0, inf, 1}, {1e200, -1e200, 1e200}, {0.3, 0.1, -1e300}};
  for (const Eigen::Vector3d& p : points) {
    using Start = std::optional<Eigen::Vector2d>;
    for (const Start& start : {Start(), Start(Eigen::Vector2d(0.4, 0.6))}) {
      ShellProximity::Projection r;
      ASSERT_NO_THROW(r = prox.project(p, start)) << p.transpose();
      if (!p.allFinite()) {
        EXPECT_EQ(r.where, Where::failed) << p.transpose();
      }
      if (r.where != Where::failed) {
        EXPECT_TRUE(std::isfinite(r.u) && std::isfinite(r.v)) << p.transpose();
      }
    }
  }
  // A shell whose control points overflowed: no projection either.
  std::vector<Eigen::Vector3d> points_nan = s.control_points();
  for (Eigen::Vector3d& x : points_nan) x.x() = nan;
  prox.update(points_nan);
  ShellProximity::Projection r;
  ASSERT_NO_THROW(r = prox.project(Eigen::Vector3d(0.1, 0.2, 0.3), Eigen::Vector2d(0.4, 0.6)));
  EXPECT_EQ(r.where, Where::failed);
}

}  // namespace
}  // namespace fibrane::interaction
