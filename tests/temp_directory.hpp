#pragma once
// Temporary directories for the tests that write cases and run output.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace fibrane::testing {

// A fresh directory for a case and its output, named by this process so that two test runs side by side
// (a CI run beside a developer's) do not share it. The directories are removed when the process exits
// with every test passed, and kept for inspection otherwise.
inline std::filesystem::path fresh_directory(const std::string& name) {
  static std::vector<std::filesystem::path> made;
  if (made.empty())
    std::atexit([] {
      if (::testing::UnitTest::GetInstance()->Passed())
        for (const auto& dir : made) std::filesystem::remove_all(dir);
    });
  const auto dir = std::filesystem::temp_directory_path() / ("fibrane-test-" + name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  made.push_back(dir);
  return dir;
}

}  // namespace fibrane::testing
