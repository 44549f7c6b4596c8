// Command-line options of `fibrane run` that override the case: --max-steps bounds every continuation
// method (load stepping, arc length, dynamics) alike, and is at least 1.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <sstream>

#include "cli_util.hpp"
#include "temp_directory.hpp"

namespace fibrane::testing {
namespace {

int data_rows(const std::filesystem::path& history) {
  std::ifstream in(history);
  int rows = -1;  // the header
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) ++rows;
  return rows;
}

// Runs the shallow roof example (8 x 8 quarter) with the given method replacing its steps block.
CliResult run_roof(const std::string& steps_block, const std::filesystem::path& out, int max_steps) {
  std::ifstream in(std::string(FIBRANE_SOURCE_DIR) + "/examples/shallow-roof.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml = std::regex_replace(text.str(), std::regex("steps:[^]*"), steps_block);
  yaml = std::regex_replace(yaml, std::regex("poisson: 0.3\\}"), "poisson: 0.3, density: 1.0e-6}");  // for dynamics
  std::filesystem::remove_all(out);
  std::filesystem::create_directories(out);
  const auto case_file = out / "case.yaml";
  std::ofstream(case_file) << yaml << "output: {directory: out, vtk: false}\n";
  return run_cli("run '" + case_file.string() + "' -q --threads 1 --max-steps " + std::to_string(max_steps) +
                 " -o '" + (out / "out").string() + "'");
}

struct MethodCase {
  const char* name;
  const char* steps;
};

class MaxSteps : public ::testing::TestWithParam<MethodCase> {};

void PrintTo(const MethodCase& c, std::ostream* os) { *os << c.name; }

// The run stops (exit 1, "max_steps") after exactly the given number of steps: history.csv has the initial
// row and one row per step.
TEST_P(MaxSteps, BoundsTheRunOfEveryMethod) {
  if (fibrane_binary().empty()) GTEST_SKIP() << "FIBRANE_BIN not set (run through ctest)";
  const auto out = fresh_directory(std::string("max-steps-") + GetParam().name);
  const auto run = run_roof(GetParam().steps, out, 3);
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find("max_steps = 3"), std::string::npos) << run.output;
  EXPECT_EQ(data_rows(out / "out" / "history.csv"), 4);
}

INSTANTIATE_TEST_SUITE_P(
    Methods, MaxSteps,
    ::testing::Values(MethodCase{"load_stepping", "steps: {t_end: 1.0, dt: 0.01}\n"},
                      MethodCase{"arc_length", "steps: {method: arc_length, t_end: 1.0, arc_length: {ds: 0.5}}\n"},
                      MethodCase{"dynamics", "steps: {method: dynamics, t_end: 1.0, dt: 0.01}\n"}),
    [](const auto& info) { return std::string(info.param.name); });

// --max-steps 0 is a usage error (exit 2) that states the range readably, and nothing is written.
TEST(MaxStepsOption, ZeroIsRefusedWithItsRange) {
  if (fibrane_binary().empty()) GTEST_SKIP() << "FIBRANE_BIN not set (run through ctest)";
  const auto out = fresh_directory("max-steps-zero");
  const auto run = run_roof("steps: {t_end: 1.0, dt: 0.01}\n", out, 0);
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("--max-steps: Value 0 not in range 1 to 100000000"), std::string::npos) << run.output;
  EXPECT_LT(run.output.size(), 200u) << run.output;
  EXPECT_FALSE(std::filesystem::exists(out / "out"));
}

}  // namespace
}  // namespace fibrane::testing
