#include "case/case_steps.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "case/case_limits.hpp"
#include "case/case_methods.hpp"

namespace fibrane::casefile {
namespace {


// An optional number key in the range given by lo, hi and whether each end is open; `fallback` when absent.
double number_in(const io::YamlNode& map, const std::string& key, double lo, double hi, bool lo_open, bool hi_open,
                 double fallback) {
  const auto v = map.optional(key);
  return v ? v->in_range(lo, hi, lo_open, hi_open) : fallback;
}

// A first step `step` (dt, ds) at least its smallest allowed size `minimum` (dt_min, ds_min): a given minimum
// is reported at its key; the default one at the step's key, since the step is what is too small.
void check_not_below_minimum(const io::YamlNode& map, const char* step, double value, const char* minimum_key,
                             double minimum) {
  if (value >= minimum) return;
  if (map.has(minimum_key)) map[minimum_key].fail(std::string(minimum_key) + " <= " + step);
  map[step].fail_message(fmt::format("expected {} >= {} = {} (the default smallest step; give a smaller {} to "
                                     "allow it), got {}",
                                     step, minimum_key, minimum, minimum_key, value));
}

void read_newton(solve::NewtonOptions& newton, const io::YamlNode& node) {
  newton.max_iterations = optional_int_in(node, "max_iterations", 1, 1000, newton.max_iterations,
                                 "the most Newton iterations per step");
  newton.stall_iterations = optional_int_in(node, "stall_iterations", 0, 1000, newton.stall_iterations,
                                           "the most Newton updates without halving |r| (0: no limit)");
  newton.tol_relative = number_in(node, "tolerance", 0.0, 1.0, true, true, newton.tol_relative);
  newton.tol_absolute = number_in(node, "tolerance_absolute", 0.0, INFINITY, false, true, newton.tol_absolute);
  newton.tol_increment = number_in(node, "tolerance_increment", 0.0, 1.0, false, true, newton.tol_increment);
  newton.line_search = optional_int_in(node, "line_search", 0, 30, newton.line_search,
                              "the most halvings of a Newton update (0: none)");
  newton.reuse_below = number_in(node, "reuse_factorization", 0.0, 1.0, false, true, newton.reuse_below);
  newton.reuse_first = node.get("reuse_first_factorization", newton.reuse_first);
  newton.local_share = number_in(node, "local_first_update", 0.0, 0.5, false, true, newton.local_share);
  newton.local_newton = optional_int_in(node, "local_newton", 0, 20, newton.local_newton,
                                        "the most updates of a local Newton solve (0: none)");
  if (newton.reuse_first && !(newton.reuse_below > 0))
    node["reuse_first_factorization"].fail_message("needs reuse_factorization > 0 (the reuse rule it extends)");
}

// The directory for MUMPS's factor files that `node` names (or the temporary directory, $TMPDIR or /tmp,
// for `directory` empty); it must exist and be writable.
std::string factor_directory(const io::YamlNode& node, std::string directory) {
  if (directory.empty()) {
    const char* tmp = std::getenv("TMPDIR");
    directory = tmp && *tmp ? tmp : "/tmp";
  }
  constexpr size_t kMumpsPathLength = 255;  // OOC_TMPDIR is char[256]
  if (directory.size() > kMumpsPathLength)
    node.fail_message(fmt::format("the directory '{}' has a name longer than MUMPS's {} characters", directory,
                                  kMumpsPathLength));
  std::error_code error;
  if (!std::filesystem::is_directory(directory, error))
    node.fail_message("the directory '" + directory + "' for the out-of-core factor files does not exist");
  if (::access(directory.c_str(), W_OK | X_OK) != 0)
    node.fail_message("the directory '" + directory + "' for the out-of-core factor files is not writable");
  return directory;
}

// steps.out_of_core: true (the factor always in files of the temporary directory), false, a directory
// (always, there), when_needed (in memory, and in files of the temporary directory where a factorisation
// does not fit), or a map {when: always | needed, directory: D}.
void read_out_of_core(solve::LinearSolverSettings& ls, const io::YamlNode& node) {
  ls.out_of_core_when_needed = false;
  ls.out_of_core_directory.clear();
  if (node.is_map()) {
    const bool needed = node.has("when") && node["when"].as_choice({"always", "needed"}) == "needed";
    std::string directory;
    if (auto d = node.optional("directory")) {
      directory = d->as_string();
      if (directory.empty()) d->fail("the directory for the factor's files");
    }
    node.reject_unknown_keys();
    ls.out_of_core_directory = factor_directory(node, directory);
    ls.out_of_core_when_needed = needed;
    return;
  }
  static const char* const words[] = {"true", "false", "yes", "no", "on", "off", "y", "n"};
  const std::string text = node.as_string();
  std::string lower = text;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  if (text.empty()) node.fail("true, false, when_needed, or the directory for the factor's files");
  if (lower == "when_needed") {
    ls.out_of_core_directory = factor_directory(node, {});
    ls.out_of_core_when_needed = true;
  } else if (std::find(std::begin(words), std::end(words), lower) == std::end(words)) {
    ls.out_of_core_directory = factor_directory(node, text);
  } else if (node.as_bool()) {
    ls.out_of_core_directory = factor_directory(node, {});
  }
}

// steps.solver, precision, low_rank, out_of_core, split and krylov (a map, or true for its defaults).
void read_linear_solver(solve::LinearSolverSettings& ls, const io::YamlNode& node) {
  if (node.has("solver"))
    ls.kind = node["solver"].as_choice({"auto", "cholmod", "ldlt", "mumps", "mumps-lu", "umfpack", "umfpack64"});
  if (node.has("precision")) ls.precision = node["precision"].as_choice({"double", "single"});
  ls.low_rank = number_in(node, "low_rank", 0.0, 0.1, false, true, ls.low_rank);
  if (auto k = node.optional("krylov")) {
    if (k->is_map()) {
      ls.krylov = true;
      ls.krylov_tolerance = number_in(*k, "tolerance", 0.0, 0.1, true, true, ls.krylov_tolerance);
      ls.krylov_max_iterations = optional_int_in(*k, "max_iterations", 1, 1000, ls.krylov_max_iterations,
                                                 "the Krylov iterations of a solve before the factorisation is renewed");
      k->reject_unknown_keys();
    } else {
      ls.krylov = k->as_bool();
    }
  }
  if (auto o = node.optional("out_of_core")) read_out_of_core(ls, *o);
  if (auto v = node.optional("split")) {
    ls.split = v->as_bool();
    if (ls.split && ls.kind != "auto" && ls.kind != "cholmod")
      v->fail_message("split is CHOLMOD's Cholesky in two halves: it needs solver auto or cholmod, not " + ls.kind);
  }
  const bool always_out_of_core = !ls.out_of_core_directory.empty() && !ls.out_of_core_when_needed;
  const bool mumps_only = ls.precision == "single" || ls.low_rank > 0 || always_out_of_core;
  if (ls.split && mumps_only)
    node["split"].fail_message("split is CHOLMOD's Cholesky in two halves; single-precision, low-rank and "
                               "out-of-core factorisations are MUMPS's (out_of_core: when_needed keeps it)");
  if ((mumps_only || ls.out_of_core_when_needed) && !(ls.kind == "auto" || ls.kind == "mumps" || ls.kind == "mumps-lu")) {
    const char* key = node.has("precision") ? "precision" : node.has("low_rank") ? "low_rank" : "out_of_core";
    node[key].fail_message("single-precision, low-rank and out-of-core factorisations are MUMPS's: they need "
                           "solver auto, mumps or mumps-lu, not " + ls.kind);
  }
}

}  // namespace

// steps.arc_length: {ds, ds_min, ds_max, desired_iterations, growth, cutback, scale, corrector, t_min, t_max,
// max_path_length, direction}.
void read_arc_length(solve::ArcLengthControl& a, const io::YamlNode& map, double start) {
  const io::YamlNode* node = &map;
  if (auto v = node->optional("ds")) a.ds_initial = v->positive();
  if (auto v = node->optional("ds_min")) a.ds_min = v->positive();
  a.ds_max = node->has("ds_max") ? (*node)["ds_max"].positive() : std::max(a.ds_max, a.ds_initial);
  check_not_below_minimum(*node, "ds", a.ds_initial, "ds_min", a.ds_min);
  if (a.ds_max < a.ds_initial) (*node)["ds_max"].fail("ds_max >= ds");
  a.desired_iterations = optional_int_in(*node, "desired_iterations", 1, 1000, a.desired_iterations,
                                "the Newton iterations a step aims at");
  if (auto v = node->optional("growth")) a.growth = v->in_range(1.0, 10.0, false, false);
  if (auto v = node->optional("cutback")) a.cutback = v->in_range(0.0, 1.0, true, true);
  if (auto v = node->optional("scale")) {  // auto, cylindrical, or a positive number
    const std::string text = v->is_scalar() ? v->as_string() : "";
    if (text == "auto") a.load_scale = -1.0;
    else if (text == "cylindrical") a.load_scale = 0.0;
    else a.load_scale = v->positive();
  }
  if (auto v = node->optional("corrector"))
    a.corrector = v->as_choice({"quadratic", "linearized"}) == "quadratic" ? solve::ArcLengthCorrector::quadratic
                                                                           : solve::ArcLengthCorrector::linearized;
  a.t_min = node->get("t_min", a.t_min);
  a.t_max = node->get("t_max", a.t_max);
  if (a.t_min > a.t_max) (*node)["t_max"].fail(fmt::format("t_max >= t_min = {}", a.t_min));
  if (a.t_min > start) (*node)["t_min"].fail(fmt::format("t_min <= {} (the path starts at t = {})", start, start));
  if (a.t_max < start) (*node)["t_max"].fail(fmt::format("t_max >= {} (the path starts at t = {})", start, start));
  if (auto v = node->optional("max_path_length")) a.max_path_length = v->positive();
  if (auto v = node->optional("direction"))
    a.initial_direction = v->as_choice({"increasing", "decreasing"}) == "increasing" ? 1 : -1;
  node->reject_unknown_keys();
}

// steps.dynamics: {rho_inf: r | scheme: trapezoidal, mass_damping, error_tolerance, energy_tolerance, start: rest | equilibrium | static}.
void read_dynamics(solve::TransientOptions& d, const io::YamlNode& map) {
  const io::YamlNode* node = &map;
  if (node->has("rho_inf") && node->has("scheme"))
    (*node)["scheme"].fail_message("give either 'rho_inf' or 'scheme: trapezoidal'");
  if (auto r = node->optional("rho_inf"))
    d.parameters = solve::GeneralizedAlphaParameters::chung_hulbert(r->in_range(0.0, 1.0, false, false));
  if (auto sc = node->optional("scheme")) {
    sc->as_choice({"trapezoidal"});
    d.parameters = solve::GeneralizedAlphaParameters::trapezoidal();
  }
  if (auto v = node->optional("mass_damping")) d.mass_damping = v->non_negative();
  if (auto v = node->optional("error_tolerance")) d.error_tolerance = v->in_range(0.0, 1.0, true, false);
  if (auto v = node->optional("energy_tolerance")) d.energy_tolerance = v->positive();
  if (auto v = node->optional("start")) {
    const std::string start = v->as_choice({"rest", "equilibrium", "static"});
    d.start = start == "rest"     ? solve::TransientOptions::Start::rest
              : start == "static" ? solve::TransientOptions::Start::static_equilibrium
                                  : solve::TransientOptions::Start::solve;
  }
  node->reject_unknown_keys();
}

void read_steps(RunSettings& run, const std::optional<io::YamlNode>& node) {
  if (!node) return;
  if (!node->is_map()) node->fail("a map of step settings (t_end, dt, ...)");
  auto& s = run.steps;
  s.t_end = number_in(*node, "t_end", s.t_start, INFINITY, true, true, s.t_end);
  s.dt_initial = number_in(*node, "dt", 0.0, INFINITY, true, true, s.dt_initial);
  s.dt_max = node->has("dt_max") ? (*node)["dt_max"].positive() : std::max(s.dt_max, s.dt_initial);
  s.dt_min = number_in(*node, "dt_min", 0.0, INFINITY, true, true, s.dt_min);
  check_not_below_minimum(*node, "dt", s.dt_initial, "dt_min", s.dt_min);
  if (s.dt_max < s.dt_initial) (*node)["dt_max"].fail("dt_max >= dt");
  s.easy_iterations = optional_int_in(*node, "easy_iterations", 1, 1000, s.easy_iterations,
                             "the most Newton iterations of a step that lets dt grow");
  s.growth = number_in(*node, "growth", 1.0, 100.0, false, false, s.growth);
  s.cutback = number_in(*node, "cutback", 0.0, 1.0, true, true, s.cutback);
  s.max_steps = optional_int_in(*node, "max_steps", 1, 100'000'000, s.max_steps, "the most steps of the run");
  if (auto method = node->optional("method")) {
    std::vector<std::string> names;
    for (const MethodEntry& e : continuation_methods()) names.push_back(e.name);
    run.method = method->as_choice(names);
  }
  if (auto linear = node->optional("linear")) {  // the short form of method: linear
    if (node->has("method")) linear->fail_message("give either 'linear' or 'method', not both");
    if (linear->as_bool()) run.method = "linear";
  }
  for (const MethodEntry& e : continuation_methods()) {
    if (e.controls_key.empty()) continue;
    if (auto controls = node->optional(e.controls_key)) {
      if (run.method != e.name) controls->fail_message(e.controls_what + " need 'method: " + e.name + "'");
      e.read_controls(run, *controls);
    }
  }
  if (auto stop = node->optional("stop")) {
    if (stop->has("column") || stop->has("below_fraction_of_peak")) {
      run.stop_column = (*stop)["column"].as_string();
      run.stop_fraction = (*stop)["below_fraction_of_peak"].in_range(0.0, 1.0, true, true);
    }
    s.stop_at_limit_point = stop->get("at_limit_point", false);
    stop->reject_unknown_keys();
  }
  if (node->has("predictor")) {
    const std::string predictor = (*node)["predictor"].as_choice({"secant", "quadratic", "cubic"});
    s.predictor_order = predictor == "cubic" ? 3 : predictor == "quadratic" ? 2 : 1;
    if (run.method != "load_stepping")
      (*node)["predictor"].fail_message("applies to method: load_stepping (arc_length and dynamics predict "
                                        "each step their own way)");
  }
  if (!node->get("extrapolate", true)) {
    if (node->has("predictor")) (*node)["predictor"].fail_message("a predictor needs extrapolate: true");
    s.predictor_order = 0;
  }
  // Model events (a point switching to the soft minimum) are crossed in steps of at most this share of
  // the load range (path/event_locator.hpp); 0 (the default): wherever the steps fall.
  s.event_tolerance = number_in(*node, "event_tolerance", 0.0, INFINITY, false, true, 0.0) * (s.t_end - s.t_start);
  if (node->has("event_tolerance") && run.method != "load_stepping")
    (*node)["event_tolerance"].fail_message("applies to method: load_stepping (the arc-length and dynamics steps "
                                            "cross events wherever they fall)");
  read_newton(run.newton, *node);
  // Steps at most this share of the planned dt (an event's approach and crossing) start with the last
  // converged attempt's factorisation; it extends reuse_factorization's rule across steps.
  s.reuse_in_short_steps = number_in(*node, "reuse_in_short_steps", 0.0, 1.0, false, false, 0.0);
  if (node->has("reuse_in_short_steps") && run.method != "load_stepping")
    (*node)["reuse_in_short_steps"].fail_message("applies to method: load_stepping (the arc-length and dynamics "
                                                  "steps factorise their own tangents)");
  if (s.reuse_in_short_steps > 0 && !(run.newton.reuse_below > 0))
    (*node)["reuse_in_short_steps"].fail_message("needs reuse_factorization > 0 (the reuse rule it extends)");
  for (const char* key : {"local_first_update", "local_newton"})
    if (node->has(key) && run.method != "load_stepping")
      (*node)[key].fail_message("applies to method: load_stepping (the arc-length corrector and the dynamics' "
                                "steps update globally)");
  read_linear_solver(run.linear_solver, *node);
  if (node->has("reuse_factorization") && (run.linear_solver.krylov || run.linear_solver.precision == "single" ||
                                           run.linear_solver.low_rank > 0))
    (*node)["reuse_factorization"].fail_message(
        "reuse_factorization (modified Newton) and the Krylov solves of krylov, precision: single or low_rank "
        "(which reuse factorisations as preconditioners) exclude each other: give one");
  node->reject_unknown_keys();
}

}  // namespace fibrane::casefile
