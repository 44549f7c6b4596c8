#pragma once
// Constraints, loads and monitors of a case file (docs/case-format.md).
#include "io/yaml_input.hpp"
#include "model/model.hpp"

namespace fibrane::casefile {

using model::Model;

void read_constraint(Model& m, const io::YamlNode& entry);
void read_load(Model& m, const io::YamlNode& entry);
void read_monitor(Model& m, const io::YamlNode& entry);
// A load function reference: the name of a function defined under 'functions' (default: ramp, f = t).
int read_function_ref(const Model& m, const io::YamlNode& entry);

}  // namespace fibrane::casefile
