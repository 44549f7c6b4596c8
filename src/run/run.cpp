#include "run/run.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <csignal>
#include <cmath>
#include <cstdint>
#include <exception>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "common/error.hpp"
#include "common/format.hpp"
#include "io/progress.hpp"
#include "model/observables.hpp"
#include "output/directory_lock.hpp"
#include "output/run_output.hpp"
#include "output/vtk_pieces.hpp"
#include "run/checkpoint.hpp"
#include "run/interrupt.hpp"
#include "run/limit_points.hpp"
#include "run/memory_report.hpp"
#include "run/partition_report.hpp"
#include "run/run_checks.hpp"
#include "case/case_methods.hpp"
#include "linalg/linear_solver.hpp"

namespace fibrane::run {

namespace {

// The case's linear solver, logging its Krylov solves with --newton-log.
std::unique_ptr<solve::LinearSolver> make_solver(solve::LinearSolverSettings settings, bool verbose, bool symmetric) {
  settings.verbose = verbose;
  return solve::make_linear_solver(settings, symmetric);
}

}  // namespace

std::unique_ptr<solve::ContinuationMethod> make_method(const casefile::RunSettings& s, bool verbose) {
  solve::NewtonOptions newton = s.newton;
  newton.verbose = verbose;
  return casefile::method_entry(s.method).make(s, newton);
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
  double peak() const { return peak_; }  // the largest magnitude so far (kept in checkpoints)
  void set_peak(double peak) { peak_ = peak; }

 private:
  model::Observable quantity_;
  double fraction_, peak_ = 0;
};

// One run of a case: the continuation method, the output, the checks after every step and the
// checkpoints.
class Run {
 public:
  Run(casefile::Case& c, const RunOptions& options, const std::string& directory,
      const std::optional<RunCheckpoint>& restart)
      : c_(c), m_(*c.model), options_(options), method_(make_method(c.run, options.newton_log)),
        solver_(options.make_solver ? options.make_solver(m_.symmetric())
                                    : make_solver(c.run.linear_solver, options.newton_log, m_.symmetric())),
        writes_(!m_.distribution() || m_.distribution()->rank() == 0),
        q_(m_.initial_unknowns()), stop_rule_(c.run, m_),
        limits_(model::observables(m_)),
        progress_(options.quiet || !writes_ ? io::ProgressLine(c.run.steps.t_end, quiet_sink_, false)
                                            : io::ProgressLine(c.run.steps.t_end)) {
    progress_.set_monotone(!casefile::method_entry(c.run.method).traits.path_parametrised);
    // A checkpoint that does not fit fails here, before the output directory is touched.
    if (restart) resume(*restart);
    // A distributed run's processes hold the same state: the first one writes.
    if (writes_) out_ = std::make_unique<output::RunOutput>(c, directory, restart ? &restart->output : nullptr);
    if (c.output.vtk && c.output.vtk_pieces)
      pieces_ = std::make_unique<output::VtkPieces>(c, directory, m_, out_.get(), restart ? &restart->output : nullptr);
    if (restart) {
      if (!options.quiet && writes_)
        std::cerr << "fibrane: restarting from the checkpoint of step " << restart->step
                  << " (t = " << format_number(restart->t) << ") in " << directory << "\n";
    } else {
      prepared_ = method_->prepare(m_, q_, *solver_, prepare_failure_);
      m_.evaluate(q_, c.run.steps.t_start, false);
      solve::StepReport initial;
      initial.t = c.run.steps.t_start;
      initial.residual_norm = m_.residual().norm();
      if (out_) {
        out_->write_history(m_, initial);
        warn();
        out_->write_vtk(m_, initial);
      }
      if (pieces_) pieces_->write(m_, initial);
    }
  }

  // Marches to the end; `summary` gets the result.
  void march(RunSummary& summary);
  // summary.json, with `extra` members. If the run ended on an error and the summary cannot be written
  // either, the run's error is rethrown (it says what went wrong first).
  void write_summary(const RunSummary& summary, const io::JsonValue& extra) {
    try {
      io::JsonValue members = extra;
      members.set("factorizations", static_cast<std::int64_t>(solver_->factorizations()));
      members.set("linear_solver_statistics", solver_->analysis_summary());
      if (out_) out_->write_summary(m_, summary.result, summary.wall_seconds, solver_->name(), &members);
    } catch (...) {
      if (error_) std::rethrow_exception(error_);
      throw;
    }
  }
  const std::vector<LimitPoint>& limit_points() const { return limits_.found(); }
  // The checkpoints written by this run: count, wall time spent writing them, size of the last one.
  io::JsonValue checkpoint_json() const {
    io::JsonValue j = io::JsonValue::object();
    j.set("written", checkpoints_).set("seconds", checkpoint_seconds_).set("bytes", checkpoint_bytes_);
    return j;
  }

 private:
  void resume(const RunCheckpoint& k);
  bool on_step(const solve::StepReport& r);
  // Warnings of the steps just written go to stderr even with --quiet: they say that an output is not
  // what its name suggests (lost interaction points).
  void warn() {
    if (!out_) return;
    for (const auto& w : out_->take_warnings()) std::cerr << "\nfibrane: warning: " << w << "\n";
  }
  void write_checkpoint(int step, double t, bool completed = false);
  int agreed_signal() const;

  casefile::Case& c_;
  model::Model& m_;
  const RunOptions& options_;
  std::unique_ptr<solve::ContinuationMethod> method_;
  std::unique_ptr<output::RunOutput> out_;
  std::unique_ptr<output::VtkPieces> pieces_;  // on every process, with output.vtk_pieces
  std::unique_ptr<solve::LinearSolver> solver_;
  bool writes_;  // this process writes the output (not a distributed run's other processes)
  Eigen::VectorXd q_;
  StopRule stop_rule_;
  LimitPointFinder limits_;
  std::ostringstream quiet_sink_;
  io::ProgressLine progress_;
  bool stopped_ = false, interrupted_ = false;  // by the stop rule, by a signal
  bool stopped_by_caller_ = false;              // RunOptions::on_step returned false
  int signal_ = 0;  // the signal that interrupted the run (agreed by a distributed run's processes)
  bool prepared_ = true;  // the method found its starting state (ContinuationMethod::prepare)
  std::string prepare_failure_;
  std::exception_ptr error_;  // the exception that ended march(), if one did
  int last_checkpoint_ = -1, last_step_ = 0, checkpoints_ = 0;
  double checkpoint_seconds_ = 0;
  std::size_t checkpoint_bytes_ = 0;
  double last_t_ = 0;
};

void Run::resume(const RunCheckpoint& k) {
  if (k.method_name != method_->name())
    throw InputError("checkpoint: written by the " + k.method_name + " method, the case asks for " + method_->name());
  q_ = k.q;
  m_.restore_state(k.model);
  try {
    method_->restore(k.method);
  } catch (const std::out_of_range&) {
    throw InputError("checkpoint: the " + k.method_name + " method's state in it is incomplete");
  }
  stop_rule_.set_peak(k.stop_peak);
  limits_.restore(k.limit_points);
  last_checkpoint_ = last_step_ = k.step;
  last_t_ = k.t;
}

void Run::write_checkpoint(int step, double t, bool completed) {
  if (!out_) return;  // a distributed run's other processes
  const auto start = std::chrono::steady_clock::now();
  RunCheckpoint k;
  k.step = step;
  k.t = t;
  k.q = q_;
  k.method_name = method_->name();
  k.method = method_->save();
  k.model = m_.save_state();
  k.output = out_->position();
  k.stop_peak = stop_rule_.peak();
  k.limit_points = limits_.save();
  k.completed = completed;
  checkpoint_bytes_ = run::write_checkpoint(out_->directory(), c_, k);
  last_checkpoint_ = step;
  ++checkpoints_;
  checkpoint_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The signal received since the run started, or 0. A distributed run's processes agree (one collective
// sum per step): a signal to any of them ends the run on all after the same step, SIGTERM before SIGINT
// if both came. A batch system signals the processes of a job at slightly different moments.
int Run::agreed_signal() const {
  const int own = InterruptHandlers::received();
  const solve::Distribution* d = m_.distribution();
  if (!d || d->size() == 1) return own;
  std::array<double, 2> received{own == SIGINT ? 1.0 : 0.0, own == SIGTERM ? 1.0 : 0.0};
  d->sum(received);
  return received[1] > 0 ? SIGTERM : received[0] > 0 ? SIGINT : 0;
}

bool Run::on_step(const solve::StepReport& r) {
  // A dynamic run's support forces include inertia: the time integrator's reactions replace the residual.
  if (const Eigen::VectorXd* reactions = method_->reactions()) m_.set_reactions(reactions);
  if (out_) out_->write_history(m_, r);
  warn();
  if (limits_.add(r, m_) && !options_.quiet && writes_)
    std::cerr << "\nfibrane: limit point (" << (limits_.last().maximum ? "maximum" : "minimum") << " of t) at t = "
              << format_number(limits_.last().t) << " in step " << r.step << "\n";
  stopped_ = stop_rule_.reached(m_);
  const double t_end = c_.run.steps.t_end;
  const double t_last = t_end - 1e-12 * std::max(1.0, std::abs(t_end));
  if (r.t >= t_last || stopped_ || (c_.output.vtk && r.step % c_.output.vtk_every == 0)) {
    if (out_) out_->write_vtk(m_, r);
    if (pieces_) pieces_->write(m_, r);
  }
  last_step_ = r.step;
  last_t_ = r.t;
  if (!stopped_ && options_.on_step && !options_.on_step(r, q_, m_)) stopped_by_caller_ = true;
  const int every = c_.output.checkpoint_every;
  // A signal received by now (while the step was solved, its output written or the caller's hook ran) ends
  // the run here.
  signal_ = agreed_signal();
  interrupted_ = signal_ != 0;
  if ((every > 0 && r.step % every == 0) || interrupted_) write_checkpoint(r.step, r.t);
  progress_.update(r.step, r.t, r.iterations, r.residual_norm);
  return !stopped_ && !interrupted_ && !stopped_by_caller_;
}

void Run::march(RunSummary& summary) {
  InterruptHandlers handlers;
  if (!prepared_) {
    summary.result.t_reached = c_.run.steps.t_start;
    summary.result.message = prepare_failure_;
  } else {
    try {
      summary.result = method_->run(m_, q_, *solver_, [&](const solve::StepReport& r, const Eigen::VectorXd& q) {
        q_ = q;
        return on_step(r);
      });
    } catch (const InputError&) {
      throw;
    } catch (const std::exception& e) {
      // A failure no step anticipated (a bug, an exhausted resource): the run ends as failed after its last
      // finished step, and summary.json says why. A distributed run's process leaves instead (the others may
      // wait for it in a collective operation; mpirun ends them).
      if (m_.distribution()) throw;
      error_ = std::current_exception();
      summary.result.outcome = solve::Outcome::failed;
      summary.result.t_reached = last_t_;
      summary.result.steps = last_step_;
      summary.result.message = "error after step " + std::to_string(last_step_) + ": " + e.what();
    }
  }
  m_.set_reactions(nullptr);
  summary.interrupted_by = interrupted_ ? signal_ : 0;
  // A run that ran out of steps can be continued with a larger budget, an interrupted one as it was:
  // their last step is checkpointed.
  const bool out_of_steps = summary.result.outcome == solve::Outcome::max_steps;
  if ((out_of_steps || summary.interrupted_by) && last_checkpoint_ != last_step_) write_checkpoint(last_step_, last_t_);
  // A completed run's checkpoint says so: a restart would march past the end (or the stop rule). With
  // checkpoint_every 0 a run writes none unless it has one already (it continues an interrupted run).
  const bool has_checkpoint = c_.output.checkpoint_every > 0 || last_checkpoint_ >= 0;
  if (summary.result.completed() && !summary.interrupted_by && has_checkpoint)
    write_checkpoint(last_step_, last_t_, true);
  if (stopped_) summary.result.message = stop_rule_.message();
  if (stopped_by_caller_)
    summary.result.message = "stopped by the step callback after step " + std::to_string(last_step_) + " (t = " +
                             format_number(last_t_) + ")";
  summary.q = q_;
  if (summary.interrupted_by) {
    summary.result.message = std::string("interrupted at t = ") + format_number(last_t_) + " by " +
                             signal_name(summary.interrupted_by) + " after step " + std::to_string(last_step_);
    summary.result.outcome = solve::Outcome::interrupted;
  }
  progress_.finish(summary.result.completed() ? "done" : "stopped: " + summary.result.message);
}

io::JsonValue limit_points_json(const std::vector<LimitPoint>& found) {
  io::JsonValue points = io::JsonValue::array();
  for (const auto& p : found) {
    io::JsonValue j = io::JsonValue::object();
    j.set("t", p.t).set("kind", p.maximum ? "maximum" : "minimum").set("step", p.step).set("path_length", p.path_length);
    io::JsonValue values = io::JsonValue::object();
    for (const auto& [name, value] : p.values) values.set(name, value);
    j.set("values", std::move(values));
    points.push_back(std::move(j));
  }
  return points;
}

}  // namespace

RunSummary run_case(casefile::Case& c, const RunOptions& options) {
  solve::set_thread_count(options.threads);  // OpenMP and OpenBLAS; 0 keeps the defaults
  const auto start = std::chrono::steady_clock::now();
  InUsePeak in_use;
  RunSummary summary;
  summary.directory = options.output_directory.empty() ? c.output.directory : options.output_directory;
  // One run per directory, from before its first write to its exit; a distributed run's first process
  // writes and locks. A run refused before it starts leaves no lock file or directory behind.
  output::DirectoryLock lock;
  std::optional<RunCheckpoint> restart;
  std::string refused;  // why this process cannot start the run (the lock, the checkpoint)
  const solve::Distribution* d = c.model->distribution();
  try {
    // Only the writing process probes the directory: probes of several processes would race (one
    // removes the directory it created while another probes a file in it).
    const bool writes = !d || d->rank() == 0;
    if (writes)
      check_output_directory(c, summary.directory,
                             options.output_directory.empty() ? "output.directory" : options.restart ? "--restart" : "-o");
    check_finite_model(c);
    if (writes) {
      try {
        lock = output::DirectoryLock(summary.directory, !options.restart);
      } catch (const InputError& e) {
        throw InputError(c.path + ": " + e.what());
      }
      if (!lock.warning().empty()) std::cerr << "fibrane: warning: " << lock.warning() << "\n";
    }
    // Every process reads the checkpoint (and checks history.csv) before the first one writes.
    if (options.restart) restart = read_checkpoint(summary.directory, c);
  } catch (const InputError& e) {
    refused = e.what();
  }
  // A distributed run's processes refuse it together, with the first process's reason.
  if (d) refused = d->first_text(refused);
  if (!refused.empty()) {
    lock.abandon();
    throw InputError(refused);
  }
  std::unique_ptr<Run> started;
  try {
    c.model->evaluate(c.model->initial_unknowns(), c.run.steps.t_start, false);  // the initial state
    started = std::make_unique<Run>(c, options, summary.directory, restart);
  } catch (const InputError&) {
    lock.abandon();
    throw;
  }
  Run& run = *started;
  run.march(summary);
  summary.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  io::JsonValue extra = io::JsonValue::object();
  extra["limit_points"] = limit_points_json(run.limit_points());
  extra.set("restarted_from_step", restart ? restart->step : -1);
  extra.set("checkpoints", run.checkpoint_json());
  if (summary.interrupted_by) extra.set("interrupted", signal_name(summary.interrupted_by));
  if (d) extra.set("partition", partition_json(c.model->partition()));
  extra.set("memory", memory_json(c.memory_estimate, in_use, d));
  run.write_summary(summary, extra);
  return summary;
}

}  // namespace fibrane::run
