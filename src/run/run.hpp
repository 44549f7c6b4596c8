#pragma once
// Runs a case: the continuation method the case chose marches along the model's path, and after every
// converged step the results are written and the case's stop rule is checked.
#include <functional>
#include <memory>
#include <string>

#include "case/case.hpp"
#include "path/continuation.hpp"

namespace fibrane::run {

struct RunOptions {
  std::string output_directory;  // overrides the case's output.directory when non-empty
  int threads = 0;               // OpenMP threads; 0 keeps the default
  bool quiet = false;            // no progress line
  bool newton_log = false;       // one line per Newton iteration (t, iteration, |r|) on stderr
  // Continue from the checkpoint in the output directory (run/checkpoint.hpp) instead of starting anew.
  bool restart = false;
  // The linear solver instead of the case's `solver` (a distributed run's, src/parallel), given whether
  // the model promises symmetric tangents. Empty: the case's.
  std::function<std::unique_ptr<solve::LinearSolver>(bool symmetric)> make_solver;
  // Called after every converged step, once its output is written and before its checkpoint, with the step,
  // its free unknowns and the model evaluated there (the Python module's step callback). Returning false
  // ends the run after this step: outcome `stopped`, "stopped by the step callback". Empty: none.
  std::function<bool(const solve::StepReport&, const Eigen::VectorXd& q, const model::Model&)> on_step;
};

struct RunSummary {
  solve::ContinuationResult result;
  double wall_seconds = 0.0;
  std::string directory;
  int interrupted_by = 0;  // SIGINT or SIGTERM if a signal ended the run (result.outcome: interrupted)
  Eigen::VectorXd q;       // the free unknowns of the last converged state (or the initial state)
};

// Runs the case into the output directory (a new run clears an earlier run's files there; a restart
// continues them). SIGINT and SIGTERM end the run after the current step's output and a checkpoint are
// written (run/interrupt.hpp). InputError for bad input, including a checkpoint that does not fit.
// In a distributed run (the case's model has a distribution) every process calls run_case; the first
// writes the output files and the progress line, the others only compute (their state is the same).
RunSummary run_case(casefile::Case& c, const RunOptions& options);

// The continuation method the case's `steps` block chose, with its controls (verbose: a line per Newton
// iteration on stderr).
std::unique_ptr<solve::ContinuationMethod> make_method(const casefile::RunSettings& settings, bool verbose);

}  // namespace fibrane::run
