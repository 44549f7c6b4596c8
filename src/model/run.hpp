#pragma once
// Runs a case: quasi-time continuation of the model, writing results after every converged step.
#include <string>

#include "model/case_reader.hpp"
#include "solve/continuation.hpp"

namespace fibrane::model {

struct RunOptions {
  std::string output_directory;  // overrides the case's output.directory when non-empty
  int threads = 0;               // OpenMP threads; 0 keeps the default
  bool quiet = false;            // no progress line
  bool newton_log = false;       // one line per Newton iteration (t, iteration, |r|) on stderr
};

struct RunSummary {
  solve::ContinuationResult result;
  double wall_seconds = 0.0;
  std::string directory;
};

RunSummary run_case(Case& c, const RunOptions& options);

}  // namespace fibrane::model
