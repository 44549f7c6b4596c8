#pragma once
// The 'output' block of a case file: directory, VTK files, sampling; every key checked where it is read.
#include <optional>
#include <string>

#include "case/case.hpp"
#include "io/yaml_input.hpp"

namespace fibrane::casefile {

// Reads 'output' (absent: the defaults, directory out/<case name>) into `out`.
void read_output(OutputSettings& out, const std::optional<io::YamlNode>& node, const std::string& case_name);

}  // namespace fibrane::casefile
