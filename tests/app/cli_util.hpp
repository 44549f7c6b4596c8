#pragma once
// Runs the fibrane executable (path in $FIBRANE_BIN, set by ctest) and captures exit code and output.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

namespace fibrane::testing {

struct CliResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

inline std::string fibrane_binary() {
  const char* bin = std::getenv("FIBRANE_BIN");
  return bin ? bin : "";
}

// Runs any shell command, capturing stdout and stderr together.
inline CliResult run_cli_command(const std::string& shell_command) {
  CliResult r;
  const std::string command = shell_command + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buffer{};
  while (std::fgets(buffer.data(), buffer.size(), pipe)) r.output += buffer.data();
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

inline CliResult run_cli(const std::string& arguments) {
  std::string command = "'";  // appended piece by piece: GCC 12 warns (-Wrestrict) on "'" + std::string
  command += fibrane_binary();
  command += "' ";
  command += arguments;
  return run_cli_command(command);
}

// Starts `fibrane run CASE -q --threads 1 -o OUT` in the background (output to /dev/null); returns its pid.
inline pid_t spawn_run(const std::filesystem::path& case_file, const std::filesystem::path& out) {
  const std::string bin = fibrane_binary(), file = case_file.string(), dir = out.string();
  std::vector<std::string> args{bin, "run", file, "-q", "--threads", "1", "-o", dir};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid = -1;
  EXPECT_EQ(posix_spawn(&pid, bin.c_str(), &actions, nullptr, argv.data(), environ), 0);
  posix_spawn_file_actions_destroy(&actions);
  return pid;
}

}  // namespace fibrane::testing
