#pragma once
// An interaction: a Contribution between two bodies (or a body and itself) that also reports what it
// does through a type-free interface, which the output (history.csv, summary.json, the interaction
// tables, VTK), the observables and the stop rules use without knowing its kind:
// - quantities: named scalars of the last evaluation (history columns <name>_<quantity>, stop rules);
// - point series: data at points along one body (a VTK point cloud per series, optionally a CSV table);
// - a run record: what summary.json reports of it after a run, accumulated step by step, with warnings;
// - summary sections: members it adds to top-level objects of summary.json.
// The beam-shell SBS coupling (model/coupling.hpp) is one implementation; a new kind is a class deriving
// from Interaction and a registration in case/case_interactions.cpp.
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <Eigen/Dense>

#include "model/contribution.hpp"

namespace fibrane::model {

// A named array of values at points: `components` numbers per point (1: scalar, 3: vector).
struct PointField {
  std::string name;
  int components = 1;
  std::vector<double> values;
};

// Points along a body with data at each (a VTK point cloud of vertex cells).
struct PointCloud {
  std::vector<Eigen::Vector3d> positions;
  std::vector<PointField> fields;
};

// A table with one row per point (interaction/<series>_<step>.csv): each column holds numbers (written
// as the shortest text that reads back to the same double; NaN as `nan`) or texts.
struct PointTable {
  struct Column {
    std::string name;
    std::vector<double> numbers;     // used when `texts` is empty
    std::vector<std::string> texts;  // a text column
  };
  std::vector<Column> columns;
};

// One series of point data: written as <name>.pvd with vtk/<name>_<step>.vtu and, with `table`, as
// interaction/<name>_<step>.csv. The name must not collide with another output name of the case.
struct PointSeries {
  std::string name;
  std::string body;  // the body its points lie on
  bool table = false;
};

// A member of summary.json: a number, an integer (a count, a step) or a list of numbers.
struct SummaryField {
  std::string key;
  std::variant<double, std::int64_t, std::vector<double>> value;
};

class Interaction : public Contribution {
 public:
  EnergyKind energy_kind() const override { return EnergyKind::interaction; }

  // The bodies it acts between, by name (the same name twice: a body with itself).
  virtual std::pair<std::string, std::string> bodies() const = 0;

  // Its scalar quantities: names fixed at construction (history.csv gets <name>_<quantity> for each, in
  // this order), values of the model's last evaluation.
  virtual std::vector<std::string> quantity_names() const = 0;
  virtual double quantity(std::size_t k) const = 0;

  // Point data: the series (fixed at construction) and, for series k, its points at the last evaluation
  // and, if the series has a table, its table.
  virtual std::vector<PointSeries> point_series() const { return {}; }
  virtual PointCloud point_cloud(std::size_t /*series*/) const { return {}; }
  virtual PointTable point_table(std::size_t /*series*/) const { return {}; }

  // What summary.json reports of the interaction over one run (its member of "interactions"). The
  // output makes one record per run and calls step() after every step it writes.
  class RunRecord {
   public:
    virtual ~RunRecord() = default;
    // After step `step` (at t) is written: warnings for stderr (sentences), usually none.
    virtual std::vector<std::string> step(int step, double t) = 0;
    virtual std::vector<SummaryField> fields() const = 0;
  };
  // The default record reports final_<quantity> of every quantity at the last step written.
  virtual std::unique_ptr<RunRecord> run_record() const;

  // Members it adds to top-level objects of summary.json at the end of a run: a field {section, value}
  // puts <name>: value into the object `section`. The sections a kind may fill are listed with its
  // registration (case/case_interactions.hpp), so that they are present, possibly empty, in every run.
  virtual std::vector<SummaryField> summary_sections() const { return {}; }
};

}  // namespace fibrane::model
