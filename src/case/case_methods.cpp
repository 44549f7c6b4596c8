#include "case/case_methods.hpp"

#include <stdexcept>

#include "case/case_steps.hpp"
#include "path/arc_length.hpp"
#include "path/generalized_alpha.hpp"
#include "path/linear_step.hpp"
#include "path/load_stepping.hpp"

namespace fibrane::casefile {

const std::vector<MethodEntry>& continuation_methods() {
  static const std::vector<MethodEntry> registry = {
      {"load_stepping", {}, "", "", nullptr,
       [](const RunSettings& s, const solve::NewtonOptions& newton) {
         return std::make_unique<solve::LoadStepping>(s.steps, newton);
       }},
      {"linear", {}, "", "", nullptr,
       [](const RunSettings& s, const solve::NewtonOptions&) {
         return std::make_unique<solve::LinearStep>(s.steps.t_start, s.steps.t_end);
       }},
      {"arc_length", {.path_parametrised = true}, "arc_length", "arc-length controls",
       [](RunSettings& s, const io::YamlNode& node) { read_arc_length(s.arc_length, node, s.steps.t_start); },
       [](const RunSettings& s, const solve::NewtonOptions& newton) {
         solve::ArcLengthControl control = s.arc_length;  // the run's range and step budget are those of `steps`
         control.t_start = s.steps.t_start;
         control.t_end = s.steps.t_end;
         control.max_steps = s.steps.max_steps;
         return std::make_unique<solve::ArcLength>(control, newton);
       }},
      {"dynamics", {.dynamic = true}, "dynamics", "time-integration controls",
       [](RunSettings& s, const io::YamlNode& node) { read_dynamics(s.dynamics, node); },
       [](const RunSettings& s, const solve::NewtonOptions& newton) {
         return std::make_unique<solve::GeneralizedAlpha>(s.steps, newton, s.dynamics);
       }},
  };
  return registry;
}

const MethodEntry& method_entry(const std::string& name) {
  for (const MethodEntry& e : continuation_methods())
    if (e.name == name) return e;
  throw std::invalid_argument("no continuation method '" + name + "'");
}

}  // namespace fibrane::casefile
