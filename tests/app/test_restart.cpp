// Runs that survive: a run stopped by its step budget, killed with SIGKILL, or interrupted with SIGTERM
// or SIGINT continues with `fibrane run CASE --restart OUTDIR` from its last checkpoint, and its
// history.csv equals the uninterrupted run's to 1e-10 (per column, relative to the column's largest
// magnitude; step and iteration counts exactly); its VTK series equal the uninterrupted run's. A restart
// against another case, or without a checkpoint, is bad input (exit 2, located).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <stdexcept>

#include "restart_util.hpp"

namespace fibrane::testing {
namespace {

TEST(Restart, AfterMaxStepsEqualsTheUninterruptedRun) {
  if (fibrane_binary().empty()) GTEST_SKIP() << "FIBRANE_BIN not set (run through ctest)";
  const fs::path& reference = reference_run();
  const fs::path dir = fs::temp_directory_path() / ("fibrane-restart-max-steps-" + std::to_string(::getpid()));
  const fs::path case_file = write_peeling(dir, 4);
  const fs::path out = dir / "out";
  // 24 steps: the run that runs out of steps writes a checkpoint at its last step, whatever
  // checkpoint_every (4) says. Step 25 passes the pull-off limit point, which the restarted run locates
  // from the last three points before the checkpoint and the one after it.
  const auto first = run_case(case_file, "-o '" + out.string() + "' --max-steps 24");
  ASSERT_EQ(first.exit_code, 1) << first.output;
  EXPECT_NE(read_file(out / "summary.json").find("\"max_steps\""), std::string::npos);
  const auto second = run_case(case_file, "--restart '" + out.string() + "'");
  ASSERT_EQ(second.exit_code, 0) << second.output;
  expect_same_history(reference, out);
  EXPECT_EQ(read_file(out / "fiber.pvd"), read_file(reference / "fiber.pvd"));
  EXPECT_EQ(read_file(out / "membrane.pvd"), read_file(reference / "membrane.pvd"));
  const std::string summary = read_file(out / "summary.json"), expected = read_file(reference / "summary.json");
  EXPECT_NE(summary.find("\"restarted_from_step\": 24"), std::string::npos);
  auto limit_points = [](const std::string& text) {
    const auto from = text.find("\"limit_points\""), to = text.find("\"restarted_from_step\"");
    return from == std::string::npos || to == std::string::npos ? std::string() : text.substr(from, to - from);
  };
  EXPECT_NE(limit_points(expected).find("maximum"), std::string::npos) << expected;
  EXPECT_EQ(limit_points(summary), limit_points(expected));
  fs::remove_all(dir);
}

// The shallow roof (8 x 8 quarter) with each continuation method (8 to 10 steps, under a second each):
// 5 steps, then --restart to the end.
struct MethodCase {
  const char* name;
  const char* steps;
};

class RestartMethod : public ::testing::TestWithParam<MethodCase> {};

void PrintTo(const MethodCase& c, std::ostream* os) { *os << c.name; }

TEST_P(RestartMethod, AfterMaxStepsEqualsTheUninterruptedRun) {
  if (fibrane_binary().empty()) GTEST_SKIP() << "FIBRANE_BIN not set (run through ctest)";
  const fs::path dir = fs::temp_directory_path() / (std::string("fibrane-restart-") + GetParam().name + "-" +
                                                    std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::string yaml = read_file(std::string(FIBRANE_SOURCE_DIR) + "/examples/shallow-roof.yaml");
  yaml = yaml.substr(0, yaml.find("steps:")) + GetParam().steps;
  const auto at = yaml.find("poisson: 0.3}");
  ASSERT_NE(at, std::string::npos);
  yaml.replace(at, 13, "poisson: 0.3, density: 1.0}");  // for dynamics
  std::ofstream(dir / "case.yaml") << yaml << "output: {directory: out, vtk: true, vtk_every: 2, checkpoint_every: 2}\n";
  const auto full = run_case(dir / "case.yaml", "-o '" + (dir / "full").string() + "'");
  ASSERT_EQ(full.exit_code, 0) << full.output;
  const auto first = run_case(dir / "case.yaml", "-o '" + (dir / "part").string() + "' --max-steps 5");
  ASSERT_EQ(first.exit_code, 1) << first.output;
  const auto second = run_case(dir / "case.yaml", "--restart '" + (dir / "part").string() + "'");
  ASSERT_EQ(second.exit_code, 0) << second.output;
  expect_same_history(dir / "full", dir / "part");
  EXPECT_EQ(read_file(dir / "part" / "roof.pvd"), read_file(dir / "full" / "roof.pvd"));
  // The run is complete now: another restart is refused and changes nothing.
  const std::string history = read_file(dir / "part" / "history.csv");
  const auto again = run_case(dir / "case.yaml", "--restart '" + (dir / "part").string() + "'");
  EXPECT_EQ(again.exit_code, 2) << again.output;
  EXPECT_NE(again.output.find("nothing to continue"), std::string::npos) << again.output;
  EXPECT_EQ(read_file(dir / "part" / "history.csv"), history);
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(
    Methods, RestartMethod,
    ::testing::Values(MethodCase{"load_stepping", "steps: {t_end: 0.5, dt: 0.05}\n"},
                      MethodCase{"arc_length", "steps: {method: arc_length, t_end: 0.3, arc_length: {ds: 2.0}}\n"},
                      MethodCase{"dynamics", "steps: {method: dynamics, t_end: 0.5, dt: 0.01}\n"}),
    [](const auto& info) { return std::string(info.param.name); });

// A new run (no --restart) into a directory never continues or keeps an earlier run's checkpoint: the
// stale file is removed before the run starts, and with checkpoint_every 0 a completed run writes none.
TEST(Restart, ANewRunRemovesAnEarlierRunsCheckpoint) {
  if (fibrane_binary().empty()) GTEST_SKIP() << "FIBRANE_BIN not set (run through ctest)";
  const fs::path dir = fs::temp_directory_path() / ("fibrane-restart-stale-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "out");
  std::string yaml = read_file(std::string(FIBRANE_SOURCE_DIR) + "/examples/shallow-roof.yaml");
  yaml = yaml.substr(0, yaml.find("steps:")) + "steps: {t_end: 0.2, dt: 0.1}\n";
  std::ofstream(dir / "case.yaml") << yaml << "output: {directory: out, vtk: false, checkpoint_every: 0}\n";
  std::ofstream(dir / "out" / "checkpoint.bin") << "an earlier run's checkpoint";
  const auto r = run_case(dir / "case.yaml", "-o '" + (dir / "out").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(fs::exists(dir / "out" / "checkpoint.bin"));
  const auto restart = run_case(dir / "case.yaml", "--restart '" + (dir / "out").string() + "'");
  EXPECT_EQ(restart.exit_code, 2) << restart.output;
  fs::remove_all(dir);
}

TEST(Restart, AfterSigkillEqualsTheUninterruptedRun) {
  if (fibrane_binary().empty()) GTEST_SKIP() << "FIBRANE_BIN not set (run through ctest)";
  const fs::path& reference = reference_run();
  const fs::path dir = fs::temp_directory_path() / ("fibrane-restart-kill-" + std::to_string(::getpid()));
  const fs::path case_file = write_peeling(dir, 3);
  const fs::path out = dir / "out";
  const pid_t pid = spawn_run(case_file, out);
  wait_for_rows(pid, out, 20, true);
  ASSERT_EQ(kill(pid, SIGKILL), 0);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << "the run ended before the kill";
  EXPECT_FALSE(fs::exists(out / "summary.json"));
  // The case text differs from the reference's (checkpoint_every) but not its results.
  const auto second = run_case(case_file, "--restart '" + out.string() + "'");
  ASSERT_EQ(second.exit_code, 0) << second.output;
  expect_same_history(reference, out);
  EXPECT_EQ(read_file(out / "fiber.pvd"), read_file(reference / "fiber.pvd"));
  fs::remove_all(dir);
}

// SIGTERM (143) and SIGINT (130): the step in progress is finished and written, then a checkpoint and a
// summary saying "interrupted"; the restart completes the run, its history one row per step. (That a
// restarted history equals the uninterrupted one is the SIGKILL test's; this one spares the reference.)
void interrupt_and_restart(int signal, int exit_code, const char* name) {
  const fs::path dir = fs::temp_directory_path() / (std::string("fibrane-restart-") + name + std::to_string(::getpid()));
  const fs::path case_file = write_peeling(dir, 50);  // the checkpoint comes from the interruption
  const fs::path out = dir / "out";
  const pid_t pid = spawn_run(case_file, out);
  wait_for_rows(pid, out, 10, false);
  // fibrane re-executes itself once at start-up (run/process_environment.cpp) with execv: the process that
  // runs the steps is the re-executed image under the pid the signal goes to.
  const std::string environ = read_file("/proc/" + std::to_string(pid) + "/environ");
  EXPECT_NE(environ.find("FIBRANE_OPENMP_CONFIGURED=1"), std::string::npos);
  if (!std::getenv("GLIBC_TUNABLES")) {  // the malloc thresholds it sets unless the user gave their own
    EXPECT_NE(environ.find("GLIBC_TUNABLES=glibc.malloc.mmap_threshold="), std::string::npos);
  }
  if (!std::getenv("OPENBLAS_THREAD_TIMEOUT")) {  // and OpenBLAS's shorter spin
    EXPECT_NE(environ.find("OPENBLAS_THREAD_TIMEOUT=20"), std::string::npos);
  }
  EXPECT_FALSE(fs::exists(out / "checkpoint.bin"));
  ASSERT_EQ(kill(pid, signal), 0);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status)) << "killed by the signal instead of ending the run";
  EXPECT_EQ(WEXITSTATUS(status), exit_code);
  const std::string summary = read_file(out / "summary.json");
  EXPECT_NE(summary.find(std::string("\"interrupted\": \"") + name + "\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("interrupted at t = "), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"completed\": false"), std::string::npos) << summary;
  EXPECT_TRUE(fs::exists(out / "checkpoint.bin"));
  const int interrupted_rows = history_rows(out);
  // The run ended after the step in progress (steps take ~0.1 s; the poll looks every 20 ms).
  EXPECT_LE(interrupted_rows, 14);
  EXPECT_NE(summary.find("after step " + std::to_string(interrupted_rows - 1)), std::string::npos) << summary;
  const auto second = run_case(case_file, "--restart '" + out.string() + "'");
  ASSERT_EQ(second.exit_code, 0) << second.output;
  const History h = read_history(out);
  EXPECT_GT(static_cast<int>(h.rows.size()), interrupted_rows + 10);
  for (std::size_t i = 0; i < h.rows.size(); ++i) EXPECT_EQ(h.rows[i][0], static_cast<double>(i)) << "step column";
  EXPECT_NE(read_file(out / "summary.json").find("\"completed\": true"), std::string::npos);
  fs::remove_all(dir);
}

TEST(Restart, SigtermWritesAnInterruptedSummaryAndExits143) {
  if (fibrane_binary().empty()) GTEST_SKIP() << "FIBRANE_BIN not set (run through ctest)";
  interrupt_and_restart(SIGTERM, 143, "SIGTERM");
}

TEST(Restart, SigintWritesAnInterruptedSummaryAndExits130) {
  if (fibrane_binary().empty()) GTEST_SKIP() << "FIBRANE_BIN not set (run through ctest)";
  interrupt_and_restart(SIGINT, 130, "SIGINT");
}

// A fresh directory holding case.yaml: examples/bending.yaml with the shell's and the fiber's elements,
// the text after `dt_max: ` and no VTK output.
fs::path write_bending(const std::string& name, const std::string& shell, const std::string& fiber,
                       const std::string& dt_max) {
  const fs::path dir = fs::temp_directory_path() / ("fibrane-restart-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::string yaml = read_file(std::string(FIBRANE_SOURCE_DIR) + "/examples/bending.yaml");
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"elements: [100, 100]", "elements: " + shell},
                                 {"elements: 400", "elements: " + fiber},
                                 {"dt_max: 0.04", "dt_max: " + dt_max},
                                 {"output: {directory: out/bending, vtk_every: 5}", "output: {vtk: false}"}}) {
    const auto at = yaml.find(from);
    if (at == std::string::npos) throw std::runtime_error("examples/bending.yaml lacks '" + from + "'");
    yaml.replace(at, from.size(), to);
  }
  std::ofstream(dir / "case.yaml") << yaml;
  return dir;
}

// The bending example at 32 x 8 x 8 (RF2 with the soft minimum; about 5 s of CPU per run): the first
// beam point switches to the soft minimum in step 32, requested when step 31 was accepted. A run stopped
// after step 31 and restarted carries the pending switch over, and its history and per-point interaction
// files equal the uninterrupted run's.
TEST(Restart, AcrossASoftMinimumSwitchEqualsTheUninterruptedRun) {
  if (fibrane_binary().empty()) GTEST_SKIP() << "FIBRANE_BIN not set (run through ctest)";
  // The step numbers below are those of steps up to 0.03.
  const fs::path dir = write_bending("soft", "[8, 8]", "32", "0.03");
  ASSERT_EQ(run_case(dir / "case.yaml", "-o '" + (dir / "full").string() + "'").exit_code, 0);
  ASSERT_EQ(run_case(dir / "case.yaml", "-o '" + (dir / "part").string() + "' --max-steps 31").exit_code, 1);
  const auto second = run_case(dir / "case.yaml", "--restart '" + (dir / "part").string() + "'");
  ASSERT_EQ(second.exit_code, 0) << second.output;
  expect_same_history(dir / "full", dir / "part");
  const std::string step32 = "interaction/adhesion_000032.csv", last = "interaction/adhesion_000035.csv";
  EXPECT_NE(read_file(dir / "full" / step32).find(",1\n"), std::string::npos) << "no soft point in step 32";
  EXPECT_EQ(read_file(dir / "part" / step32), read_file(dir / "full" / step32));
  EXPECT_EQ(read_file(dir / "part" / last), read_file(dir / "full" / last));
  fs::remove_all(dir);
}

// The bending example at 40 x 10 x 10 with located switches (steps.event_tolerance 1e-3, dt_max 0.03;
// about 3 s of CPU per run): after a withdrawn attempt, step 29 ends a shortened step before the crossing
// and step 30 crosses it in a step of the tolerance. A run stopped after step 29 and restarted carries the
// bracket and the margins over (LoadStepping's checkpoint keys) and takes the same steps.
TEST(Restart, InsideALocatedSwitchEqualsTheUninterruptedRun) {
  if (fibrane_binary().empty()) GTEST_SKIP() << "FIBRANE_BIN not set (run through ctest)";
  const fs::path dir = write_bending("located", "[10, 10]", "40", "0.03\n  event_tolerance: 1.0e-3");
  ASSERT_EQ(run_case(dir / "case.yaml", "-o '" + (dir / "full").string() + "'").exit_code, 0);
  EXPECT_NE(read_file(dir / "full" / "summary.json").find("\"withdrawn_attempts\": 1,"), std::string::npos);
  const History full = read_history(dir / "full");
  ASSERT_GT(full.rows.size(), 31u);
  ASSERT_EQ(full.columns[1], "t");
  auto dt = [&](std::size_t step) { return full.rows[step][1] - full.rows[step - 1][1]; };
  EXPECT_GT(dt(29), 2e-3);               // the shortened step
  EXPECT_NEAR(dt(30), 1e-3, 1e-12);      // the crossing
  ASSERT_EQ(run_case(dir / "case.yaml", "-o '" + (dir / "part").string() + "' --max-steps 29").exit_code, 1);
  const auto second = run_case(dir / "case.yaml", "--restart '" + (dir / "part").string() + "'");
  ASSERT_EQ(second.exit_code, 0) << second.output;
  expect_same_history(dir / "full", dir / "part");
  fs::remove_all(dir);
}

TEST(Restart, RefusesAnotherCaseOrAMissingCheckpoint) {
  if (fibrane_binary().empty()) GTEST_SKIP() << "FIBRANE_BIN not set (run through ctest)";
  const fs::path dir = fs::temp_directory_path() / ("fibrane-restart-refuse-" + std::to_string(::getpid()));
  const fs::path case_file = write_peeling(dir, 2);
  const fs::path out = dir / "out";
  const auto missing = run_case(case_file, "--restart '" + out.string() + "'");
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_NE(missing.output.find("checkpoint.bin"), std::string::npos) << missing.output;
  ASSERT_EQ(run_case(case_file, "-o '" + out.string() + "' --max-steps 2").exit_code, 1);
  const std::string history = read_file(out / "history.csv");
  std::ofstream(case_file, std::ios::app) << "# edited\n";
  const auto other = run_case(case_file, "--restart '" + out.string() + "'");
  EXPECT_EQ(other.exit_code, 2) << other.output;
  EXPECT_NE(other.output.find("checkpoint.bin: written for another case file"), std::string::npos) << other.output;
  EXPECT_EQ(read_file(out / "history.csv"), history);  // nothing touched
  const auto both = run_case(case_file, "--restart '" + out.string() + "' -o '" + out.string() + "'");
  EXPECT_EQ(both.exit_code, 2) << both.output;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace fibrane::testing
