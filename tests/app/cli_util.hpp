#pragma once
// Runs the fibrane executable (path in $FIBRANE_BIN, set by ctest) and captures exit code and output.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <sys/wait.h>

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
  return run_cli_command("'" + fibrane_binary() + "' " + arguments);
}

}  // namespace fibrane::testing
