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

// Column names of history.csv for this model: step, t, load factor, iterations, residual, energy, then per
// interaction its energy and the components of its total force on the beam, then the monitors.
std::vector<std::string> history_columns(const Model& m);

// Sampled geometry and fields of one body for ParaView.
io::VtuMesh shell_vtu(const Model& m, const ShellBody& s, int samples);
io::VtuMesh beam_vtu(const Model& m, const BeamBody& b, int samples);
// The beam quadrature points of an interaction with distance, cos(alpha) and the force per length.
io::VtuMesh coupling_vtu(const Coupling& c);

class RunOutput {
 public:
  RunOutput(const Case& c, std::string directory);
  // Writes the state of the model's last evaluate() as step `report.step`: a history row (and the
  // interaction CSVs), then the VTK files if `with_vtk`.
  void write_history(const Model& m, const solve::StepReport& report);
  void write_vtk(const Model& m, const solve::StepReport& report);
  bool vtk_due(int step) const { return case_.output.vtk && step % case_.output.vtk_every == 0; }
  // Value of a history column in the last row written.
  double last_value(const std::string& column) const;
  void write_summary(const Model& m, const solve::ContinuationResult& result, double wall_seconds,
                     const std::string& solver_name);
  const std::string& directory() const { return dir_; }

 private:
  void write_coupling_csv(const Coupling& c, int step) const;
  const Case& case_;
  std::string dir_;
  std::unique_ptr<io::CsvWriter> history_;
  std::vector<io::PvdCollection> series_;
  std::vector<std::string> columns_;
  std::vector<double> last_row_;
  int steps_written_ = 0;
};

}  // namespace fibrane::model
