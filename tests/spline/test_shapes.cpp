// Generators are exact: points on the circle / sphere / cylinder to round-off (1e-13 for O(1) radii:
// a few dozen ulps of the rational evaluation), and tangents along the analytic directions.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "spline/shapes.hpp"

namespace fibrane::spline {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kExact = 1e-13;

TEST(Shapes, ArcIsExactWithAnalyticTangents) {
  const Eigen::Vector3d center(1.0, -2.0, 0.5);
  const Eigen::Vector3d e1 = Eigen::Vector3d(1, 1, 0).normalized();
  const Eigen::Vector3d e2 = Eigen::Vector3d(0, 0, 1);
  for (const auto& [a0, a1] : {std::pair{0.0, kPi / 3}, {-0.3, 2.9}, {0.0, 2 * kPi}, {1.0, -1.5}}) {
    const NurbsCurve arc = make_arc(center, e1, e2, 2.5, a0, a1);
    EXPECT_EQ(arc.degree(), 2);
    EXPECT_LE((arc.point(0.0) - (center + 2.5 * (std::cos(a0) * e1 + std::sin(a0) * e2))).norm(), kExact);
    EXPECT_LE((arc.point(1.0) - (center + 2.5 * (std::cos(a1) * e1 + std::sin(a1) * e2))).norm(), kExact);
    for (int s = 0; s <= 200; ++s) {
      const double u = s / 200.0;
      const Eigen::Vector3d x = arc.point(u);
      EXPECT_NEAR((x - center).norm(), 2.5, kExact);
      // The tangent is perpendicular to the radius and in the plane, turning in the sweep's sense.
      const Eigen::Vector3d r = (x - center).normalized();
      const Eigen::Vector3d t = arc.derivative(u, 1).normalized();
      const Eigen::Vector3d expected = std::copysign(1.0, a1 - a0) * e1.cross(e2).cross(r);
      EXPECT_LE((t - expected).norm(), 1e-12) << "u=" << u;
    }
  }
  // Up to 120 degrees: one Bezier segment; a half circle: two, joined C1 (a simple knot).
  EXPECT_EQ(make_arc(center, e1, e2, 1.0, 0.0, kPi / 2).knots().num_elements(), 1);
  EXPECT_EQ(make_arc(center, e1, e2, 1.0, 0.0, 2 * kPi / 3).knots().num_elements(), 1);
  EXPECT_EQ(make_arc(center, e1, e2, 1.0, 0.0, kPi).knots().num_elements(), 2);
  EXPECT_EQ(make_arc(center, e1, e2, 1.0, 0.0, kPi).knots().multiplicity(0.5), 1);
  EXPECT_THROW(make_arc(center, e1, e2, 1.0, 0.0, 7.0), std::invalid_argument);
}

// Every arc below a full turn has no C0 knot (no knot of multiplicity >= the degree inside the domain), its
// points lie on the circle to 1e-12 of the radius, the angle grows monotonically with the parameter, and
// its tangent direction is continuous (the two one-sided tangents at the interior knot agree to 1e-12).
TEST(Shapes, ArcsBelowAFullTurnHaveNoC0Knot) {
  const Eigen::Vector3d center(0.3, 0.0, -1.0), e1(0, 1, 0), e2(0, 0, 1);
  const double radius = 3.0;
  for (double degrees : {30.0, 90.0, 100.0, 120.0, 150.0, 179.0, 180.0, 181.0, 270.0, 359.0}) {
    SCOPED_TRACE(std::to_string(degrees) + " degrees");
    const double a0 = -0.4, a1 = a0 + degrees * kPi / 180.0;
    const NurbsCurve arc = make_arc(center, e1, e2, radius, a0, a1);
    const KnotVector& kv = arc.knots();
    EXPECT_EQ(kv.num_elements(), degrees <= 120.0 ? 1 : 2);
    for (double u : kv.unique_knots())
      if (u > kv.front() && u < kv.back()) EXPECT_LT(kv.multiplicity(u), kv.degree());
    double previous = -1e300;
    for (int s = 0; s <= 400; ++s) {
      const double u = s / 400.0;
      const Eigen::Vector3d x = arc.point(u) - center;
      EXPECT_NEAR(x.norm(), radius, 1e-12 * radius);
      EXPECT_NEAR(x.x(), 0.0, 1e-12 * radius);
      // The angle from e1, unwrapped from a0 on.
      double angle = std::atan2(x.dot(e2), x.dot(e1));
      while (angle < a0 - 1e-9) angle += 2 * kPi;
      EXPECT_GT(angle, previous - 1e-12);
      previous = angle;
    }
    EXPECT_NEAR(previous, a1, 1e-12);
    const Eigen::Vector3d left = arc.derivative(0.5 - 1e-13, 1), right = arc.derivative(0.5 + 1e-13, 1);
    EXPECT_LE((left - right).norm(), 1e-9 * right.norm());  // C1 in the parameter at the middle
  }
  // A full turn keeps its four 90-degree segments joined C0 (a ring has a seam anyway).
  const NurbsCurve ring = make_arc(center, e1, e2, radius, 0.0, 2 * kPi);
  EXPECT_EQ(ring.knots().multiplicity(0.5), 2);
}

// A half cylinder (180 degrees) has no C0 knot line and lies on the exact cylinder to 1e-12 of the radius,
// also after refinement (degree 3, C2, 6 x 2 elements).
TEST(Shapes, HalfCylinderIsC1AndExact) {
  const double radius = 2.0, length = 5.0;
  NurbsSurface half = make_cylinder_patch(radius, length, 0.0, kPi);
  EXPECT_EQ(half.knots(0).multiplicity(0.5), 1);
  half.refine(0, 3, 2, 6);
  half.refine(1, 3, 2, 2);
  for (int dir = 0; dir < 2; ++dir)
    for (double u : half.knots(dir).unique_knots())
      if (u > 0.0 && u < 1.0) EXPECT_LE(half.knots(dir).multiplicity(u), 2) << "dir " << dir << " knot " << u;
  for (int s = 0; s <= 60; ++s)
    for (int t = 0; t <= 6; ++t) {
      const Eigen::Vector3d x = half.point(s / 60.0, t / 6.0);
      EXPECT_NEAR(std::hypot(x.y(), x.z()), radius, 1e-12 * radius);
      EXPECT_GE(x.z(), -1e-12 * radius);
    }
  EXPECT_LE((half.point(1.0, 0.0) - Eigen::Vector3d(0, -radius, 0)).norm(), 1e-12 * radius);
  EXPECT_LE((half.point(0.5, 0.0) - Eigen::Vector3d(0, 0, radius)).norm(), 1e-12 * radius);  // symmetric
}

TEST(Shapes, LineAndRectangle) {
  const NurbsCurve line = make_line({0, 0, 0}, {2, 4, 6});
  EXPECT_LE((line.point(0.25) - Eigen::Vector3d(0.5, 1, 1.5)).norm(), 1e-15);
  const NurbsSurface rect = make_rectangle({1, 0, 0}, {2, 0, 0}, {0, 3, 0});
  EXPECT_LE((rect.point(0.5, 1.0 / 3.0) - Eigen::Vector3d(2, 1, 0)).norm(), 1e-15);
  EXPECT_FALSE(rect.is_rational());
}

TEST(Shapes, CylinderPatchConvention) {
  const double radius = 25.0, length = 50.0;  // Scordelis-Lo roof: 80 degrees centred on +z
  const double t0 = kPi / 2 - 40 * kPi / 180, t1 = kPi / 2 + 40 * kPi / 180;
  const NurbsSurface roof = make_cylinder_patch(radius, length, t0, t1);
  EXPECT_LE((roof.point(0.5, 0.0) - Eigen::Vector3d(0, 0, radius)).norm(), kExact * radius);  // apex
  EXPECT_LE((roof.point(0.0, 1.0) - Eigen::Vector3d(length, radius * std::cos(t0), radius * std::sin(t0))).norm(),
            kExact * radius);
  for (int s = 0; s <= 30; ++s)
    for (int t = 0; t <= 10; ++t) {
      const Eigen::Vector3d x = roof.point(s / 30.0, t / 10.0);
      EXPECT_NEAR(std::hypot(x.y(), x.z()), radius, kExact * radius);  // distance from the x axis
      EXPECT_NEAR(x.x(), length * t / 10.0, kExact * length);
    }
  const NurbsSurface full = make_cylinder_patch(1.0, 2.0, 0.0, 2 * kPi);
  EXPECT_EQ(full.knots(0).num_elements(), 4);
  for (int s = 0; s <= 100; ++s) EXPECT_NEAR(std::hypot(full.point(s / 100.0, 0.3).y(), full.point(s / 100.0, 0.3).z()), 1.0, kExact);
}

TEST(Shapes, SpherePatchIsExact) {
  const double radius = 10.0;
  const NurbsSurface hemisphere = make_sphere_patch(radius, 0.0, 2 * kPi, 0.0, kPi / 2);
  const NurbsSurface patch = make_sphere_patch(radius, -0.4, 1.3, -1.2, 0.3);
  for (const NurbsSurface* s : {&hemisphere, &patch})
    for (int i = 0; i <= 40; ++i)
      for (int j = 0; j <= 40; ++j) EXPECT_NEAR(s->point(i / 40.0, j / 40.0).norm(), radius, kExact * radius);
  // Corners follow the documented (longitude, latitude) convention.
  const Eigen::Vector3d corner = patch.point(1.0, 0.0);
  EXPECT_LE((corner - radius * Eigen::Vector3d(std::cos(-1.2) * std::cos(1.3), std::cos(-1.2) * std::sin(1.3),
                                               std::sin(-1.2))).norm(), kExact * radius);
  EXPECT_LE((hemisphere.point(0.3, 1.0) - Eigen::Vector3d(0, 0, radius)).norm(), kExact * radius);  // pole
}

}  // namespace
}  // namespace fibrane::spline
