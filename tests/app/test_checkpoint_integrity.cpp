// What a restart trusts: the case text the run started with (kept in memory from the start, its hash in
// every checkpoint), the checkpoint file (sealed by a checksum, read within its real size, a regular file
// only) and the history.csv rows the checkpoint vouches for (their count and hash). Anything else is
// refused with exit code 2, a message naming the file and what is wrong, and nothing in the output
// directory changed; a run never reads its case file again after it started.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>

#include "common/hash.hpp"
#include "restart_util.hpp"

namespace fibrane::testing {
namespace {

void write_bytes(const fs::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary | std::ios::trunc) << bytes;
}

// The offset of the element count of the checkpoint entry `name` (layout: io/checkpoint_file.hpp).
std::size_t count_field(const std::string& bytes, const std::string& name) {
  for (std::size_t at = bytes.find(name); at != std::string::npos; at = bytes.find(name, at + 1)) {
    std::uint32_t size = 0;
    if (at < 5) continue;
    std::memcpy(&size, bytes.data() + at - 4, 4);
    if (size == name.size()) return at + name.size();
  }
  ADD_FAILURE() << "no checkpoint entry '" << name << "'";
  return 0;
}

template <typename T>
void patch(std::string& bytes, std::size_t at, T value) {
  std::memcpy(bytes.data() + at, &value, sizeof(T));
}

// Recomputes the checksum (the last 8 bytes), as a forger would.
void reseal(std::string& bytes) { patch(bytes, bytes.size() - 8, fnv1a64(bytes.data(), bytes.size() - 8)); }

// The shallow roof (8 x 8 quarter) by load stepping to t = 0.5 (6 steps, a second in all): `part` stopped
// by --max-steps 5 (its checkpoint at step 5, six history rows) and `full`, the uninterrupted run.
struct RoofRuns {
  fs::path dir = fs::temp_directory_path() / ("fibrane-checkpoint-integrity-" + std::to_string(::getpid()));
  fs::path case_file = dir / "case.yaml", part = dir / "part", full = dir / "full";
  RoofRuns() {
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::string yaml = read_file(std::string(FIBRANE_SOURCE_DIR) + "/examples/shallow-roof.yaml");
    std::ofstream(case_file) << yaml.substr(0, yaml.find("steps:")) << "steps: {t_end: 0.5, dt: 0.05}\n"
                             << "output: {directory: out, vtk: false, checkpoint_every: 2}\n";
    const auto whole = run_case(case_file, "-o '" + full.string() + "'");
    EXPECT_EQ(whole.exit_code, 0) << whole.output;
    const auto first = run_case(case_file, "-o '" + part.string() + "' --max-steps 5");
    EXPECT_EQ(first.exit_code, 1) << first.output;
  }
  ~RoofRuns() { fs::remove_all(dir); }
  // A copy of `part` to damage.
  fs::path copy(const std::string& name) const {
    const fs::path to = dir / name;
    fs::remove_all(to);
    fs::copy(part, to, fs::copy_options::recursive);
    return to;
  }
  CliResult restart(const fs::path& out) const { return run_case(case_file, "--restart '" + out.string() + "'"); }
};

const RoofRuns& roof() {
  static const RoofRuns runs;
  return runs;
}

// A restart from `out` is refused: exit code 2, a message naming `file` and containing `what`, and the
// directory's files as they were.
void expect_refused(const fs::path& out, const std::string& file, const std::string& what) {
  const std::string history = read_file(out / "history.csv");
  const std::string checkpoint = fs::is_regular_file(out / "checkpoint.bin") ? read_file(out / "checkpoint.bin") : "";
  const auto r = roof().restart(out);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find((out / file).string() + ":"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(what), std::string::npos) << "expected '" << what << "' in: " << r.output;
  EXPECT_EQ(read_file(out / "history.csv"), history);
  if (fs::is_regular_file(out / "checkpoint.bin")) {
    EXPECT_EQ(read_file(out / "checkpoint.bin"), checkpoint);
  }
  EXPECT_TRUE(fs::exists(out / "summary.json")) << "the stopped run's summary was removed";
}

#define SKIP_WITHOUT_BINARY() \
  if (fibrane_binary().empty()) GTEST_SKIP() << "FIBRANE_BIN not set (run through ctest)"

TEST(CheckpointIntegrity, AnUndamagedCopyRestartsToTheUninterruptedHistory) {
  SKIP_WITHOUT_BINARY();
  const fs::path out = roof().copy("undamaged");
  const auto r = roof().restart(out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(read_file(out / "history.csv"), read_file(roof().full / "history.csv"));
}

TEST(CheckpointIntegrity, FlippedBitsAreRefused) {
  SKIP_WITHOUT_BINARY();
  const std::string bytes = read_file(roof().part / "checkpoint.bin");
  ASSERT_GT(bytes.size(), 1000u);
  const std::size_t q = count_field(bytes, "q") + 8;  // the unknowns' first byte
  const std::pair<std::size_t, const char*> flips[] = {
      {3, "not a fibrane checkpoint"},  {25, "checksum"}, {q + 100, "checksum"}, {q + 7, "checksum"},
      {bytes.size() / 2, "checksum"}, {bytes.size() - 12, "truncated"}, {bytes.size() - 1, "checksum"}};
  for (const auto& [at, what] : flips) {
    SCOPED_TRACE("byte " + std::to_string(at));
    const fs::path out = roof().copy("flip");
    std::string damaged = bytes;
    damaged[at] = static_cast<char>(damaged[at] ^ 0x10);
    write_bytes(out / "checkpoint.bin", damaged);
    expect_refused(out, "checkpoint.bin", what);
  }
}

TEST(CheckpointIntegrity, TruncationsAreRefused) {
  SKIP_WITHOUT_BINARY();
  const std::string bytes = read_file(roof().part / "checkpoint.bin");
  const std::pair<std::size_t, const char*> sizes[] = {
      {0, "is empty"}, {10, "not a fibrane checkpoint"}, {21, "truncated"}, {bytes.size() / 2, "truncated"},
      {bytes.size() - 8, "truncated"}, {bytes.size() - 1, "truncated"}};
  for (const auto& [size, what] : sizes) {
    SCOPED_TRACE("size " + std::to_string(size));
    const fs::path out = roof().copy("truncated");
    write_bytes(out / "checkpoint.bin", bytes.substr(0, size));
    expect_refused(out, "checkpoint.bin", what);
  }
}

// history_rows 6 -> 2: steps 2 to 5 would be lost. The checksum catches the patch; resealed, the history
// hash does (the hash of three lines is not the hash of seven).
TEST(CheckpointIntegrity, PatchedHistoryRowsAreRefused) {
  SKIP_WITHOUT_BINARY();
  std::string bytes = read_file(roof().part / "checkpoint.bin");
  const std::size_t rows = count_field(bytes, "history_rows") + 8;
  double value = 0;
  std::memcpy(&value, bytes.data() + rows, 8);
  ASSERT_EQ(value, 6.0);
  patch(bytes, rows, 2.0);
  fs::path out = roof().copy("rows");
  write_bytes(out / "checkpoint.bin", bytes);
  expect_refused(out, "checkpoint.bin", "checksum");
  reseal(bytes);
  out = roof().copy("rows-resealed");
  write_bytes(out / "checkpoint.bin", bytes);
  expect_refused(out, "history.csv", "its header and first 2 rows differ from those the run wrote");
}

// Lengths patched and resealed: every length read from the file is bounded by the file's size before
// anything is allocated (4 GiB of address space; a declared 2^60 doubles would throw bad_alloc).
TEST(CheckpointIntegrity, PatchedLengthsAreRefusedWithoutAllocating) {
  SKIP_WITHOUT_BINARY();
  const std::string bytes = read_file(roof().part / "checkpoint.bin");
  const std::size_t q = count_field(bytes, "q");
  struct Patch {
    std::size_t at;
    std::uint64_t value;
    int size;
    const char* what;
  };
  const Patch patches[] = {{q, std::uint64_t{1} << 60, 8, "entry 'q' declares"},
                           {q, 3, 8, "damaged"},
                           {21, std::uint64_t{1} << 62, 8, "entries cannot fit"},
                           {q - 5, 0xFFFFFFFFu, 4, "name at byte"}};
  for (const auto& p : patches) {
    SCOPED_TRACE(p.what);
    std::string damaged = bytes;
    if (p.size == 8) patch(damaged, p.at, p.value);
    else patch(damaged, p.at, static_cast<std::uint32_t>(p.value));
    reseal(damaged);
    const fs::path out = roof().copy("length");
    write_bytes(out / "checkpoint.bin", damaged);
    const auto r = run_cli_command("bash -c \"ulimit -v 4194304; timeout 20 '" + fibrane_binary() + "' run '" +
                                   roof().case_file.string() + "' -q --threads 1 --restart '" + out.string() + "'\"");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("checkpoint.bin: the checkpoint file is damaged"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(p.what), std::string::npos) << r.output;
  }
}

// Rows the checkpoint vouches for, edited or removed, are refused; rows after them (a killed run's steps
// after its last checkpoint, or anything appended) are cut off by the restart.
TEST(CheckpointIntegrity, EditedHistoryRowsAreRefusedLaterRowsAreCut) {
  SKIP_WITHOUT_BINARY();
  const std::string history = read_file(roof().part / "history.csv");
  const std::size_t row3 = [&] {
    std::size_t at = 0;
    for (int line = 0; line < 3; ++line) at = history.find('\n', at) + 1;
    return at;
  }();
  fs::path out = roof().copy("garbage-row");
  write_bytes(out / "history.csv", history.substr(0, row3) + "1,2,3\n" + history.substr(row3));
  expect_refused(out, "history.csv", "differ from those the run wrote");
  out = roof().copy("digit");
  std::string edited = history;
  edited[row3 + 2] = edited[row3 + 2] == '1' ? '2' : '1';
  write_bytes(out / "history.csv", edited);
  expect_refused(out, "history.csv", "differ from those the run wrote");
  out = roof().copy("short");
  write_bytes(out / "history.csv", history.substr(0, row3));
  expect_refused(out, "history.csv", "it has 2 complete rows, the checkpoint");
  out = roof().copy("appended");
  write_bytes(out / "history.csv", history + "garbage,row\n7,8\n");
  const auto r = roof().restart(out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(read_file(out / "history.csv"), read_file(roof().full / "history.csv"));
}

TEST(CheckpointIntegrity, NonRegularFilesAreRefused) {
  SKIP_WITHOUT_BINARY();
  fs::path out = roof().copy("dev-zero");
  fs::remove(out / "checkpoint.bin");
  fs::create_symlink("/dev/zero", out / "checkpoint.bin");
  const auto r = run_cli_command("bash -c \"ulimit -v 4194304; timeout 20 '" + fibrane_binary() + "' run '" +
                                 roof().case_file.string() + "' -q --threads 1 --restart '" + out.string() + "'\"");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("checkpoint.bin: the checkpoint file is not a regular file"), std::string::npos) << r.output;
  out = roof().copy("fifo");
  fs::remove(out / "checkpoint.bin");
  ASSERT_EQ(::mkfifo((out / "checkpoint.bin").c_str(), 0644), 0);
  expect_refused(out, "checkpoint.bin", "not a regular file");
  out = roof().copy("history-link");
  fs::remove(out / "history.csv");
  fs::create_symlink("/dev/zero", out / "history.csv");
  const auto h = roof().restart(out);
  EXPECT_EQ(h.exit_code, 2) << h.output;
  // A link is refused before it is read (nothing is written or read through links in the output directory).
  EXPECT_NE(h.output.find("history.csv: cannot continue it: it is not a regular file"), std::string::npos) << h.output;
}

// checkpoint_every 0: the run stopped by its step budget writes a checkpoint; its restart to the end
// marks it complete, so a second --restart is refused instead of repeating the steps after it.
TEST(CheckpointIntegrity, ACompletedRestartIsNotRestartedAgainWithCheckpointEvery0) {
  SKIP_WITHOUT_BINARY();
  const fs::path dir = roof().dir / "every0";
  fs::create_directories(dir);
  std::string yaml = read_file(roof().case_file);
  yaml.replace(yaml.find("checkpoint_every: 2"), 19, "checkpoint_every: 0");
  std::ofstream(dir / "case.yaml") << yaml;
  const std::string out = (dir / "out").string();
  ASSERT_EQ(run_case(dir / "case.yaml", "-o '" + out + "' --max-steps 5").exit_code, 1);
  ASSERT_TRUE(fs::exists(dir / "out" / "checkpoint.bin"));
  const auto first = run_case(dir / "case.yaml", "--restart '" + out + "'");
  ASSERT_EQ(first.exit_code, 0) << first.output;
  const std::string history = read_file(dir / "out" / "history.csv");
  EXPECT_EQ(history, read_file(roof().full / "history.csv"));
  const auto again = run_case(dir / "case.yaml", "--restart '" + out + "'");
  EXPECT_EQ(again.exit_code, 2) << again.output;
  EXPECT_NE(again.output.find("checkpoint.bin: the run completed at t = "), std::string::npos) << again.output;
  EXPECT_NE(again.output.find("there is nothing to continue"), std::string::npos) << again.output;
  EXPECT_EQ(read_file(dir / "out" / "history.csv"), history);
}

// The peeling case (checkpoint every 3 steps) is edited while it runs (epsilon 6400 -> 6300), then
// killed: the checkpoints written after the edit still carry the text the run started with, so the
// edited file is refused and the original one continues the run to the uninterrupted history.
TEST(CheckpointIntegrity, ACaseEditedDuringTheRunIsRefusedTheOriginalAccepted) {
  SKIP_WITHOUT_BINARY();
  const fs::path& reference = reference_run();
  const fs::path dir = fs::temp_directory_path() / ("fibrane-checkpoint-edited-" + std::to_string(::getpid()));
  const fs::path case_file = write_peeling(dir, 3), out = dir / "out";
  const std::string original = read_file(case_file);
  std::string edited = original;
  const auto at = edited.find("epsilon: 6400");
  ASSERT_NE(at, std::string::npos);
  edited.replace(at, 13, "epsilon: 6300");
  const pid_t pid = spawn_run(case_file, out);
  wait_for_rows(pid, out, 8, true);
  write_bytes(case_file, edited);
  wait_for_rows(pid, out, history_rows(out) + 7, true);  // two checkpoints after the edit
  ASSERT_EQ(kill(pid, SIGKILL), 0);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the run ended before the kill";
  const std::string history = read_file(out / "history.csv");
  const auto refused = run_case(case_file, "--restart '" + out.string() + "'");
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_NE(refused.output.find("differs from the text the run started with"), std::string::npos) << refused.output;
  EXPECT_EQ(read_file(out / "history.csv"), history);
  write_bytes(case_file, original);
  const auto accepted = run_case(case_file, "--restart '" + out.string() + "'");
  ASSERT_EQ(accepted.exit_code, 0) << accepted.output;
  expect_same_history(reference, out);
  fs::remove_all(dir);
}

// A run reads its case file once: deleting it mid-run (checkpoints every 3 steps after that) does not
// stop the run.
TEST(CheckpointIntegrity, ARunWhoseCaseFileIsDeletedFinishes) {
  SKIP_WITHOUT_BINARY();
  const fs::path dir = fs::temp_directory_path() / ("fibrane-checkpoint-deleted-" + std::to_string(::getpid()));
  const fs::path case_file = write_peeling(dir, 3), out = dir / "out";
  const pid_t pid = spawn_run(case_file, out);
  wait_for_rows(pid, out, 5, true);
  fs::remove(case_file);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  const std::string summary = read_file(out / "summary.json");
  EXPECT_NE(summary.find("\"completed\": true"), std::string::npos) << summary;
  EXPECT_GT(history_rows(out), 30);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace fibrane::testing
