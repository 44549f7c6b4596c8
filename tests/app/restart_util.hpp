#pragma once
// Helpers of the restart tests (test_restart.cpp, test_checkpoint_integrity.cpp): the coarse peeling case,
// runs in the foreground and in the background, and history.csv read back and compared.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cli_util.hpp"

extern char** environ;

namespace fibrane::testing {

namespace fs = std::filesystem;

inline std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

struct History {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
};

inline History read_history(const fs::path& dir) {
  History h;
  std::ifstream in(dir / "history.csv");
  std::string line;
  std::getline(in, line);
  for (std::stringstream s(line); std::getline(s, line, ',');) h.columns.push_back(line);
  while (std::getline(in, line)) {
    std::vector<double> row;
    for (std::stringstream s(line); std::getline(s, line, ',');) row.push_back(std::stod(line));
    h.rows.push_back(row);
  }
  return h;
}

inline int history_rows(const fs::path& dir) {
  std::ifstream in(dir / "history.csv");
  int n = -1;
  for (std::string line; std::getline(in, line);) ++n;
  return n;
}

// Same columns and rows; entries within 1e-10 of the column's largest magnitude, counts exactly.
inline void expect_same_history(const fs::path& reference, const fs::path& restarted) {
  const History a = read_history(reference), b = read_history(restarted);
  ASSERT_EQ(a.columns, b.columns);
  ASSERT_EQ(a.rows.size(), b.rows.size()) << "rows";
  for (std::size_t j = 0; j < a.columns.size(); ++j) {
    double scale = 0;
    for (const auto& row : a.rows) scale = std::max(scale, std::abs(row[j]));
    const bool count = a.columns[j] == "step" || a.columns[j] == "iterations";
    for (std::size_t i = 0; i < a.rows.size(); ++i) {
      if (count) EXPECT_EQ(a.rows[i][j], b.rows[i][j]) << a.columns[j] << " row " << i;
      else EXPECT_LE(std::abs(a.rows[i][j] - b.rows[i][j]), 1e-10 * scale) << a.columns[j] << " row " << i;
    }
  }
}

// A coarse peeling case (arc length through pull-off, the closest-point coupling, a stop rule, two limit
// points; 4 x 2 shell and 10 beam elements), about fifty steps and a few seconds, with a checkpoint every
// `every` steps.
inline fs::path write_peeling(const fs::path& dir, int every) {
  std::ifstream in(std::string(FIBRANE_SOURCE_DIR) + "/examples/peeling.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  auto replace = [&](const std::string& from, const std::string& to) {
    const auto at = yaml.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    yaml.replace(at, from.size(), to);
  };
  replace("elements: [20, 10]", "elements: [4, 2]");
  replace("elements: 100", "elements: 10");
  replace("ds: 0.02, ds_max: 0.5", "ds: 0.02, ds_max: 0.4");
  replace("output: {directory: out/peeling, vtk_every: 5}",
          "output: {directory: out, vtk_every: 5, checkpoint_every: " + std::to_string(every) + "}");
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "case.yaml") << yaml;
  return dir / "case.yaml";
}

inline CliResult run_case(const fs::path& case_file, const std::string& options) {
  return run_cli("run '" + case_file.string() + "' -q --threads 1 " + options);
}

// The uninterrupted run of the coarse peeling case, computed once per test process and removed at its end.
inline const fs::path& reference_run() {
  struct Reference {
    fs::path dir = fs::temp_directory_path() / ("fibrane-restart-reference-" + std::to_string(::getpid()));
    fs::path out = dir / "out";
    Reference() {
      const auto r = run_case(write_peeling(dir, 4), "-o '" + out.string() + "'");
      EXPECT_EQ(r.exit_code, 0) << r.output;
    }
    ~Reference() { fs::remove_all(dir); }
  };
  static const Reference reference;
  return reference.out;
}

// Waits until the run has written `rows` history rows (and, with `checkpoint`, a checkpoint), or ended.
inline void wait_for_rows(pid_t pid, const fs::path& out, int rows, bool checkpoint) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < deadline) {
    if (history_rows(out) >= rows && (!checkpoint || fs::exists(out / "checkpoint.bin"))) return;
    int status = 0;
    if (waitpid(pid, &status, WNOHANG) == pid) FAIL() << "the run ended before it was signalled";
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  FAIL() << "the run did not reach " << rows << " rows";
}

}  // namespace fibrane::testing
