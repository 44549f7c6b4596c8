#pragma once
// Limit points of the load parameter on an arc-length path: where t passes an extremum (StepReport::
// limit_point), the extremum is located between the steps, s being the path length. Where the method
// reports the path's slope dt/ds at the points, by the cubic Hermite interpolant of t(s) on the interval
// where dt/ds changes sign (error O(ds^4) in t); otherwise by the parabola through the last three points
// (O(ds^3)). The model's observables are interpolated at the extremum by that parabola (O(ds^3)).
#include <string>
#include <vector>

#include "model/observables.hpp"
#include "path/continuation.hpp"

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
  // Restart support: the last three points and the limit points found, as numbers, and their restoration
  // (InputError if they do not fit the observables).
  std::vector<double> save() const;
  void restore(const std::vector<double>& state);

 private:
  struct Row {
    double s, t, dt_ds;
    std::vector<double> values;
  };
  // The extremum of t(s) on [a, b] from the Hermite cubic, if the slopes change sign there.
  static bool hermite_extremum(const Row& a, const Row& b, double& s, double& t);
  std::vector<model::Observable> observables_;
  std::vector<Row> rows_;  // the last three points
  std::vector<LimitPoint> found_;
};

}  // namespace fibrane::run
