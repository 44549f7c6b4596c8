#pragma once
// Everything a run leaves in its output directory: history.csv (one row per converged step), the
// interactions' point tables per step (interaction/<series>_<step>.csv), a VTK time series per body
// (<body>.pvd + vtk/<body>_<step>.vtu), summary.json, and the manifest listing all of them
// (output/manifest.hpp). Every file is complete on disk after each step (rows are appended whole, VTK and
// JSON files are renamed into place), and each is a regular file created in the directory: nothing is
// written or removed through a symbolic link. The caller holds the directory's lock (directory_lock.hpp).
#include <Eigen/Dense>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "case/case.hpp"
#include "io/csv.hpp"
#include "io/json.hpp"
#include "io/vtk.hpp"
#include "model/observables.hpp"
#include "path/continuation.hpp"

namespace fibrane::output {

class Manifest;

// Column names of history.csv: step, t, load factor, iterations, residual, the number of negative
// eigenvalues of the tangent at the step's end (-1: the solver does not tell), whether t passed an
// extremum within the step (1) or not (0), then the model's observables (model/observables.hpp).
// With `energy` (dynamic runs) the energy account follows: kinetic energy, interaction energy, work of the
// external loads and of the prescribed motion, damping work, and their balance.
std::vector<std::string> history_columns(const model::Model& m, bool energy = false);

// The name of the checkpoint file in a run's output directory (run/checkpoint.hpp).
inline constexpr const char* kCheckpointFile = "checkpoint.bin";

// Where a restarted run's output continues: the history rows (and the hash of the file up to them) and
// the VTK series' entries at the checkpoint (series in the order RunOutput writes them).
struct OutputPosition {
  std::size_t history_rows = 0;
  std::uint64_t history_hash = 0;  // FNV-1a 64 of history.csv's bytes up to the end of those rows
  std::vector<std::vector<io::PvdCollection::Entry>> series;
};

class RunOutput {
 public:
  // A new run: removes an earlier run's files from `directory` (those its manifest lists, and this case's
  // names: see run_output.cpp), creates it. A restarted run (`resume`): keeps the directory's files,
  // cuts history.csv back to resume->history_rows rows, continues the VTK series from resume->series and
  // the manifest, and removes only summary.json. InputError, before anything is written, if vtk/ or
  // interaction/ is a symbolic link or not a directory, if the earlier manifest is damaged, or if the
  // history or the series do not fit the case.
  RunOutput(const casefile::Case& c, std::string directory, const OutputPosition* resume = nullptr);
  ~RunOutput();
  // Writes the state of the model's last evaluate() as step `report.step`: a history row and the
  // interactions' point tables.
  void write_history(const model::Model& m, const solve::StepReport& report);
  void write_vtk(const model::Model& m, const solve::StepReport& report);
  // `extra`: further members of the summary object (e.g. the limit points the run driver found).
  void write_summary(const model::Model& m, const solve::ContinuationResult& result, double wall_seconds,
                     const std::string& solver_name, const io::JsonValue* extra = nullptr);
  const std::string& directory() const { return dir_; }
  // Lists a file that another writer (output/vtk_pieces.hpp) is about to create in the manifest.
  void list(const std::string& relative_path);
  // Warnings raised by the steps written since the last call (the first step of the run at which an
  // interaction has lost points), as sentences for stderr; clears them.
  std::vector<std::string> take_warnings();
  // The position a restart continues from after the last write.
  OutputPosition position() const;

 private:
  io::JsonValue interactions_json(const model::Model& m) const;
  // interaction/<series>_<step>.csv
  void write_table(const std::string& series, const model::PointTable& table, int step) const;
  const casefile::Case& case_;
  std::string dir_;
  std::vector<model::Observable> observables_;
  bool energy_ = false;
  std::unique_ptr<Manifest> manifest_;
  std::unique_ptr<io::CsvWriter> history_;
  std::vector<io::PvdCollection> series_;
  // What summary.json reports per interaction (model::Interaction::run_record), fed every step written.
  std::vector<std::unique_ptr<model::Interaction::RunRecord>> records_;
  bool recorded_ = false;  // a step has been written
  std::vector<std::string> warnings_;
};

}  // namespace fibrane::output
