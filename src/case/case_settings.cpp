#include "case/case_settings.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "case/case_limits.hpp"

namespace fibrane::casefile {
namespace {

// An optional integer key in [lo, hi]; `fallback` when absent.
int int_in(const io::YamlNode& map, const std::string& key, int lo, int hi, int fallback, const std::string& what) {
  const auto v = map.optional(key);
  if (!v) return fallback;
  const int x = v->as_int();
  if (x < lo || x > hi) v->fail(fmt::format("{}, an integer in [{}, {}]", what, lo, hi));
  return x;
}

// An optional number key in the range given by lo, hi and whether each end is open; `fallback` when absent.
double number_in(const io::YamlNode& map, const std::string& key, double lo, double hi, bool lo_open, bool hi_open,
                 double fallback) {
  const auto v = map.optional(key);
  return v ? v->in_range(lo, hi, lo_open, hi_open) : fallback;
}

void read_stop(RunSettings& run, const io::YamlNode& stop) {
  if (stop.has("column") || stop.has("below_fraction_of_peak")) {
    run.stop_column = stop["column"].as_string();
    run.stop_fraction = stop["below_fraction_of_peak"].in_range(0.0, 1.0, true, true);
  }
  run.steps.stop_at_limit_point = stop.get("at_limit_point", false);
  stop.reject_unknown_keys();
}

void read_newton(solve::NewtonOptions& newton, const io::YamlNode& node) {
  newton.max_iterations = int_in(node, "max_iterations", 1, 1000, newton.max_iterations,
                                 "the most Newton iterations per step");
  newton.tol_relative = number_in(node, "tolerance", 0.0, 1.0, true, true, newton.tol_relative);
  newton.tol_absolute = number_in(node, "tolerance_absolute", 0.0, INFINITY, false, true, newton.tol_absolute);
  newton.tol_increment = number_in(node, "tolerance_increment", 0.0, 1.0, false, true, newton.tol_increment);
  newton.line_search = int_in(node, "line_search", 0, 30, newton.line_search,
                              "the most halvings of a Newton update (0: none)");
  newton.reuse_below = number_in(node, "reuse_factorization", 0.0, 1.0, false, true, newton.reuse_below);
}

}  // namespace

void read_steps(RunSettings& run, const std::optional<io::YamlNode>& node) {
  if (!node) return;
  if (!node->is_map()) node->fail("a map of step settings (t_end, dt, ...)");
  auto& s = run.steps;
  s.t_end = number_in(*node, "t_end", s.t_start, INFINITY, true, true, s.t_end);
  s.dt_initial = number_in(*node, "dt", 0.0, INFINITY, true, true, s.dt_initial);
  s.dt_max = node->has("dt_max") ? (*node)["dt_max"].positive() : std::max(s.dt_max, s.dt_initial);
  s.dt_min = number_in(*node, "dt_min", 0.0, INFINITY, true, true, s.dt_min);
  if (s.dt_min > s.dt_initial) (*node)["dt_min"].fail("dt_min <= dt");
  if (s.dt_max < s.dt_initial) (*node)["dt_max"].fail("dt_max >= dt");
  s.easy_iterations = int_in(*node, "easy_iterations", 1, 1000, s.easy_iterations,
                             "the most Newton iterations of a step that lets dt grow");
  s.growth = number_in(*node, "growth", 1.0, 100.0, false, false, s.growth);
  s.cutback = number_in(*node, "cutback", 0.0, 1.0, true, true, s.cutback);
  s.max_steps = int_in(*node, "max_steps", 1, 100'000'000, s.max_steps, "the most steps of the run");
  if (auto method = node->optional("method"))
    run.method = method->as_choice({"load_stepping", "linear"}) == "linear" ? Method::linear : Method::load_stepping;
  if (auto linear = node->optional("linear")) {  // the short form of method: linear
    if (node->has("method")) linear->fail_message("give either 'linear' or 'method', not both");
    if (linear->as_bool()) run.method = Method::linear;
  }
  if (auto stop = node->optional("stop")) read_stop(run, *stop);
  s.extrapolate = node->get("extrapolate", s.extrapolate);
  read_newton(run.newton, *node);
  run.linear_solver = node->has("solver") ? (*node)["solver"].as_choice({"auto", "cholmod", "ldlt", "umfpack"})
                                          : run.linear_solver;
  node->reject_unknown_keys();
}

void read_output(OutputSettings& out, const std::optional<io::YamlNode>& node, const std::string& case_name) {
  out.directory = "out/" + case_name;
  if (!node) return;
  if (!node->is_map()) node->fail("a map of output settings (directory, vtk, ...)");
  if (auto d = node->optional("directory")) {
    out.directory = d->as_string();
    if (out.directory.empty() || out.directory.find('\0') != std::string::npos)
      d->fail("a non-empty directory path");
  }
  out.vtk = node->get("vtk", out.vtk);
  out.vtk_every = int_in(*node, "vtk_every", 1, 100'000'000, out.vtk_every, "write VTK every n-th step");
  out.samples = int_in(*node, "samples", 1, kMaxSamples, out.samples, "sampling points per element edge");
  if (auto cells = node->optional("vtk_cells")) {
    const std::string which = cells->as_choice({"bezier", "sampled", "both"});
    out.bezier = which != "sampled";
    out.sampled = which != "bezier";
  }
  node->reject_unknown_keys();
}

}  // namespace fibrane::casefile
