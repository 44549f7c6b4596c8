// The hostile corpus (tests/app/hostile/*.yaml): each file is a case that is wrong in one way, and its
// first line says how and which message it must get ("# ... -> expect: <text>"). Every one must end with
// exit code 2 and a message naming the file and containing the expected text, within 20 s and 4 GiB of
// address space (bash's ulimit -v and coreutils' timeout around the real binary), and leave nothing behind:
// each runs in an empty working directory that must hold only the case file afterwards. Generated inputs
// (too large to keep, or not regular files) follow; tests/app/hostile_runs holds legal cases that must end as
// failed runs (exit 1, summary.json) instead of crashing.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "cli_util.hpp"
#include "temp_directory.hpp"

namespace fibrane::testing {
namespace {

namespace fs = std::filesystem;

fs::path corpus_dir() { return fs::path(FIBRANE_SOURCE_DIR) / "tests" / "app" / "hostile"; }

std::vector<std::string> corpus() {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(corpus_dir()))
    if (e.path().extension() == ".yaml") names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// The text after "expect:" on the file's first line.
std::string expected_message(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::string first;
  std::getline(in, first);
  const auto at = first.find("expect:");
  if (at == std::string::npos) return "";
  std::string text = first.substr(at + 7);
  while (!text.empty() && (text.front() == ' ')) text.erase(text.begin());
  while (!text.empty() && (text.back() == ' ' || text.back() == '\r')) text.pop_back();
  return text;
}

// Address-space limit: ASan reserves terabytes of virtual memory, so a sanitizer build runs without it.
std::string limits() {
#if defined(__SANITIZE_ADDRESS__)
  return "timeout 60";
#else
  return "ulimit -v 4194304; timeout 20";
#endif
}

class HostileCase : public ::testing::TestWithParam<std::string> {};

TEST_P(HostileCase, InputErrorLocatedBoundedNothingWritten) {
  if (fibrane_binary().empty()) GTEST_SKIP() << "FIBRANE_BIN not set (run through ctest)";
  const std::string name = GetParam();
  const fs::path source = corpus_dir() / name;
  const std::string expected = expected_message(source);
  ASSERT_FALSE(expected.empty()) << name << ": the first line must say '... -> expect: <message>'";
  const fs::path dir = fresh_directory("hostile-" + fs::path(name).stem().string());
  fs::copy_file(source, dir / name);
  const auto r = run_cli_command("cd '" + dir.string() + "' && bash -c \"" + limits() + " '" + fibrane_binary() +
                                 "' run '" + name + "' -q --threads 1\"");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(name + ":"), std::string::npos) << "the message must name the file: " << r.output;
  EXPECT_NE(r.output.find(expected), std::string::npos) << "expected '" << expected << "' in: " << r.output;
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename() != name) left.push_back(e.path().filename().string());
  EXPECT_TRUE(left.empty()) << "bad input must write nothing, found " << (left.empty() ? "" : left.front());
}

INSTANTIATE_TEST_SUITE_P(Corpus, HostileCase, ::testing::ValuesIn(corpus()), [](const auto& info) {
  std::string id = fs::path(info.param).stem().string();
  for (char& ch : id)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return id;
});

TEST(HostileCorpus, HasAtLeastSixtyCases) { EXPECT_GE(corpus().size(), 60u); }

// Cases too large to keep in the repository are written here: a 50 MB list under an unknown key (refused by
// size before parsing) and a 1.2 million-item list under 16 MiB (refused by its node count).
TEST(HostileGenerated, LargeFilesAreRefusedQuickly) {
  if (fibrane_binary().empty()) GTEST_SKIP();
  const fs::path dir = fresh_directory("hostile-generated");
  const std::pair<const char*, std::size_t> cases[] = {{"huge.yaml", 25'000'000}, {"many.yaml", 1'200'000}};
  for (const auto& [name, items] : cases) {
    {
      std::ofstream out(dir / name);
      out << "shells: []\njunk: [";
      for (std::size_t i = 0; i < items; ++i) out << (i ? ",0" : "0");
      out << "]\n";
    }
    const auto r = run_cli_command("cd '" + dir.string() + "' && bash -c \"" + limits() + " '" + fibrane_binary() +
                                   "' run " + name + " -q\"");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(std::string(name) + ":"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(items > 10'000'000 ? "larger than 16 MiB" : "more than 1000000 YAML nodes"),
              std::string::npos)
        << r.output;
    fs::remove(dir / name);
    EXPECT_TRUE(fs::is_empty(dir)) << "nothing may be written";
  }
}

// A FIFO (or a directory) as the case file is refused at once with exit 2: open() on a FIFO without a
// writer would block, so the file's type is checked first (nothing ever writes to this FIFO).
TEST(HostileGenerated, CaseFileThatIsNotARegularFileIsRefusedAtOnce) {
  if (fibrane_binary().empty()) GTEST_SKIP();
  const fs::path dir = fresh_directory("hostile-not-regular");
  fs::create_directories(dir / "folder.yaml");
  ASSERT_EQ(mkfifo((dir / "fifo.yaml").c_str(), 0600), 0);
  using Expected = std::pair<const char*, const char*>;
  for (const auto& [name, what] : {Expected{"fifo.yaml", "is a FIFO (named pipe), not a case file"},
                                   Expected{"folder.yaml", "is a directory, not a case file"}}) {
    const auto start = std::chrono::steady_clock::now();
    const auto r =
        run_cli_command("cd '" + dir.string() + "' && timeout 20 '" + fibrane_binary() + "' run " + name + " -q");
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_EQ(r.exit_code, 2) << name << ": " << r.output;
    EXPECT_NE(r.output.find(std::string(name) + ": " + what), std::string::npos) << r.output;
    EXPECT_LT(seconds, 10.0) << name;
  }
  std::vector<std::string> entries;
  for (const auto& e : fs::directory_iterator(dir)) entries.push_back(e.path().filename().string());
  EXPECT_EQ(entries.size(), 2u) << "nothing may be written";
}

// A legal dynamics case whose first time step overflows (dt = t_end = 1e100, 1e90, 1e70; the beam falls
// onto the membrane) does not crash: the step's states are invalid (non-finite or unprojectable), Newton fails
// and the step is cut back until the run ends as a failed run (exit 1) with its summary.json.
TEST(HostileRuns, OverflowingDynamicsStepEndsAsAFailedRun) {
  if (fibrane_binary().empty()) GTEST_SKIP();
  for (const auto& [dt, dt_min] : {std::pair<std::string, std::string>{"1.0e100", "1.0e99"}, {"1.0e90", "1.0e89"},
                                   {"1.0e70", "1.0e69"}}) {
    const fs::path dir = fresh_directory("hostile-huge-dt-" + dt);
    std::ifstream in(corpus_dir() / ".." / "hostile_runs" / "dynamics_huge_dt.yaml");
    std::stringstream text;
    text << in.rdbuf();
    std::string yaml = text.str();
    for (const auto& [from, to] : {std::pair{std::string("1.0e100"), dt}, std::pair{std::string("1.0e99"), dt_min}})
      for (std::size_t at = 0; (at = yaml.find(from, at)) != std::string::npos; at += to.size())
        yaml.replace(at, from.size(), to);
    std::ofstream(dir / "case.yaml") << yaml;
    const auto r = run_cli_command("cd '" + dir.string() + "' && bash -c \"" + limits() + " '" + fibrane_binary() +
                                   "' run case.yaml -q -o out\"");
    EXPECT_EQ(r.exit_code, 1) << dt << ": " << r.output;
    EXPECT_NE(r.output.find("fibrane: stopped at t = 0"), std::string::npos) << r.output;
    std::ifstream summary(dir / "out" / "summary.json");
    std::stringstream json;
    json << summary.rdbuf();
    EXPECT_NE(json.str().find("\"outcome\": \"failed\""), std::string::npos) << json.str();
    EXPECT_NE(json.str().find("\"failed_attempts\": "), std::string::npos) << json.str();
    EXPECT_EQ(json.str().find("\"failed_attempts\": 0"), std::string::npos) << json.str();  // every attempt failed
  }
}

}  // namespace
}  // namespace fibrane::testing
