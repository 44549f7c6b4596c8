#pragma once
// Load factors as functions of quasi-time t. Every load and every prescribed value of a case is scaled by
// one of these; the default is the linear ramp f(t) = t.
#include <string>
#include <utility>
#include <vector>

namespace fibrane::model {

class LoadFunction {
 public:
  static LoadFunction linear(double slope = 1.0);
  static LoadFunction constant(double value);
  // Piecewise-linear interpolation of (t, f) pairs with strictly increasing t; constant extrapolation.
  static LoadFunction table(std::vector<std::pair<double, double>> points);
  // A ramp that starts at rest: its rate rises smoothly from 0 to `slope` over `duration`,
  //   f'(t) = slope (1 - cos(pi t / T)) / 2 for t < T, slope after,
  // so that f, f' and f'' are continuous (prescribed motion for dynamics without an impulsive start).
  static LoadFunction smooth_ramp(double slope, double duration);

  double operator()(double t) const;
  // d^k f / dt^k for k = 1, 2; for a table the slope of the segment that starts at or before t (right
  // derivative at nodes) and no second derivative (its kinks are impulses).
  double derivative(double t, int order = 1) const;

 private:
  enum class Kind { linear, constant, table, smooth_ramp };
  Kind kind_ = Kind::linear;
  double value_ = 1.0, duration_ = 0.0;
  std::vector<std::pair<double, double>> points_;
};

// The named functions of a case; index 0 is always the default ramp f(t) = t.
class LoadFunctions {
 public:
  LoadFunctions();
  int add(std::string name, LoadFunction f);
  int find(const std::string& name) const;  // -1 if unknown
  double operator()(int id, double t) const { return id < 0 ? 1.0 : functions_[id].second(t); }
  double derivative(int id, double t, int order = 1) const {
    return id < 0 ? 0.0 : functions_[id].second.derivative(t, order);
  }
  std::vector<std::string> names() const;

 private:
  std::vector<std::pair<std::string, LoadFunction>> functions_;
};

}  // namespace fibrane::model
