#pragma once
// The continuation methods a case can name (steps.method), each registered once in case_methods.cpp with
// its traits, the sub-block of `steps` holding its controls, and the factory that makes it. The case
// reader, the run driver and the output ask the registry, so a new method is a ContinuationMethod
// (src/path), a reader for its controls and one registration.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "case/case.hpp"
#include "io/yaml_input.hpp"
#include "path/continuation.hpp"

namespace fibrane::casefile {

// What the rest of fibrane needs to know of a method without knowing the method.
struct MethodTraits {
  // Time integration: the model gets inertia, every body needs a density, history.csv the energy account.
  bool dynamic = false;
  // t may turn back along the path (arc length): VTK series are ordered by the path length, and the
  // progress line does not assume t grows.
  bool path_parametrised = false;
};

// One continuation method of the registry.
struct MethodEntry {
  std::string name;  // the value of steps.method
  MethodTraits traits;
  // Its own sub-block of `steps` (empty: none), what the sub-block is called in messages, and its reader.
  std::string controls_key, controls_what;
  std::function<void(RunSettings&, const io::YamlNode&)> read_controls;
  // The method for a case's settings, with Newton's options (verbosity already applied).
  std::function<std::unique_ptr<solve::ContinuationMethod>(const RunSettings&, const solve::NewtonOptions&)> make;
};

// Every registered method, in the order the case format lists them.
const std::vector<MethodEntry>& continuation_methods();

// The entry named `name`; std::invalid_argument if none is.
const MethodEntry& method_entry(const std::string& name);

}  // namespace fibrane::casefile
