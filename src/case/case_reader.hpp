#pragma once
// Reads a YAML case file (docs/case-format.md) into a Case. Bad input throws fibrane::InputError naming
// the file, line, key and what was expected; nothing is written before the whole case has been read and
// checked.
#include <string>

#include "case/case.hpp"

namespace fibrane::casefile {

Case read_case(const std::string& path);

}  // namespace fibrane::casefile
