#include "model/run.hpp"

#include <omp.h>

#include <chrono>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "io/progress.hpp"
#include "model/results.hpp"
#include "solve/linear_solver.hpp"
#include "solve/load_stepping.hpp"

namespace fibrane::model {

RunSummary run_case(Case& c, const RunOptions& options) {
  solve::set_thread_count(options.threads);  // OpenMP and OpenBLAS; 0 keeps the defaults
  const auto start = std::chrono::steady_clock::now();
  Model& m = *c.model;
  RunSummary summary;
  summary.directory = options.output_directory.empty() ? c.output.directory : options.output_directory;
  RunOutput out(c, summary.directory);
  auto solver = solve::make_linear_solver(c.run.linear_solver, m.symmetric());

  Eigen::VectorXd q = m.initial_unknowns();
  m.evaluate(q, c.run.steps.t_start, false);
  const solve::StepReport initial{0, c.run.steps.t_start, 0.0, 0, m.residual().norm(), 0, {}};
  out.write_history(m, initial);
  out.write_vtk(m, initial);

  std::ostringstream quiet_sink;
  io::ProgressLine progress = options.quiet ? io::ProgressLine(c.run.steps.t_end, quiet_sink, false)
                                            : io::ProgressLine(c.run.steps.t_end);
  if (c.run.linear) {
    // The linearised problem: one Newton step from the reference configuration at full load.
    const double t = c.run.steps.t_end;
    m.evaluate(q, t, true);
    solver->analyze(m.tangent());
    if (!solver->factorize(m.tangent())) throw std::runtime_error("the linear system is singular");
    q -= solver->solve(m.residual());
    m.evaluate(q, t, false);
    const solve::StepReport report{1, t, t, 1, m.residual().norm(), 0, {}};
    out.write_history(m, report);
    out.write_vtk(m, report);
    summary.result = {solve::Outcome::reached_end, t, 1, 1, "linear analysis"};
    summary.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    out.write_summary(m, summary.result, summary.wall_seconds, solver->name());
    return summary;
  }
  solve::NewtonOptions newton = c.run.newton;
  newton.verbose = options.newton_log;
  double peak = 0.0;
  if (!c.run.stop_column.empty()) peak = std::abs(out.last_value(c.run.stop_column));
  bool stopped_by_condition = false;
  const double t_last = c.run.steps.t_end - 1e-12 * std::max(1.0, std::abs(c.run.steps.t_end));
  solve::StepControl steps = c.run.steps;
  steps.stop_at_limit_point = c.run.stop_at_limit_point;
  summary.result = solve::LoadStepping(steps, newton).run(m, q, *solver, [&](const solve::StepReport& r, const Eigen::VectorXd&) {
        out.write_history(m, r);
        bool stop = false;
        if (!c.run.stop_column.empty()) {
          const double v = std::abs(out.last_value(c.run.stop_column));
          peak = std::max(peak, v);
          stop = v < c.run.stop_fraction * peak;
        }
        if (r.t >= t_last || stop || out.vtk_due(r.step)) out.write_vtk(m, r);
        progress.update(r.step, r.t, r.iterations, r.residual_norm);
        if (stop) stopped_by_condition = true;
        return !stop;
      });
  if (stopped_by_condition) {
    summary.result.message = "stopped: " + c.run.stop_column + " fell below " + std::to_string(c.run.stop_fraction) +
                             " of its peak";
  }
  progress.finish(summary.result.completed() ? "done" : "stopped: " + summary.result.message);
  summary.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.write_summary(m, summary.result, summary.wall_seconds, solver->name());
  return summary;
}

}  // namespace fibrane::model
