// The shallow hinged cylindrical roof under a central point load (examples/shallow-roof.yaml, its mesh and
// arc lengths): arc-length continuation through the snap-through of the 12.7 mm roof and the snap-back of
// the 6.35 mm roof, against the whole published path of Sze, Liu & Lo (2004), Table 9
// (tests/model/data/sze2004_roof_table9.csv; docs/verification.md, "Shell snap-through (shallow roof)",
// has the mesh study).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "case_runner.hpp"

namespace fibrane::testing {
namespace {

constexpr double kPMax = 3000.0;  // N: the whole roof's load at t = 1 (the example applies a quarter)

// A load-deflection path: P (N, whole roof) and the downward central deflection -W (mm).
struct Path {
  std::vector<double> load, deflection;
};

// Sze et al.'s rows for one thickness.
Path published_path(const std::string& thickness) {
  std::ifstream in(std::filesystem::path(FIBRANE_SOURCE_DIR) / "tests/model/data/sze2004_roof_table9.csv");
  Path p;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || line.rfind("thickness", 0) == 0) continue;
    const auto c1 = line.find(','), c2 = line.find(',', c1 + 1);
    if (line.substr(0, c1) != thickness) continue;
    p.load.push_back(kPMax * std::stod(line.substr(c1 + 1, c2 - c1 - 1)));
    p.deflection.push_back(std::stod(line.substr(c2 + 1)));
  }
  return p;
}

Path computed_path(const CaseRun& r) {
  Path p;
  for (double t : r.history.at("t")) p.load.push_back(kPMax * t);
  for (double v : r.history.at("w_centre")) p.deflection.push_back(-v);
  return p;
}

// The first limit point of a path: the vertex of the parabola P(w) through the point of the first maximum
// of P and its two neighbours. Both paths are sampled (Sze's rows are not located extrema either), so both
// are read the same way; other fits through Sze's rows (cubics through four or five rows) move his vertex
// by < 0.5 N and < 0.02 mm.
struct LimitPoint {
  std::size_t index = 0;  // the point with the largest load; 0 if the load has no interior maximum
  double load = 0, deflection = 0;
};

LimitPoint first_limit_point(const Path& p) {
  LimitPoint lp;
  const auto& y = p.load;
  const auto& x = p.deflection;
  for (std::size_t i = 1; i + 1 < y.size() && lp.index == 0; ++i)
    if (y[i] >= y[i - 1] && y[i] > y[i + 1]) lp.index = i;
  if (lp.index == 0) return lp;
  const std::size_t i = lp.index;
  const double d01 = (y[i] - y[i - 1]) / (x[i] - x[i - 1]), d12 = (y[i + 1] - y[i]) / (x[i + 1] - x[i]);
  const double a = (d12 - d01) / (x[i + 1] - x[i - 1]);  // P = a w^2 + b w + c
  const double b = d01 - a * (x[i - 1] + x[i]);
  const double c = y[i - 1] - (a * x[i - 1] + b) * x[i - 1];
  lp.deflection = -b / (2 * a);
  lp.load = (a * lp.deflection + b) * lp.deflection + c;
  return lp;
}

// The largest distance of a published row from the computed path (a polyline), in the plane of P / 3000 N
// and w / 30 mm (the paths' ranges), over the rows up to the computed path's end load.
double largest_distance(const Path& published, const Path& computed) {
  constexpr double kW = 30.0;
  double largest = 0;
  for (std::size_t k = 0; k < published.load.size(); ++k) {
    if (published.load[k] > computed.load.back()) continue;
    const Eigen::Vector2d q(published.deflection[k] / kW, published.load[k] / kPMax);
    double nearest = INFINITY;
    for (std::size_t i = 0; i + 1 < computed.load.size(); ++i) {
      const Eigen::Vector2d a(computed.deflection[i] / kW, computed.load[i] / kPMax);
      const Eigen::Vector2d b(computed.deflection[i + 1] / kW, computed.load[i + 1] / kPMax);
      const double s = std::clamp((q - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
      nearest = std::min(nearest, (a + s * (b - a) - q).norm());
    }
    largest = std::max(largest, nearest);
  }
  return largest;
}

// Indices of the steps where t turned (dt changed sign against the previous step).
std::vector<std::size_t> turns_of_t(const std::vector<double>& t) {
  std::vector<std::size_t> turns;
  for (std::size_t i = 2; i < t.size(); ++i)
    if ((t[i] - t[i - 1]) * (t[i - 1] - t[i - 2]) < 0) turns.push_back(i);
  return turns;
}

// The computed path against the published one: the first limit point (load within load_tolerance,
// deflection within 2 %, relative) and every published row near the path. Returns our limit point.
LimitPoint check_against_sze(const CaseRun& r, const std::string& thickness, double load_tolerance,
                             double distance_tolerance) {
  const Path ours = computed_path(r), sze = published_path(thickness);
  EXPECT_EQ(sze.load.size(), 37u) << "the reference table";
  const LimitPoint lp = first_limit_point(ours), ref = first_limit_point(sze);
  EXPECT_GT(lp.index, 0u) << "no maximum of t along the path";
  EXPECT_GT(ref.index, 0u);
  EXPECT_NEAR(lp.load, ref.load, load_tolerance * ref.load);
  EXPECT_NEAR(lp.deflection, ref.deflection, 0.02 * ref.deflection);
  EXPECT_LT(largest_distance(sze, ours), distance_tolerance);
  return lp;
}

CaseRun run_roof(const std::string& name, const std::string& thickness) {
  return run_yaml(name, example_text("shallow-roof.yaml", {{"thickness: 12.7", "thickness: " + thickness}}), 1);
}

// h = 12.7: snap-through. Sze's path has its vertex at 2231.2 N, 10.876 mm. Measured: 2225.6 N (-0.25 %),
// 10.714 mm (-1.5 %; meshes from 4 x 4 to 32 x 32 quartic give 10.70-10.72, so this is the model's
// difference from Sze's, not the mesh's); the rows lie within 0.0055 of our path (largest on the
// stiffening branch past the snap, where dP/dw is steep). Tolerances: load 1 % (four times the
// measured), deflection 2 % (the criterion for this benchmark; a flat maximum, dP/dw = 0, so its location
// is the ill-conditioned part), distance 0.015 (1.6 times the larger of the two roofs' measured values).
// The test fails for E 2 % too high (limit load +1.7 % off Sze's) and for nu = 0.25 (-2.2 %, distance 0.018).
TEST(ShallowRoof, ThickRoofFollowsThePublishedSnapThrough) {
  const auto r = run_roof("roof-thick", "12.7");
  ASSERT_TRUE(r.summary.result.completed()) << r.summary.result.message;
  const auto& t = r.history.at("t");
  const auto w = computed_path(r).deflection;
  EXPECT_DOUBLE_EQ(t.back(), 1.0);
  const LimitPoint lp = check_against_sze(r, "12.7", 0.01, 0.015);
  ASSERT_GT(lp.index, 0u);

  // The path goes on through the snap-through: t falls to a minimum (second limit point, still a
  // positive load for this thickness), then rises again to t_end = 1, which lies far above the limit
  // load, while the deflection grows monotonically (no snap-back at h = 12.7).
  const auto turns = turns_of_t(t);
  ASSERT_EQ(turns.size(), 2u);
  EXPECT_EQ(turns[0], lp.index + 1);
  const std::size_t minimum = turns[1] - 1;
  EXPECT_LT(t[minimum], 0.5 * lp.load / kPMax);
  EXPECT_GT(t[minimum], 0.0);
  for (std::size_t i = 1; i < w.size(); ++i) EXPECT_GT(w[i], w[i - 1]) << "step " << i;
  EXPECT_GT(w.back(), 2 * lp.deflection);
  // history.csv flags exactly the steps where t turned.
  const auto& flag = r.history.at("limit_point");
  for (std::size_t i = 0; i < t.size(); ++i)
    EXPECT_EQ(flag[i] != 0.0, i == turns[0] || i == turns[1]) << "step " << i;
}

// h = 6.35: snap-through with snap-back. Sze's vertex: 586.8 N, 13.247 mm. Measured: 584.7 N (-0.36 %),
// 13.124 mm (-0.9 %); the rows, through the snap-back and the negative loads, lie within 0.0091 of our
// path. Tolerances as for the thick roof.
TEST(ShallowRoof, ThinRoofFollowsThePublishedSnapBack) {
  const auto r = run_roof("roof-thin", "6.35");
  ASSERT_TRUE(r.summary.result.completed()) << r.summary.result.message;
  const auto& t = r.history.at("t");
  const auto w = computed_path(r).deflection;
  EXPECT_DOUBLE_EQ(t.back(), 1.0);
  const LimitPoint lp = check_against_sze(r, "6.35", 0.01, 0.015);
  ASSERT_GT(lp.index, 0u);

  // Past the first limit point the load falls through zero to a negative minimum (second limit point of
  // t), then rises to t_end. On the way down the deflection reaches a maximum and decreases over several
  // steps (snap-back: a turning point of w, where load control in w would fail too) before it grows again.
  const auto turns = turns_of_t(t);
  ASSERT_EQ(turns.size(), 2u);
  EXPECT_EQ(turns[0], lp.index + 1);
  const std::size_t minimum = turns[1] - 1;
  EXPECT_LT(t[minimum], -0.3 * lp.load / kPMax);
  std::size_t w_peak = lp.index;
  while (w_peak + 1 < w.size() && w[w_peak + 1] > w[w_peak]) ++w_peak;
  ASSERT_LT(w_peak, minimum) << "the deflection must turn back before the load's minimum";
  EXPECT_LT(t[w_peak], lp.load / kPMax);
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
