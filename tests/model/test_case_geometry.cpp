// Geometry keys of a case file: graded refinement (geometric ratio or explicit knots per direction), arcs
// up to 360 degrees without C0 knots, and C0 knot lines that a shell keeps only with allow_kinks.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>

#include "case_runner.hpp"
#include "common/error.hpp"

namespace fibrane::testing {
namespace {

casefile::Case read_yaml(const std::string& name, const std::string& yaml) {
  const auto dir = fresh_directory(name);
  std::ofstream(dir / "case.yaml") << yaml;
  return casefile::read_case((dir / "case.yaml").string());
}

std::string shell_case(const std::string& geometry, const std::string& refine, const std::string& extra = "") {
  return "shells:\n  - name: roof\n    geometry: " + geometry + "\n    refine: " + refine +
         "\n    thickness: 0.1\n    material: {young: 1000, poisson: 0.3}\n" + extra +
         "constraints:\n  - {body: roof, at: {edge: v0}, fix: [x, y, z]}\nsteps: {dt: 0.5}\n";
}

// The distinct interior knots of a direction.
std::vector<double> interior(const spline::KnotVector& kv) {
  std::vector<double> out;
  for (double u : kv.unique_knots())
    if (u > kv.front() && u < kv.back()) out.push_back(u);
  return out;
}

// grading: {u: {ratio: r}} gives the knots (r^k - 1) / (r^n - 1) along u (to 1e-14), explicit knots are
// taken as they are, and the other direction stays uniform.
TEST(CaseGeometry, GradedRefinementPlacesTheKnots) {
  const auto c = read_yaml("graded-shell",
                           shell_case("{rectangle: {origin: [0, 0, 0], edge_u: [3, 0, 0], edge_v: [0, 1, 0]}}",
                                      "{degree: 3, elements: [6, 4], grading: {u: {ratio: 1.3}, v: {knots: [0.5, "
                                      "0.75, 0.875]}}}"));
  const auto& s = c.model->shells.at(0).surface;
  const auto u = interior(s.knots(0)), v = interior(s.knots(1));
  ASSERT_EQ(u.size(), 5u);
  for (int k = 1; k <= 5; ++k) EXPECT_NEAR(u[k - 1], (std::pow(1.3, k) - 1) / (std::pow(1.3, 6) - 1), 1e-14);
  for (double x : u) EXPECT_EQ(s.knots(0).multiplicity(x), 1);  // C2 cubic: simple knots
  EXPECT_EQ(v, (std::vector<double>{0.5, 0.75, 0.875}));

  const auto beam = read_yaml("graded-beam", R"(
beams:
  - name: rod
    geometry: {line: {from: [0, 0, 0], to: [10, 0, 0]}}
    refine: {degree: 2, elements: 5, grading: {ratio: 0.5}}
    material: {young: 1.0e6, poisson: 0.0}
    section: {circle: {radius: 0.1}}
constraints:
  - {body: rod, at: {end: start}, fix: [x, y, z, twist]}
steps: {dt: 0.5}
)");
  const auto xi = interior(beam.model->beams.at(0).curve.knots());
  ASSERT_EQ(xi.size(), 4u);
  for (int k = 1; k <= 4; ++k) EXPECT_NEAR(xi[k - 1], (std::pow(0.5, k) - 1) / (std::pow(0.5, 5) - 1), 1e-14);
}

// A half cylinder and a 270-degree arc beam are accepted (C1 everywhere); a full cylinder's C0 knot lines
// are refused, unless the shell says allow_kinks: true.
TEST(CaseGeometry, ArcsBelowAFullTurnAreAcceptedC0LinesOnlyWithAllowKinks) {
  const auto half = read_yaml("half-cylinder", shell_case("{cylinder: {radius: 2, length: 3, angles: [0, 180]}}",
                                                          "{degree: 2, elements: [4, 2]}"));
  const auto& s = half.model->shells.at(0).surface;
  for (double u : interior(s.knots(0))) EXPECT_EQ(s.knots(0).multiplicity(u), 1);
  for (int k = 0; k <= 20; ++k) {
    const Eigen::Vector3d x = s.point(k / 20.0, 0.5);
    EXPECT_NEAR(std::hypot(x.y(), x.z()), 2.0, 1e-12 * 2.0);
  }
  const auto beam = read_yaml("arc-270", R"(
beams:
  - name: hoop
    geometry: {arc: {center: [0, 0, 0], e1: [1, 0, 0], e2: [0, 1, 0], radius: 5, angles: [0, 270]}}
    refine: {degree: 3, elements: 6}
    material: {young: 1.0e6, poisson: 0.0}
    section: {circle: {radius: 0.1}}
constraints:
  - {body: hoop, at: {end: start}, fix: [x, y, z, twist]}
steps: {dt: 0.5}
)");
  EXPECT_EQ(beam.model->beams.at(0).elements.size(), 6u);

  const std::string full = shell_case("{cylinder: {radius: 2, length: 3, angles: [0, 360]}}", "{degree: 2, elements: [4, 2]}");
  try {
    read_yaml("full-cylinder", full);
    ADD_FAILURE() << "a full cylinder's C0 knot lines were accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("case.yaml:3: shells[0].geometry: shell 'roof': the surface is only C0 at the interior knot line "
                     "u = 0.25"),
              std::string::npos)
        << m;
    EXPECT_NE(m.find("allow_kinks: true"), std::string::npos) << m;
  }
  const auto kept = read_yaml("full-cylinder-kinks",
                              shell_case("{cylinder: {radius: 2, length: 3, angles: [0, 360]}}",
                                         "{degree: 2, elements: [4, 2]}", "    allow_kinks: true\n"));
  EXPECT_EQ(kept.model->shells.at(0).surface.knots(0).multiplicity(0.5), 2);
}

// The pinched cylinder (octant, degree 4, 8 x 8 elements) graded toward the load (ratio 0.85 in u and v):
// the displacement under the load is within 1 % of the reference 1.8248e-5, and 3 times closer to it than
// on the uniform 8 x 8 mesh (measured: 0.59 % against 2.6 %).
TEST(CaseGeometry, GradedPinchedCylinderIsCloserToTheReference) {
  const double reference = 1.8248e-5;
  auto error = [&](const std::string& name, const std::string& refine) {
    const auto r = run_yaml(name, example_text("pinched-cylinder.yaml", {{"elements: [16, 16]}", refine}}));
    return std::abs(std::abs(r.history.at("w_load").back()) / reference - 1.0);
  };
  const double uniform = error("pinched-uniform", "elements: [8, 8]}");
  const double graded = error("pinched-graded", "elements: [8, 8], grading: {u: {ratio: 0.85}, v: {ratio: 0.85}}}");
  EXPECT_LT(graded, 0.01);
  EXPECT_LT(3.0 * graded, uniform) << "graded " << graded << ", uniform " << uniform;
}

}  // namespace
}  // namespace fibrane::testing
