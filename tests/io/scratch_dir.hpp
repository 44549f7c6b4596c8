#pragma once
// Small file helpers for the io tests, and their per-test scratch directory (tests/temp_directory.hpp).
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "temp_directory.hpp"

namespace fibrane::io::testing {

using fibrane::testing::ScratchDir;

inline std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

inline void write_text(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// True if /usr/bin/python3 exists and can import `module` (the VTU/JSON checks need it).
inline bool python_has(const std::string& module) {
  const std::string command = "/usr/bin/python3 -c 'import " + module + "' >/dev/null 2>&1";
  return std::system(command.c_str()) == 0;
}

}  // namespace fibrane::io::testing
