// The shallow hinged cylindrical roof under a central point load (examples/shallow-roof.yaml): arc-length
// continuation through the snap-through of the 12.7 mm roof and the snap-back of the 6.35 mm roof, the
// first limit point against Sze, Liu & Lo (2004), Table 9 (docs/verification.md, "Shell
// snap-through (shallow roof)", has the mesh study and the reference).
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "case_runner.hpp"

namespace fibrane::testing {
namespace {

constexpr double kPMax = 3000.0;  // N: the whole roof's load at t = 1 (the example applies a quarter)

// Sze et al.'s tabulated point of largest load on the way up: P (N) and the central deflection -W (mm).
struct Published {
  double load, deflection;
};
constexpr Published kThick{0.7421 * kPMax, 11.293};  // h = 12.7
constexpr Published kThin{0.1953 * kPMax, 12.892};   // h = 6.35

// The test's mesh: quartic C3, 4 x 4 elements on the quarter (the example: 8 x 8), the example's arc
// lengths; under a second of CPU time for both thicknesses.
CaseRun run_roof(const std::string& name, const std::string& thickness) {
  return run_yaml(name, example_text("shallow-roof.yaml", {{"elements: [8, 8]", "elements: [4, 4]"},
                                                            {"thickness: 12.7", "thickness: " + thickness}}),
                  1);
}

// The parabola t(w) through the converged step with the first maximum of t and its two neighbours.
struct LimitPoint {
  std::size_t step = 0;  // the step with the largest t
  double a = 0, b = 0, c = 0;  // t = a w^2 + b w + c
  double w() const { return -b / (2 * a); }
  double t() const { return t_at(w()); }
  double t_at(double x) const { return (a * x + b) * x + c; }
};

LimitPoint first_limit_point(const std::vector<double>& t, const std::vector<double>& w) {
  LimitPoint lp;
  for (std::size_t i = 1; i + 1 < t.size() && lp.step == 0; ++i)
    if (t[i] >= t[i - 1] && t[i] > t[i + 1]) lp.step = i;
  if (lp.step == 0) return lp;
  const double x0 = w[lp.step - 1], x1 = w[lp.step], x2 = w[lp.step + 1];
  const double y0 = t[lp.step - 1], y1 = t[lp.step], y2 = t[lp.step + 1];
  const double d01 = (y1 - y0) / (x1 - x0), d12 = (y2 - y1) / (x2 - x1);
  lp.a = (d12 - d01) / (x2 - x0);
  lp.b = d01 - lp.a * (x0 + x1);
  lp.c = y0 - (lp.a * x0 + lp.b) * x0;
  return lp;
}

// The first limit point against the published one: its load within `load_tolerance` (relative), its
// deflection within 7 %, and the load of the path at the published deflection within 1 %.
LimitPoint check_first_limit_point(const std::vector<double>& t, const std::vector<double>& w, const Published& ref,
                                   double load_tolerance) {
  const LimitPoint lp = first_limit_point(t, w);
  EXPECT_GT(lp.step, 0u) << "no maximum of t along the path";
  if (lp.step == 0) return lp;
  EXPECT_LT(lp.a, 0.0);
  EXPECT_NEAR(kPMax * lp.t(), ref.load, load_tolerance * ref.load);
  EXPECT_NEAR(lp.w(), ref.deflection, 0.07 * ref.deflection);
  EXPECT_GT(ref.deflection, w[lp.step - 1]);
  EXPECT_LT(ref.deflection, w[lp.step + 1]);
  EXPECT_NEAR(kPMax * lp.t_at(ref.deflection), ref.load, 0.01 * ref.load);
  return lp;
}

// Downward central deflection along the path.
std::vector<double> deflection(const CaseRun& r) {
  std::vector<double> w;
  for (double v : r.history.at("w_centre")) w.push_back(-v);
  return w;
}

// Indices of the steps where t turned (dt changed sign against the previous step).
std::vector<std::size_t> turns_of_t(const std::vector<double>& t) {
  std::vector<std::size_t> turns;
  for (std::size_t i = 2; i < t.size(); ++i)
    if ((t[i] - t[i - 1]) * (t[i - 1] - t[i - 2]) < 0) turns.push_back(i);
  return turns;
}

// h = 12.7: snap-through. Measured with this mesh: limit load 2226.0 N (-0.02 % from Sze's 2226.3; the
// converged value, quartic 8 x 8 and 16 x 16 with a quarter of the arc length, is 2225.4 N, -0.04 %),
// deflection there 10.68 mm (converged 10.72 mm). Tolerances:
//  * limit load 0.2 %: ten times the measured 0.02 %, and five times the difference of the converged
//    value from the reference; the interpolation of the maximum contributes 1e-4 (verification.md).
//  * deflection at the limit point 7 % of Sze's 11.293 mm: measured -5.5 % (converged -5.1 %). The mesh
//    accounts for only 0.4 % of it; the rest is the location of a flat maximum (dP/dw = 0 there), which
//    is ill-conditioned: Sze's number is the deflection of the table row with the largest load, not an
//    interpolated vertex. The well-conditioned comparison is the load on our path at Sze's deflection:
//    measured -0.48 % (converged -0.43 to -0.44 %), checked within 1 %.
TEST(ShallowRoof, ThickRoofSnapsThroughAtThePublishedLimitLoad) {
  const auto r = run_roof("roof-thick", "12.7");
  ASSERT_TRUE(r.summary.result.completed()) << r.summary.result.message;
  const auto& t = r.history.at("t");
  const auto w = deflection(r);
  EXPECT_DOUBLE_EQ(t.back(), 1.0);

  const LimitPoint lp = check_first_limit_point(t, w, kThick, 0.002);
  ASSERT_GT(lp.step, 0u);

  // The path goes on through the snap-through: t falls to a minimum (second limit point, still a
  // positive load for this thickness), then rises again to t_end = 1, which lies far above the limit
  // load, while the deflection grows monotonically (no snap-back at h = 12.7).
  const auto turns = turns_of_t(t);
  ASSERT_EQ(turns.size(), 2u);
  EXPECT_EQ(turns[0], lp.step + 1);
  const std::size_t minimum = turns[1] - 1;
  EXPECT_LT(t[minimum], 0.5 * lp.t());
  EXPECT_GT(t[minimum], 0.0);
  for (std::size_t i = 1; i < w.size(); ++i) EXPECT_GT(w[i], w[i - 1]) << "step " << i;
  EXPECT_GT(w.back(), 2 * lp.w());
  // history.csv flags exactly the steps where t turned.
  const auto& flag = r.history.at("limit_point");
  for (std::size_t i = 0; i < t.size(); ++i)
    EXPECT_EQ(flag[i] != 0.0, i == turns[0] || i == turns[1]) << "step " << i;
}

// h = 6.35: snap-through with snap-back. Measured with this mesh: limit load 584.7 N (-0.21 % from Sze's
// 585.9; converged about 584.9 N, -0.17 %), deflection there 13.01 mm (+0.9 %; converged 13.16 mm,
// +2.1 %), load on our path at Sze's deflection -0.23 %. Tolerances: limit load 0.5 % (2.4 times the
// measured difference, which is mostly the converged model-reference difference), deflection 7 % and the
// load at Sze's deflection 1 %, as for the thick roof.
TEST(ShallowRoof, ThinRoofSnapsBackAfterThePublishedLimitLoad) {
  const auto r = run_roof("roof-thin", "6.35");
  ASSERT_TRUE(r.summary.result.completed()) << r.summary.result.message;
  const auto& t = r.history.at("t");
  const auto w = deflection(r);
  EXPECT_DOUBLE_EQ(t.back(), 1.0);

  const LimitPoint lp = check_first_limit_point(t, w, kThin, 0.005);
  ASSERT_GT(lp.step, 0u);

  // Past the first limit point the load falls through zero to a negative minimum (second limit point of
  // t), then rises to t_end. On the way down the deflection reaches a maximum and decreases over several
  // steps (snap-back: a turning point of w, where load control in w would fail too) before it grows again.
  const auto turns = turns_of_t(t);
  ASSERT_EQ(turns.size(), 2u);
  EXPECT_EQ(turns[0], lp.step + 1);
  const std::size_t minimum = turns[1] - 1;
  EXPECT_LT(t[minimum], -0.3 * lp.t());
  std::size_t w_peak = lp.step;
  while (w_peak + 1 < w.size() && w[w_peak + 1] > w[w_peak]) ++w_peak;
  ASSERT_LT(w_peak, minimum) << "the deflection must turn back before the load's minimum";
  EXPECT_LT(t[w_peak], lp.t());
  std::size_t w_valley = w_peak;
  while (w_valley + 1 < w.size() && w[w_valley + 1] < w[w_valley]) ++w_valley;
  EXPECT_GE(w_valley - w_peak, 3u) << "snap-back over at least three steps";
  EXPECT_LT(w[w_valley], w[w_peak] - 1.0);
  EXPECT_GT(w.back(), w[w_peak] + 10.0);
  const auto& flag = r.history.at("limit_point");
  for (std::size_t i = 0; i < t.size(); ++i)
    EXPECT_EQ(flag[i] != 0.0, i == turns[0] || i == turns[1]) << "step " << i;
}

}  // namespace
}  // namespace fibrane::testing
