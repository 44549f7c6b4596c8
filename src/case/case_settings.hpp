#pragma once
// The run settings of a case file: the 'steps' block (continuation, Newton, linear solver, stop rule) and
// the 'output' block. Every numeric key is checked against its valid range where it is read.
#include <optional>
#include <string>

#include "case/case.hpp"
#include "io/yaml_input.hpp"

namespace fibrane::casefile {

// Reads 'steps' (absent: the defaults) into `run`.
void read_steps(RunSettings& run, const std::optional<io::YamlNode>& node);
// Reads 'output' (absent: the defaults, directory out/<case name>) into `out`.
void read_output(OutputSettings& out, const std::optional<io::YamlNode>& node, const std::string& case_name);

}  // namespace fibrane::casefile
