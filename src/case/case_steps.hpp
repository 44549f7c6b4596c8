#pragma once
// The `steps` block of a case file: which continuation method marches along the path, and its controls.
#include <optional>

#include "case/case.hpp"
#include "io/yaml_input.hpp"

namespace fibrane::casefile {

void read_steps(RunSettings& run, const std::optional<io::YamlNode>& node);

// The controls of the built-in methods (case/case_methods.cpp registers them): steps.arc_length (the path
// starts at t = start) and steps.dynamics.
void read_arc_length(solve::ArcLengthControl& a, const io::YamlNode& node, double start);
void read_dynamics(solve::TransientOptions& d, const io::YamlNode& node);

}  // namespace fibrane::casefile
