// Interaction outputs say what they are: beam quadrature points whose closest point lies off the shell patch
// are counted in history.csv (<name>_lost_points), in summary.json (largest count, its step, the final
// energy and force) and in a warning on stderr, and the interaction CSV marks them (status) without
// distance values. The case: a fiber 4 long over a plate 2 long, pressed onto it by a line load against a
// repulsive law; the half of the fiber beyond the plate's edges has no closest point on it.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <sstream>
#include <vector>

#include "cli_util.hpp"
#include "temp_directory.hpp"

namespace fibrane::testing {
namespace {

const char* const kOverhangingFiber = R"(
shells:
  - name: plate
    geometry: {rectangle: {origin: [-1, -2, 0], edge_u: [2, 0, 0], edge_v: [0, 4, 0]}}
    refine: {degree: 2, continuity: 1, elements: [4, 4]}
    thickness: 0.2
    material: {young: 1000, poisson: 0.3}
beams:
  - name: fiber
    geometry: {line: {from: [-2, 0, 0.45], to: [2, 0, 0.45]}}
    refine: {degree: 3, continuity: 2, elements: 8}
    material: {young: 100, poisson: 0.3}
    section: {circle: {radius: 0.2}}
interactions:
  - {name: contact, beam: fiber, shell: plate, law: {model: inverse_power, exponent: 9, coefficient: 1.0e-4}}
constraints:
  - {body: plate, at: {all: true}, fix: [x, y, z]}
  - {body: fiber, at: [{end: start}, {end: end}], fix: [x, y, z]}
  - {body: fiber, at: {end: start}, fix: [twist]}
loads:
  - {body: fiber, type: line_load, force: [0, 0, -0.05]}
steps: {dt: 0.5, dt_max: 0.5}
output: {vtk: false}
)";

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream s(line);
  for (std::string field; std::getline(s, field, ',');) out.push_back(field);
  return out;
}

// The column `name` of a CSV file, as text per data row.
std::vector<std::string> column(const std::filesystem::path& csv, const std::string& name) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  const auto header = split(line);
  const auto at = std::find(header.begin(), header.end(), name) - header.begin();
  std::vector<std::string> out;
  while (std::getline(in, line))
    if (!line.empty()) out.push_back(split(line).at(at));
  return out;
}

// The number after "key": in summary.json (the first occurrence).
std::string json_value(const std::string& json, const std::string& key) {
  std::smatch m;
  if (!std::regex_search(json, m, std::regex("\"" + key + "\": ([^,\\n\\]]+)"))) return "";
  return m[1];
}

TEST(InteractionOutputs, PointsBeyondThePatchAreCountedMarkedAndReported) {
  if (fibrane_binary().empty()) GTEST_SKIP() << "FIBRANE_BIN not set (run through ctest)";
  const auto dir = fresh_directory("lost-points");
  std::ofstream(dir / "case.yaml") << kOverhangingFiber;
  const auto run = run_cli("run '" + (dir / "case.yaml").string() + "' -q --threads 1 -o '" + (dir / "out").string() + "'");
  ASSERT_EQ(run.exit_code, 0) << run.output;

  // 8 elements x 4 Gauss points; the 4 elements with |x| > 1 lie beyond the plate: 16 lost points.
  const std::string summary = slurp(dir / "out" / "summary.json");
  EXPECT_EQ(json_value(summary, "quadrature_points"), "32") << summary;
  const auto lost = column(dir / "out" / "history.csv", "contact_lost_points");
  ASSERT_EQ(lost.size(), 3u);  // the initial state and two steps
  for (const auto& n : lost) EXPECT_EQ(n, "16");
  EXPECT_EQ(json_value(summary, "max_lost_points"), "16");
  EXPECT_EQ(json_value(summary, "max_lost_points_step"), "0");
  EXPECT_EQ(json_value(summary, "final_lost_points"), "16");

  // The summary's final energy is the history's last value, digit for digit (both shortest round-trip).
  const auto energy = column(dir / "out" / "history.csv", "contact_energy");
  EXPECT_EQ(json_value(summary, "final_energy"), energy.back());
  EXPECT_GT(std::stod(energy.back()), 0.0);  // the repulsion carries the load
  std::smatch force;
  ASSERT_TRUE(std::regex_search(summary, force, std::regex("\"final_force\": \\[([^\\]]*)\\]"))) << summary;
  const auto components = split(std::regex_replace(force[1].str(), std::regex(" "), ""));
  ASSERT_EQ(components.size(), 3u);
  EXPECT_EQ(components[2], column(dir / "out" / "history.csv", "contact_force_z").back());

  // One warning, naming the interaction and the column.
  const auto first = run.output.find("warning:");
  ASSERT_NE(first, std::string::npos) << run.output;
  EXPECT_EQ(run.output.find("warning:", first + 1), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("contact_lost_points"), std::string::npos) << run.output;

  // The last step's CSV: the points beyond the edges are "outside" with nan distance, the others interior.
  const auto csv = dir / "out" / "interaction" / "contact_000002.csv";
  const auto status = column(csv, "status"), distance = column(csv, "distance"), xi = column(csv, "xi");
  ASSERT_EQ(status.size(), 32u);
  int outside = 0;
  for (std::size_t i = 0; i < status.size(); ++i) {
    const bool beyond = std::abs(4.0 * std::stod(xi[i]) - 2.0) > 1.0;  // x = -2 + 4 xi
    EXPECT_EQ(status[i], beyond ? "outside" : "interior") << "xi = " << xi[i];
    if (beyond) {
      ++outside;
      EXPECT_EQ(distance[i], "nan");
    } else {
      EXPECT_GT(std::stod(distance[i]), 0.0);
    }
  }
  EXPECT_EQ(outside, 16);
}

}  // namespace
}  // namespace fibrane::testing
