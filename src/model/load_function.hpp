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

  double operator()(double t) const;
  // df/dt; for a table the slope of the segment that starts at or before t (right derivative at nodes).
  double derivative(double t) const;

 private:
  enum class Kind { linear, constant, table };
  Kind kind_ = Kind::linear;
  double value_ = 1.0;
  std::vector<std::pair<double, double>> points_;
};

// The named functions of a case; index 0 is always the default ramp f(t) = t.
class LoadFunctions {
 public:
  LoadFunctions();
  int add(std::string name, LoadFunction f);
  int find(const std::string& name) const;  // -1 if unknown
  double operator()(int id, double t) const { return id < 0 ? 1.0 : functions_[id].second(t); }
  double derivative(int id, double t) const { return id < 0 ? 0.0 : functions_[id].second.derivative(t); }
  std::vector<std::string> names() const;

 private:
  std::vector<std::pair<std::string, LoadFunction>> functions_;
};

}  // namespace fibrane::model
