#pragma once
// A run's checkpoint: everything a restarted run needs to continue as the uninterrupted run would. It
// lives in the output directory (output::kCheckpointFile) and is replaced atomically after every
// `output.checkpoint_every` steps, when a run is interrupted or runs out of steps, and at the end of a
// completed run (marked complete: nothing to continue). It holds the unknowns q, the continuation
// method's state (ContinuationMethod::save), the state the model's contributions keep between steps
// (Model::save_state: beam frames, projection warm starts, soft points), the output position (history
// rows, VTK series), the stop rule's peak and the limit points found, and a fingerprint of the case (the
// case file's text and the model's DOF counts) that a restart checks.
#include <string>

#include <Eigen/Dense>

#include "case/case.hpp"
#include "output/run_output.hpp"
#include "solve/continuation.hpp"

namespace fibrane::run {

struct RunCheckpoint {
  int step = 0;   // the last converged step
  double t = 0;   // its load parameter
  Eigen::VectorXd q;
  std::string method_name;
  solve::MethodState method, model;
  output::OutputPosition output;
  double stop_peak = 0;
  std::vector<double> limit_points;  // LimitPointFinder::save()
  bool completed = false;  // written at the end of a completed run: there is nothing to continue
};

// 64-bit FNV-1a of the case file's bytes, as 16 hex digits (InputError if the file cannot be read).
std::string case_fingerprint(const std::string& case_path);

// Writes the checkpoint of case `c` into `directory` atomically; returns its size in bytes.
std::size_t write_checkpoint(const std::string& directory, const casefile::Case& c, const RunCheckpoint& k);

// Reads the checkpoint in `directory` and checks that it was written for case `c` (same file text, same
// DOF layout) by a run that did not complete. InputError naming the checkpoint file otherwise.
RunCheckpoint read_checkpoint(const std::string& directory, const casefile::Case& c);

}  // namespace fibrane::run
