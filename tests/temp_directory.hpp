#pragma once
// Temporary directories for the tests that write files: named by the test process, so that two test runs
// side by side (a CI run beside a developer's) never share one, and kept after a failure for inspection.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstddef>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace fibrane::testing {

inline std::filesystem::path process_directory(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("fibrane-test-" + name + "-" + std::to_string(::getpid()));
}

// A fresh directory for a case and its output, shared by the tests of this process that ask for the same
// name. The directories are removed when the process exits with every test passed.
inline std::filesystem::path fresh_directory(const std::string& name) {
  static std::vector<std::filesystem::path> made;
  if (made.empty())
    std::atexit([] {
      if (::testing::UnitTest::GetInstance()->Passed())
        for (const auto& dir : made) std::filesystem::remove_all(dir);
    });
  const auto dir = process_directory(name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  made.push_back(dir);
  return dir;
}

// A fresh empty directory owned by one test, removed when the test ends unless it failed.
class ScratchDir {
 public:
  ScratchDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = std::string(info->test_suite_name()) + "-" + info->name();
    for (char& c : name)
      if (c == '/') c = '_';  // parametrised tests: "Instance/Suite" and "Test/3"
    path_ = process_directory(name);
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    if (!::testing::Test::HasFailure()) std::filesystem::remove_all(path_);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  std::string file(const std::string& name) const { return (path_ / name).string(); }
  const std::filesystem::path& path() const { return path_; }
  std::size_t entry_count() const {
    std::size_t n = 0;
    for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(path_)) ++n;
    return n;
  }

 private:
  std::filesystem::path path_;
};

}  // namespace fibrane::testing
