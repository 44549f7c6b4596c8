// Limit points located between arc-length steps: the parabola through the last three points of a path
// whose t(s) is itself a parabola is exact, and observables are interpolated at the same vertex.
#include <gtest/gtest.h>

#include "model/model.hpp"
#include "run/limit_points.hpp"

namespace fibrane::run {
namespace {

TEST(LimitPoints, VertexOfTheParabolaThroughTheLastThreePoints) {
  model::Model m;  // the observables below ignore it
  double value = 0;
  LimitPointFinder finder({{"q", [&](const model::Model&) { return value; }}});
  // t(s) = 2 - (s - 1.3)^2 with a maximum at s = 1.3; the observable q = 3 s + 1 there is 4.9.
  const double s[4] = {0.4, 0.9, 1.5, 2.2};
  for (int k = 0; k < 4; ++k) {
    solve::StepReport r;
    r.step = k + 1;
    r.path_length = s[k];
    r.t = 2 - (s[k] - 1.3) * (s[k] - 1.3);
    r.limit_point = k == 2;  // t rose from 0.9 to 1.5 only before, fell after: flagged at the third point
    value = 3 * s[k] + 1;
    EXPECT_EQ(finder.add(r, m), k == 2) << k;
  }
  ASSERT_EQ(finder.found().size(), 1u);
  const LimitPoint& p = finder.found()[0];
  EXPECT_TRUE(p.maximum);
  EXPECT_NEAR(p.path_length, 1.3, 1e-14);
  EXPECT_NEAR(p.t, 2.0, 1e-14);
  ASSERT_EQ(p.values.size(), 1u);
  EXPECT_NEAR(p.values[0].second, 4.9, 1e-13);
  EXPECT_EQ(p.step, 3);
}

TEST(LimitPoints, NoPathCoordinateNoLocation) {
  model::Model m;
  LimitPointFinder finder({});
  for (int k = 0; k < 3; ++k) {
    solve::StepReport r;
    r.t = k == 1 ? 1.0 : 0.5;
    r.limit_point = k == 2;
    EXPECT_FALSE(finder.add(r, m));  // load stepping has no path length: nothing to interpolate in
  }
}

}  // namespace
}  // namespace fibrane::run
