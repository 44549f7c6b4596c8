#pragma once
// Limit points of the load parameter on an arc-length path: where t passes an extremum (StepReport::
// limit_point), the extremum is located between the steps by the parabola t(s) through the last three
// converged points (s: path length), and the model's observables are interpolated there the same way.
// For a smooth path the error is O(ds^3) in t and O(ds^2) in the location.
#include <string>
#include <vector>

#include "model/observables.hpp"
#include "solve/continuation.hpp"

namespace fibrane::run {

struct LimitPoint {
  int step = 0;     // the step that passed it
  double t = 0, path_length = 0;
  bool maximum = true;
  std::vector<std::pair<std::string, double>> values;  // observables there
};

class LimitPointFinder {
 public:
  explicit LimitPointFinder(std::vector<model::Observable> observables) : observables_(std::move(observables)) {}
  // After every converged step (the model at its state); returns true if the step passed a limit point,
  // which then is last().
  bool add(const solve::StepReport& r, const model::Model& m);
  const std::vector<LimitPoint>& found() const { return found_; }
  const LimitPoint& last() const { return found_.back(); }

 private:
  struct Row {
    double s, t;
    std::vector<double> values;
  };
  std::vector<model::Observable> observables_;
  std::vector<Row> rows_;  // the last three points
  std::vector<LimitPoint> found_;
};

}  // namespace fibrane::run
