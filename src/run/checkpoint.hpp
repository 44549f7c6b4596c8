#pragma once
// A run's checkpoint: everything a restarted run needs to continue as the uninterrupted run would. It
// lives in the output directory (output::kCheckpointFile) and is replaced atomically after every
// `output.checkpoint_every` steps, when a run is interrupted or runs out of steps, and at the end of a
// completed run that has a checkpoint or writes them (marked complete: nothing to continue). It holds the
// unknowns q, the continuation method's state (ContinuationMethod::save), the state the model's
// contributions keep between steps (Model::save_state: beam frames, projection warm starts, soft points),
// the output position (history rows, VTK series), the stop rule's peak and the limit points found, and
// what a restart verifies before it touches anything: the hash of the case text the run started with
// (casefile::Case::text, read once), the model's DOF counts, and the count and hash of the history.csv
// rows it vouches for. The file's own checksum (io/checkpoint_file.hpp) covers all of it.
#include <string>

#include <Eigen/Dense>

#include "case/case.hpp"
#include "output/run_output.hpp"
#include "path/continuation.hpp"

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

// FNV-1a 64 of the case text (common/hash.hpp), as 16 hex digits.
std::string case_fingerprint(const std::string& case_text);

// Writes the checkpoint of case `c` into `directory` atomically; returns its size in bytes.
std::size_t write_checkpoint(const std::string& directory, const casefile::Case& c, const RunCheckpoint& k);

// Reads the checkpoint in `directory` and checks it: its checksum, that it was written for case `c`
// (the same case text, the same DOF layout) by a run that did not complete, and that history.csv there
// still begins with the rows it vouches for. InputError naming the file and what is wrong otherwise.
// Reads only: nothing in the directory changes.
RunCheckpoint read_checkpoint(const std::string& directory, const casefile::Case& c);

}  // namespace fibrane::run
