#pragma once
// Reads a YAML case file (docs/case-format.md) into a Model plus the run settings. Bad input throws
// fibrane::InputError naming the file, line, key and what was expected; nothing is written before the
// whole case has been read and checked.
#include <memory>
#include <string>

#include "model/model.hpp"
#include "solve/load_stepping.hpp"
#include "solve/nonlinear.hpp"

namespace fibrane::model {

struct OutputSettings {
  std::string directory;  // relative paths are relative to the working directory
  bool vtk = true;
  int vtk_every = 1;      // write VTK every n-th converged step (and always the last)
  int samples = 4;        // sampling points per element edge for VTK
};

struct RunSettings {
  solve::StepControl steps;
  solve::NewtonOptions newton;
  std::string linear_solver = "auto";
  bool linear = false;  // one Newton step from the reference state at t_end: the linearised problem
  // Stop early once |history column| falls below this fraction of its largest magnitude so far (e.g. the
  // interaction energy at pull-off). Empty: run to t_end.
  std::string stop_column;
  double stop_fraction = 0.0;
  // A displacement-controlled path that ends at a limit point (pull-off) cannot be continued by Newton:
  // with this set, a run whose step fails below dt_min after at least one converged step ends as
  // completed, "at a limit point", instead of as a failure.
  bool stop_at_limit_point = false;
};

struct Case {
  std::string path;
  std::string name;  // file name without extension
  std::unique_ptr<Model> model;
  RunSettings run;
  OutputSettings output;
};

Case read_case(const std::string& path);

}  // namespace fibrane::model
