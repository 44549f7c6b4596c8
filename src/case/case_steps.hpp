#pragma once
// The `steps` block of a case file: which continuation method marches along the path, and its controls.
#include <optional>

#include "case/case.hpp"
#include "io/yaml_input.hpp"

namespace fibrane::casefile {

void read_steps(RunSettings& run, const std::optional<io::YamlNode>& node);

}  // namespace fibrane::casefile
