// The output directory belongs to one run: a second run (or a restart) into a directory that a run is
// writing is refused with exit code 2 naming the other run's pid, and the first run's history stays
// intact; nothing is written or removed through a symbolic link (a linked history.csv's target keeps its
// content, a linked vtk/ folder or output directory is refused and nothing in its target is touched); a
// new run into a directory that holds another case's output leaves none of that run's files.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <thread>
#include <vector>

#include "cli_util.hpp"

extern char** environ;

namespace fibrane::testing {
namespace {

namespace fs = std::filesystem;

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::stringstream s(text);
  for (std::string line; std::getline(s, line);) lines.push_back(line);
  return lines;
}

// A fresh scratch folder named for the test and the process.
fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("fibrane-outdir-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string example(const std::string& name) {
  return read_file(fs::path(FIBRANE_SOURCE_DIR) / "examples" / name);
}

// The coarse peeling case (a shell, a beam, an interaction; arc length, about fifty steps, a few seconds
// with one thread) with VTK output at every fifth step.
fs::path write_peeling(const fs::path& dir) {
  std::string yaml = example("peeling.yaml");
  yaml = std::regex_replace(yaml, std::regex("elements: \\[20, 10\\]"), "elements: [4, 2]");
  yaml = std::regex_replace(yaml, std::regex("elements: 100"), "elements: 10");
  yaml = std::regex_replace(yaml, std::regex("output: \\{[^}]*\\}"), "output: {directory: out, vtk_every: 5}");
  std::ofstream(dir / "peeling.yaml") << yaml;
  return dir / "peeling.yaml";
}

// The shallow roof (one shell named roof) with VTK output.
fs::path write_roof(const fs::path& dir) {
  std::string yaml = example("shallow-roof.yaml");
  yaml = std::regex_replace(yaml, std::regex("output: \\{[^}]*\\}"), "output: {directory: out, vtk: true}");
  std::ofstream(dir / "roof.yaml") << yaml;
  return dir / "roof.yaml";
}

CliResult run_case(const fs::path& case_file, const std::string& options) {
  return run_cli("run '" + case_file.string() + "' -q --threads 1 " + options);
}

// The regular files under `dir`, relative to it, without the lock file and the manifest.
std::set<std::string> files_under(const fs::path& dir) {
  std::set<std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const std::string rel = fs::relative(e.path(), dir).string();
    if (!e.is_directory() && rel != ".fibrane.lock" && rel != ".fibrane-manifest") files.insert(rel);
  }
  return files;
}

// The paths the manifest of `dir` lists.
std::set<std::string> manifest_of(const fs::path& dir) {
  const auto lines = lines_of(read_file(dir / ".fibrane-manifest"));
  EXPECT_FALSE(lines.empty()) << "no manifest in " << dir;
  return lines.empty() ? std::set<std::string>{} : std::set<std::string>(lines.begin() + 1, lines.end());
}

// Two runs into one directory: the second (a new run or a restart) is refused at once with exit code 2,
// naming the directory and the first run's pid, and writes nothing; the first run completes and its
// history has one row per step, in order, each with the header's columns. The lock file the first run
// leaves holds no lock: a later run goes ahead.
TEST(OutputDirectory, ASecondRunIntoABusyDirectoryIsRefused) {
  if (fibrane_binary().empty()) GTEST_SKIP() << "FIBRANE_BIN not set (run through ctest)";
  const fs::path dir = scratch("busy");
  const fs::path case_file = write_peeling(dir), out = dir / "out";
  const pid_t first = spawn_run(case_file, out);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (lines_of(read_file(out / "history.csv")).size() < 3 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  const std::string history_before = read_file(out / "history.csv");
  const auto second = run_case(case_file, "-o '" + out.string() + "'");
  const auto restart = run_case(case_file, "--restart '" + out.string() + "'");
  int status = 0;
  ASSERT_EQ(waitpid(first, &status, 0), first);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  for (const auto& r : {second, restart}) {
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("output directory '" + out.string() + "'"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("another fibrane run is writing into this directory (pid " + std::to_string(first)),
              std::string::npos)
        << r.output;
  }
  const auto lines = lines_of(read_file(out / "history.csv"));
  ASSERT_GT(lines.size(), 20u);
  EXPECT_EQ(read_file(out / "history.csv").compare(0, history_before.size(), history_before), 0);
  const auto columns = std::count(lines[0].begin(), lines[0].end(), ',');
  for (std::size_t i = 1; i < lines.size(); ++i) {
    EXPECT_EQ(lines[i].substr(0, lines[i].find(',')), std::to_string(i - 1)) << "row " << i;
    EXPECT_EQ(std::count(lines[i].begin(), lines[i].end(), ','), columns) << "row " << i;
  }
  EXPECT_NE(read_file(out / "summary.json").find("\"completed\": true"), std::string::npos);
  EXPECT_NE(read_file(out / ".fibrane.lock").find("pid " + std::to_string(first)), std::string::npos);
  const auto later = run_case(case_file, "-o '" + out.string() + "' --max-steps 2");
  EXPECT_EQ(later.exit_code, 1) << later.output;  // stopped by --max-steps, not by the stale lock file
  EXPECT_EQ(lines_of(read_file(out / "history.csv")).size(), 4u);
  fs::remove_all(dir);
}

// Links at names a run writes are replaced by the run's own regular files; their targets keep their
// content. A restart does not continue a history.csv that is a link.
TEST(OutputDirectory, LinkedFilesAreReplacedNotWrittenThrough) {
  if (fibrane_binary().empty()) GTEST_SKIP() << "FIBRANE_BIN not set (run through ctest)";
  const fs::path dir = scratch("links");
  const fs::path case_file = write_roof(dir), out = dir / "out";
  fs::create_directories(out);
  for (const char* name : {"history.csv", "summary.json", "roof.pvd", "checkpoint.bin"}) {
    std::ofstream(dir / (std::string("precious-") + name)) << "precious " << name << "\n";
    fs::create_symlink(dir / (std::string("precious-") + name), out / name);
  }
  const auto r = run_case(case_file, "-o '" + out.string() + "' --max-steps 2");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  for (const char* name : {"history.csv", "summary.json", "roof.pvd", "checkpoint.bin"}) {
    EXPECT_EQ(read_file(dir / (std::string("precious-") + name)), std::string("precious ") + name + "\n") << name;
    EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(out / name))) << name;
  }
  EXPECT_EQ(lines_of(read_file(out / "history.csv")).size(), 4u);
  fs::remove(out / "history.csv");
  fs::create_symlink(dir / "precious-history.csv", out / "history.csv");
  const auto restart = run_case(case_file, "--restart '" + out.string() + "'");
  EXPECT_EQ(restart.exit_code, 2) << restart.output;
  EXPECT_NE(restart.output.find("history.csv: cannot continue it: it is not a regular file"), std::string::npos)
      << restart.output;
  EXPECT_EQ(read_file(dir / "precious-history.csv"), "precious history.csv\n");
  fs::remove_all(dir);
}

// A vtk/ folder that is a link, and an output directory that is a link, are refused (exit code 2): nothing
// in the links' targets is removed or written, and nothing is left in the output directory.
TEST(OutputDirectory, LinkedFoldersAreRefusedAndNothingIsWritten) {
  if (fibrane_binary().empty()) GTEST_SKIP() << "FIBRANE_BIN not set (run through ctest)";
  const fs::path dir = scratch("folders");
  const fs::path case_file = write_roof(dir), out = dir / "out", foreign = dir / "foreign";
  fs::create_directories(foreign);
  fs::create_directories(out);
  // Names a run of this case would remove or write in vtk/.
  for (const char* name : {"roof_000000.vtu", "roof_000001.vtu", "notes.txt"})
    std::ofstream(foreign / name) << "foreign " << name << "\n";
  fs::create_symlink(foreign, out / "vtk");
  const auto linked_vtk = run_case(case_file, "-o '" + out.string() + "' --max-steps 1");
  EXPECT_EQ(linked_vtk.exit_code, 2) << linked_vtk.output;
  EXPECT_NE(linked_vtk.output.find((out / "vtk").string() + ": is a symbolic link"), std::string::npos)
      << linked_vtk.output;
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(out)) left.push_back(e.path().filename().string());
  EXPECT_EQ(left, std::vector<std::string>{"vtk"}) << "nothing may be written for a refused run";
  fs::remove(out / "vtk");
  fs::create_symlink(foreign, dir / "linked-out");
  const auto linked_out = run_case(case_file, "-o '" + (dir / "linked-out").string() + "' --max-steps 1");
  EXPECT_EQ(linked_out.exit_code, 2) << linked_out.output;
  EXPECT_NE(linked_out.output.find("output directory '" + (dir / "linked-out").string() + "': is a symbolic link"),
            std::string::npos)
      << linked_out.output;
  EXPECT_EQ(files_under(foreign), (std::set<std::string>{"notes.txt", "roof_000000.vtu", "roof_000001.vtu"}));
  for (const char* name : {"roof_000000.vtu", "roof_000001.vtu", "notes.txt"})
    EXPECT_EQ(read_file(foreign / name), std::string("foreign ") + name + "\n");
  fs::remove_all(dir);
}

// A run of another case into a used directory removes every file the earlier run wrote (its other
// bodies' collections and step files, its interaction files, its checkpoint), keeps files it did not
// write, and lists its own files in its manifest.
TEST(OutputDirectory, AnotherCaseLeavesNoneOfTheEarlierRunsFiles) {
  if (fibrane_binary().empty()) GTEST_SKIP() << "FIBRANE_BIN not set (run through ctest)";
  const fs::path dir = scratch("stale");
  const fs::path peeling = write_peeling(dir), roof = write_roof(dir), out = dir / "out";
  const auto first = run_case(peeling, "-o '" + out.string() + "' --max-steps 6");
  ASSERT_EQ(first.exit_code, 1) << first.output;
  const std::set<std::string> earlier = files_under(out);
  EXPECT_EQ(manifest_of(out), earlier);
  for (const char* f : {"membrane.pvd", "fiber.pvd", "adhesion.pvd", "interaction/adhesion_000006.csv",
                        "vtk/fiber_000005.vtu", "checkpoint.bin", "summary.json"})
    EXPECT_TRUE(earlier.count(f)) << f;
  std::ofstream(out / "notes.txt") << "the user's own file\n";
  const auto second = run_case(roof, "-o '" + out.string() + "' --max-steps 2");
  ASSERT_EQ(second.exit_code, 1) << second.output;
  std::set<std::string> now = files_under(out);
  EXPECT_EQ(now.erase("notes.txt"), 1u);
  const std::set<std::string> listed = manifest_of(out);
  for (const auto& f : now) EXPECT_TRUE(listed.count(f)) << f << " is not the second run's";
  for (const auto& f : earlier) {
    if (!listed.count(f)) {
      EXPECT_FALSE(fs::exists(out / f)) << f << " of the earlier run is left";
    }
  }
  EXPECT_FALSE(fs::exists(out / "interaction")) << "the earlier run's emptied folder is left";
  EXPECT_TRUE(now.count("roof.pvd") && now.count("vtk/roof_000002.vtu") && now.count("history.csv"));
  fs::remove_all(dir);
}

// A manifest that lists a path outside the directory (absolute, "..", another folder) is refused before
// anything is removed: the file it names is kept.
TEST(OutputDirectory, AManifestNamingOutsidePathsIsRefused) {
  if (fibrane_binary().empty()) GTEST_SKIP() << "FIBRANE_BIN not set (run through ctest)";
  const fs::path dir = scratch("manifest");
  const fs::path case_file = write_roof(dir), out = dir / "out";
  fs::create_directories(out / "sub");
  std::ofstream(dir / "victim.txt") << "victim\n";
  std::ofstream(out / "sub" / "kept.txt") << "kept\n";
  for (const std::string& entry : {(dir / "victim.txt").string(), std::string("../victim.txt"),
                                   std::string("vtk/../../victim.txt"), std::string("sub/kept.txt")}) {
    std::ofstream(out / ".fibrane-manifest") << "# fibrane manifest 1: test\nsummary.json\n" << entry << "\n";
    const auto r = run_case(case_file, "-o '" + out.string() + "' --max-steps 1");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(".fibrane-manifest: line 3: '" + entry + "' is not a file a run writes"), std::string::npos)
        << r.output;
    EXPECT_EQ(read_file(dir / "victim.txt"), "victim\n");
    EXPECT_EQ(read_file(out / "sub" / "kept.txt"), "kept\n");
    EXPECT_FALSE(fs::exists(out / ".fibrane.lock")) << "nothing may be written for a refused run";
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace fibrane::testing
