#include "run/run.hpp"

#include <omp.h>

#include <chrono>
#include <cmath>
#include <iostream>
#include <memory>
#include <sstream>

#include "common/format.hpp"
#include "io/progress.hpp"
#include "model/observables.hpp"
#include "output/run_output.hpp"
#include "run/limit_points.hpp"
#include "run/run_checks.hpp"
#include "solve/arc_length.hpp"
#include "solve/linear_solver.hpp"
#include "solve/linear_step.hpp"
#include "solve/load_stepping.hpp"

namespace fibrane::run {

std::unique_ptr<solve::ContinuationMethod> make_method(const casefile::RunSettings& s, bool verbose) {
  solve::NewtonOptions newton = s.newton;
  newton.verbose = verbose;
  switch (s.method) {
    case casefile::Method::linear: return std::make_unique<solve::LinearStep>(s.steps.t_start, s.steps.t_end);
    case casefile::Method::arc_length: {
      solve::ArcLengthControl control = s.arc_length;  // the run's range and step budget are those of `steps`
      control.t_start = s.steps.t_start;
      control.t_end = s.steps.t_end;
      control.max_steps = s.steps.max_steps;
      return std::make_unique<solve::ArcLength>(control, newton);
    }
    case casefile::Method::dynamics: return std::make_unique<solve::GeneralizedAlpha>(s.steps, newton, s.dynamics);
    case casefile::Method::load_stepping: break;
  }
  return std::make_unique<solve::LoadStepping>(s.steps, newton);
}

namespace {

// The case's stop rule: |quantity| below a fraction of its largest magnitude so far (e.g. the adhesion
// energy at pull-off). The quantity is read from the model, like the history column of the same name.
class StopRule {
 public:
  StopRule(const casefile::RunSettings& s, const model::Model& m) : fraction_(s.stop_fraction) {
    for (const auto& o : model::observables(m))
      if (o.name == s.stop_column) quantity_ = o;
    if (quantity_.value) peak_ = std::abs(quantity_.value(m));
  }
  // True when the run should stop after the model's current state.
  bool reached(const model::Model& m) {
    if (!quantity_.value) return false;
    const double v = std::abs(quantity_.value(m));
    peak_ = std::max(peak_, v);
    return v < fraction_ * peak_;
  }
  std::string message() const {
    return "stopped: " + quantity_.name + " fell below " + format_number(fraction_) + " of its peak";
  }

 private:
  model::Observable quantity_;
  double fraction_, peak_ = 0;
};

}  // namespace

RunSummary run_case(casefile::Case& c, const RunOptions& options) {
  solve::set_thread_count(options.threads);  // OpenMP and OpenBLAS; 0 keeps the defaults
  const auto start = std::chrono::steady_clock::now();
  model::Model& m = *c.model;
  RunSummary summary;
  summary.directory = options.output_directory.empty() ? c.output.directory : options.output_directory;
  check_output_directory(c, summary.directory);
  check_finite_model(c);
  output::RunOutput out(c, summary.directory);
  auto solver = solve::make_linear_solver(c.run.linear_solver, m.symmetric());
  auto method = make_method(c.run, options.newton_log);

  Eigen::VectorXd q = m.initial_unknowns();
  std::string prepare_failure;  // e.g. no static equilibrium for a dynamic run to start from
  const bool prepared = method->prepare(m, q, *solver, prepare_failure);
  m.evaluate(q, c.run.steps.t_start, false);
  solve::StepReport initial;
  initial.t = c.run.steps.t_start;
  initial.residual_norm = m.residual().norm();
  // Warnings go to stderr even with --quiet: they say that an output is not what its name suggests.
  auto warn = [&]() {
    for (const auto& w : out.take_warnings()) std::cerr << "\nfibrane: warning: " << w << "\n";
  };
  out.write_history(m, initial);
  warn();
  out.write_vtk(m, initial);
  StopRule stop_rule(c.run, m);
  std::ostringstream quiet_sink;
  io::ProgressLine progress = options.quiet ? io::ProgressLine(c.run.steps.t_end, quiet_sink, false)
                                            : io::ProgressLine(c.run.steps.t_end);
  progress.set_monotone(c.run.method != casefile::Method::arc_length);
  bool stopped = false;
  LimitPointFinder limits(model::observables(m));
  const double t_last = c.run.steps.t_end - 1e-12 * std::max(1.0, std::abs(c.run.steps.t_end));
  // A dynamic run's support forces include inertia: the time integrator's reactions replace the residual.
  const auto* dynamics = dynamic_cast<const solve::GeneralizedAlpha*>(method.get());
  summary.result.t_reached = c.run.steps.t_start;
  summary.result.message = prepare_failure;
  if (prepared) summary.result = method->run(m, q, *solver, [&](const solve::StepReport& r, const Eigen::VectorXd&) {
    if (dynamics) m.set_reactions(&dynamics->state().reaction);
    out.write_history(m, r);
    warn();
    if (limits.add(r, m) && !options.quiet)
      std::cerr << "\nfibrane: limit point (" << (limits.last().maximum ? "maximum" : "minimum") << " of t) at t = "
                << format_number(limits.last().t) << " in step " << r.step << "\n";
    stopped = stop_rule.reached(m);
    if (r.t >= t_last || stopped || out.vtk_due(r.step)) out.write_vtk(m, r);
    progress.update(r.step, r.t, r.iterations, r.residual_norm);
    return !stopped;
  });
  m.set_reactions(nullptr);
  if (stopped) summary.result.message = stop_rule.message();
  progress.finish(summary.result.completed() ? "done" : "stopped: " + summary.result.message);
  summary.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  io::JsonValue extra = io::JsonValue::object();
  io::JsonValue& points = extra["limit_points"];
  points = io::JsonValue::array();
  for (const auto& p : limits.found()) {
    io::JsonValue j = io::JsonValue::object();
    j.set("t", p.t).set("kind", p.maximum ? "maximum" : "minimum").set("step", p.step).set("path_length", p.path_length);
    io::JsonValue values = io::JsonValue::object();
    for (const auto& [name, value] : p.values) values.set(name, value);
    j.set("values", std::move(values));
    points.push_back(std::move(j));
  }
  out.write_summary(m, summary.result, summary.wall_seconds, solver->name(), &extra);
  return summary;
}

}  // namespace fibrane::run
