// A real VTK reader (python3-vtk9) opens every file of a run's time series, and history.csv and
// summary.json are written: the roll-up strip example, run through the command line.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include <sys/resource.h>

#include "cli_util.hpp"
#include "temp_directory.hpp"

namespace fibrane::testing {
namespace {

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(Outputs, RollUpExampleWritesHistorySummaryAndVtkThatVtkReads) {
  if (fibrane_binary().empty()) GTEST_SKIP() << "FIBRANE_BIN not set (run through ctest)";
  if (std::system("/usr/bin/python3 -c 'import vtk' > /dev/null 2>&1") != 0) GTEST_SKIP() << "python3-vtk9 missing";
  const auto out = fresh_directory("vtk-rollup") / "out";
  const std::string example = std::string(FIBRANE_SOURCE_DIR) + "/examples/rollup-strip.yaml";
  const auto run = run_cli("run '" + example + "' -q -o '" + out.string() + "'");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string history = slurp(out / "history.csv");
  EXPECT_EQ(history.rfind("step,t,load_factor,iterations,residual,negative_eigenvalues,limit_point,strain_energy,tip_x,tip_z", 0), 0u) << history;
  const std::string summary = slurp(out / "summary.json");
  EXPECT_NE(summary.find("\"completed\": true"), std::string::npos);
  // The memory section: the case's estimate on its solver path, and the run's peak resident memory, which
  // getrusage bounds: RUSAGE_CHILDREN holds the largest peak of the processes this test waited for, the
  // run's among them.
  const auto number = [&](const std::string& key) {
    const auto at = summary.find("\"" + key + "\": ");
    return at == std::string::npos ? -1.0 : std::stod(summary.substr(at + key.size() + 4));
  };
  rusage children{};
  getrusage(RUSAGE_CHILDREN, &children);
  EXPECT_GT(number("peak_bytes"), 1e6);
  EXPECT_LE(number("peak_bytes"), 1024.0 * children.ru_maxrss);
  // The allocator's sampled peak: more than 1 MB (the model and its tangent), and below the resident peak,
  // which also holds the program's code and libraries.
  EXPECT_GT(number("peak_allocated_bytes"), 1e6);
  EXPECT_LT(number("peak_allocated_bytes"), number("peak_bytes"));
  EXPECT_GT(number("estimated_bytes"), 1e6);
  EXPECT_NE(summary.find("\"solver_path\": \"a symmetric factorisation\""), std::string::npos) << summary;
  const std::string script = std::string(FIBRANE_SOURCE_DIR) + "/tests/app/read_vtk.py";
  const auto read = run_cli_command("/usr/bin/python3 '" + script + "' '" + out.string() + "'");
  ASSERT_EQ(read.exit_code, 0) << read.output;
  // One dataset per written step (21: the initial state and 20 steps) in each of the two series: the exact
  // Bezier cells with the displacement, and the sampled cells with the section forces.
  std::istringstream lines(read.output);
  int bezier = 0, sampled = 0;
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("strip.pvd ", 0) == 0) {
      ++bezier;
      EXPECT_NE(line.find("displacement"), std::string::npos) << line;
      EXPECT_NE(line.find("RationalWeights"), std::string::npos) << line;
    } else {
      ++sampled;
      EXPECT_EQ(line.rfind("strip_sampled.pvd ", 0), 0u) << line;
      EXPECT_NE(line.find("displacement N_local M_local"), std::string::npos) << line;
    }
  }
  EXPECT_EQ(bezier, 21) << read.output;
  EXPECT_EQ(sampled, 21) << read.output;

  // A shorter run into the same directory leaves none of the first run's steps behind (and keeps files
  // that are not a run's step files).
  std::ofstream(out / "vtk" / "notes.txt") << "mine";
  const auto shorter = out.parent_path() / "short.yaml";
  std::string text = slurp(example);
  const std::string from = "t_end: 1.0";
  ASSERT_NE(text.find(from), std::string::npos);
  std::ofstream(shorter) << text.replace(text.find(from), from.size(), "t_end: 0.25");
  const auto rerun = run_cli("run '" + shorter.string() + "' -q --newton-log -o '" + out.string() + "'");
  ASSERT_EQ(rerun.exit_code, 0) << rerun.output;
  // --newton-log: a line per Newton iteration, from the first iteration of the first step, and one per new
  // tangent naming the solver that took it and its inertia (the strip's tangent is positive definite).
  EXPECT_NE(rerun.output.find("newton t=0.05 it=0 |r|="), std::string::npos) << rerun.output;
  EXPECT_NE(rerun.output.find("newton t=0.05 it=0 new tangent for auto(cholmod), 0 negative eigenvalues;"),
            std::string::npos)
      << rerun.output;
  int vtu = 0;
  for (const auto& f : std::filesystem::directory_iterator(out / "vtk")) vtu += f.path().extension() == ".vtu";
  EXPECT_EQ(vtu, 12);  // the initial state and 5 steps of 0.05, Bezier and sampled
  EXPECT_TRUE(std::filesystem::exists(out / "vtk" / "notes.txt"));
}

}  // namespace
}  // namespace fibrane::testing
