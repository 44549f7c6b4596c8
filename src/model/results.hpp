#pragma once
// Everything a run leaves in its output directory: history.csv (one row per converged step),
// a VTK time series per body (<body>.pvd + vtk/<body>_<step>.vtu) and summary.json. Every file is
// complete on disk after each step (rows are appended whole, VTK and JSON files are renamed into place).
#include <memory>
#include <string>
#include <vector>

#include "io/csv.hpp"
#include "io/vtk.hpp"
#include "model/case_reader.hpp"
#include "solve/continuation.hpp"

namespace fibrane::model {

// Sampled geometry and fields of one body for ParaView.
io::VtuMesh shell_vtu(const Model& m, const ShellBody& s, int samples);
io::VtuMesh beam_vtu(const Model& m, const BeamBody& b, int samples);

class RunOutput {
 public:
  RunOutput(const Case& c, std::string directory);
  // Writes the state of the model's last evaluate() as step `report.step`.
  void write_step(const Model& m, const solve::StepReport& report, bool force_vtk);
  void write_summary(const Model& m, const solve::ContinuationResult& result, double wall_seconds,
                     const std::string& solver_name);
  const std::string& directory() const { return dir_; }

 private:
  const Case& case_;
  std::string dir_;
  std::unique_ptr<io::CsvWriter> history_;
  std::vector<io::PvdCollection> series_;
  int steps_written_ = 0;
};

}  // namespace fibrane::model
