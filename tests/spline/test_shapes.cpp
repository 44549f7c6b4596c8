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
  // Quarter of a circle: one Bezier segment; a half circle: two, joined C0.
  EXPECT_EQ(make_arc(center, e1, e2, 1.0, 0.0, kPi / 2).knots().num_elements(), 1);
  EXPECT_EQ(make_arc(center, e1, e2, 1.0, 0.0, kPi).knots().num_elements(), 2);
  EXPECT_THROW(make_arc(center, e1, e2, 1.0, 0.0, 7.0), std::invalid_argument);
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
