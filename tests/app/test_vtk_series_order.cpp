// ParaView plays a .pvd series in the order of its timesteps. An arc-length path's t turns back at a limit
// point, so its series are stamped with the path length: read back in timestep order (python3-vtk9,
// read_series_order.py), the data sets are the run's steps in the order it computed them, and the t each
// carries as field data is history.csv's t of that step. The case: the shallow roof example at a coarse
// mesh, whose path passes a maximum and a minimum of t (snap-through).
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <regex>
#include <sstream>
#include <vector>

#include "cli_util.hpp"

namespace fibrane::testing {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// history.csv's t per step (the second column), in row order.
std::vector<double> history_t(const fs::path& csv) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  std::vector<double> t;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    const auto first = line.find(',');
    t.push_back(std::stod(line.substr(first + 1, line.find(',', first + 1) - first - 1)));
  }
  return t;
}

TEST(VtkSeries, ArcLengthSeriesPlaysInPathOrderWithTAsFieldData) {
  if (fibrane_binary().empty()) GTEST_SKIP() << "FIBRANE_BIN not set (run through ctest)";
  if (std::system("/usr/bin/python3 -c 'import vtk' > /dev/null 2>&1") != 0) GTEST_SKIP() << "python3-vtk9 missing";
  const fs::path dir = fs::temp_directory_path() / ("fibrane-series-order-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::string yaml = slurp(fs::path(FIBRANE_SOURCE_DIR) / "examples" / "shallow-roof.yaml");
  yaml = std::regex_replace(yaml, std::regex("elements: \\[8, 8\\]"), "elements: [4, 4]");
  yaml = std::regex_replace(yaml, std::regex("output: .*"), "output: {vtk: true, vtk_cells: bezier}");
  std::ofstream(dir / "case.yaml") << yaml;
  const auto run = run_cli("run '" + (dir / "case.yaml").string() + "' -q -o '" + (dir / "out").string() + "'");
  ASSERT_EQ(run.exit_code, 0) << run.output;

  const std::vector<double> t = history_t(dir / "out" / "history.csv");
  ASSERT_GT(t.size(), 5u);
  bool turns_back = false;  // the path's t is not monotonic: the test would not tell otherwise
  for (std::size_t i = 1; i < t.size(); ++i) turns_back = turns_back || t[i] < t[i - 1];
  ASSERT_TRUE(turns_back) << "the coarse roof should pass a limit point";

  const std::string script = std::string(FIBRANE_SOURCE_DIR) + "/tests/app/read_series_order.py";
  const auto read = run_cli_command("/usr/bin/python3 '" + script + "' '" + (dir / "out" / "roof.pvd").string() + "'");
  ASSERT_EQ(read.exit_code, 0) << read.output;
  std::istringstream lines(read.output);
  std::vector<double> timesteps;
  std::size_t count = 0;
  for (std::string line; std::getline(lines, line); ++count) {
    std::istringstream fields(line);
    std::string timestep, field_t;
    std::size_t step = 0;
    fields >> timestep >> step >> field_t;
    ASSERT_TRUE(fields) << line;
    EXPECT_EQ(step, count) << "in ParaView's order, data set " << count << " is step " << step;
    ASSERT_LT(step, t.size());
    EXPECT_EQ(std::stod(field_t), t[step]) << "field data t of step " << step;
    timesteps.push_back(std::stod(timestep));
  }
  EXPECT_EQ(count, t.size()) << read.output;  // every step written (vtk_every 1)
  for (std::size_t i = 1; i < timesteps.size(); ++i)
    EXPECT_LT(timesteps[i - 1], timesteps[i]) << "timesteps must increase strictly: " << i;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace fibrane::testing
