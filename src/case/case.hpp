#pragma once
// What a run is: the model built from a case file, how to march along its path, and what to write.
#include <map>
#include <memory>
#include <string>

#include "model/model.hpp"
#include "path/arc_length.hpp"
#include "path/generalized_alpha.hpp"
#include "path/load_stepping.hpp"
#include "path/nonlinear.hpp"

namespace fibrane::casefile {

struct OutputSettings {
  std::string directory;  // relative paths are relative to the working directory
  bool vtk = true;
  int vtk_every = 1;      // write VTK every n-th converged step (and always the last)
  int samples = 4;        // sampling points per element edge for the sampled VTK files
  // Write the restart checkpoint every n-th converged step (0: only when a run is interrupted or runs out
  // of steps); run/checkpoint.hpp.
  int checkpoint_every = 1;
  // Which VTK files a body gets: exact Bezier cells (geometry, displacement, twist) as <body>.pvd,
  // sampled cells with the section forces and moments as <body>_sampled.pvd, or both.
  bool bezier = true, sampled = true;
  // Also each process's piece of every VTK series (.vtu pieces, a .pvtu per step, <series>_pieces.pvd):
  // output/vtk_pieces.hpp.
  bool vtk_pieces = false;
};

struct RunSettings {
  std::string method = "load_stepping";  // steps.method: a name of the registry (case/case_methods.hpp)
  solve::StepControl steps;
  solve::ArcLengthControl arc_length;  // its t_start, t_end and max_steps are ignored: run::make_method takes those of `steps`
  solve::TransientOptions dynamics;    // time steps: `steps` (t is time)
  solve::NewtonOptions newton;
  solve::LinearSolverSettings linear_solver;  // steps.solver, precision, low_rank, krylov
  // Stop early once |monitored value| falls below this fraction of its largest magnitude so far (e.g. the
  // interaction energy at pull-off). Empty: run to t_end.
  std::string stop_column;
  double stop_fraction = 0.0;
};

struct Case {
  std::string path;
  // The case file's bytes as read when the case was read: a run never reads the file again, and its
  // checkpoints carry this text's hash (run/checkpoint.hpp).
  std::string text;
  std::string name;  // file name without extension
  std::unique_ptr<model::Model> model;
  RunSettings run;
  OutputSettings output;
  // Where each body is defined in the case file (its entry's path, e.g. "shells[0]", and line), by body
  // name: checks after reading (run/run_checks.hpp) locate what they find in a body there.
  struct Origin {
    std::string path;
    int line = 0;
  };
  std::map<std::string, Origin> body_origins;
  // The memory estimate of the whole model on its solver path (case/case_limits.hpp), which the case
  // passed: summary.json reports it beside the run's measured peak.
  struct MemoryEstimate {
    double bytes = 0;
    std::string path;
  };
  MemoryEstimate memory_estimate;
};

}  // namespace fibrane::casefile
