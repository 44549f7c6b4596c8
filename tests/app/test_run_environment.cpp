// What a run meets outside its case file: an output directory that cannot be created is bad input (exit 2,
// naming the option, the path and the system's reason, nothing written); a write that fails mid-run names
// the system's reason; and two runs with the same number of threads give bit-identical histories (the
// assembly's sums do not depend on which thread finishes first), a restarted one included.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

#include "cli_util.hpp"

namespace fibrane::testing {
namespace {

namespace fs = std::filesystem;

// A fiber pressed onto a plate by a line load against a repulsive law: shell, beam and interaction
// elements, enough of each that two threads share every loop.
const char* const kPressedFiber = R"(
shells:
  - name: plate
    geometry: {rectangle: {origin: [-1, -1, 0], edge_u: [2, 0, 0], edge_v: [0, 2, 0]}}
    refine: {degree: 2, continuity: 1, elements: [8, 8]}
    thickness: 0.2
    material: {young: 1000, poisson: 0.3}
beams:
  - name: fiber
    geometry: {line: {from: [-0.9, 0, 0.45], to: [0.9, 0, 0.45]}}
    refine: {degree: 3, continuity: 2, elements: 24}
    material: {young: 100, poisson: 0.3}
    section: {circle: {radius: 0.2}}
interactions:
  - {name: contact, beam: fiber, shell: plate, law: {model: inverse_power, exponent: 9, coefficient: 1.0e-4}}
constraints:
  - {body: plate, at: [{edge: u0}, {edge: u1}], fix: [x, y, z]}
  - {body: fiber, at: [{end: start}, {end: end}], fix: [x, y, z]}
  - {body: fiber, at: {end: start}, fix: [twist]}
loads:
  - {body: fiber, type: line_load, force: [0, 0, -0.05]}
steps: {dt: 0.25, dt_max: 0.25}
output: {vtk: false}
)";

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("fibrane-env-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(RunEnvironment, OutputDirectoryThatCannotBeCreatedIsBadInput) {
  if (fibrane_binary().empty()) GTEST_SKIP() << "FIBRANE_BIN not set (run through ctest)";
  const fs::path target = "/proc/fibrane-output";
  if (!fs::is_directory("/proc") || ::mkdir(target.c_str(), 0755) == 0) GTEST_SKIP() << "no procfs here";
  const fs::path dir = fresh_dir("proc");
  std::ofstream(dir / "case.yaml") << kPressedFiber;
  const auto r = run_cli("run '" + (dir / "case.yaml").string() + "' -q -o " + target.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find((dir / "case.yaml").string() + ": -o '/proc/fibrane-output': cannot create the "
                          "directory '/proc/fibrane-output': "),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("filesystem error"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(target));
  fs::remove_all(dir);
}

// The file size limit (ulimit -f, SIGXFSZ ignored) makes a write fail with EFBIG, as a full disk does with
// ENOSPC: the message names the file and the system's reason.
TEST(RunEnvironment, FailedWriteNamesTheSystemsReason) {
  if (fibrane_binary().empty()) GTEST_SKIP() << "FIBRANE_BIN not set (run through ctest)";
  const fs::path dir = fresh_dir("write-error");
  std::string text = kPressedFiber;
  text.replace(text.find("output: {vtk: false}"), 20, "output: {vtk: true}");
  std::ofstream(dir / "case.yaml") << text;
  const auto r = run_cli_command("bash -c \"trap '' XFSZ; ulimit -f 4; '" + fibrane_binary() + "' run '" +
                                 (dir / "case.yaml").string() + "' -q --threads 1 -o '" + (dir / "out").string() +
                                 "'\"");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("write failed: File too large"), std::string::npos) << r.output;
  fs::remove_all(dir);
}

TEST(RunEnvironment, TwoRunsWithTwoThreadsAreBitIdentical) {
  if (fibrane_binary().empty()) GTEST_SKIP() << "FIBRANE_BIN not set (run through ctest)";
  const fs::path dir = fresh_dir("threads");
  std::ofstream(dir / "case.yaml") << kPressedFiber;
  std::string first;
  for (int k = 0; k < 3; ++k) {
    const fs::path out = dir / ("out" + std::to_string(k));
    const auto r = run_cli("run '" + (dir / "case.yaml").string() + "' -q --threads 2 -o '" + out.string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const std::string history = slurp(out / "history.csv");
    if (k == 0) first = history;
    else EXPECT_EQ(history, first) << "run " << k << " differs from run 0";
  }
  EXPECT_GT(std::count(first.begin(), first.end(), '\n'), 3);  // the initial state and 4 steps
  fs::remove_all(dir);
}

// The restart promise holds bit for bit with several threads: a run stopped after 2 steps and restarted,
// both with --threads 2, writes the uninterrupted 2-thread run's history.
TEST(RunEnvironment, RestartWithTwoThreadsIsBitIdentical) {
  if (fibrane_binary().empty()) GTEST_SKIP() << "FIBRANE_BIN not set (run through ctest)";
  const fs::path dir = fresh_dir("restart-threads");
  std::string case_file = "'";  // appended piece by piece: GCC 12 warns (-Wrestrict) on "'" + std::string
  case_file += (dir / "case.yaml").string();
  case_file += "'";
  std::ofstream(dir / "case.yaml") << kPressedFiber;
  ASSERT_EQ(run_cli("run " + case_file + " -q --threads 2 -o '" + (dir / "whole").string() + "'").exit_code, 0);
  const auto part = run_cli("run " + case_file + " -q --threads 2 --max-steps 2 -o '" + (dir / "part").string() + "'");
  ASSERT_EQ(part.exit_code, 1) << part.output;
  const auto rest = run_cli("run " + case_file + " -q --threads 2 --restart '" + (dir / "part").string() + "'");
  ASSERT_EQ(rest.exit_code, 0) << rest.output;
  EXPECT_EQ(slurp(dir / "part" / "history.csv"), slurp(dir / "whole" / "history.csv"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace fibrane::testing
