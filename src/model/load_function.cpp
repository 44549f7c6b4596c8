#include "model/load_function.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace fibrane::model {

LoadFunction LoadFunction::linear(double slope) {
  LoadFunction f;
  f.kind_ = Kind::linear;
  f.value_ = slope;
  return f;
}

LoadFunction LoadFunction::constant(double value) {
  LoadFunction f;
  f.kind_ = Kind::constant;
  f.value_ = value;
  return f;
}

LoadFunction LoadFunction::table(std::vector<std::pair<double, double>> points) {
  if (points.empty()) throw std::invalid_argument("a load table needs at least one (t, f) pair");
  for (std::size_t i = 1; i < points.size(); ++i)
    if (!(points[i].first > points[i - 1].first))
      throw std::invalid_argument("load table times must increase strictly");
  LoadFunction f;
  f.kind_ = Kind::table;
  f.points_ = std::move(points);
  return f;
}

LoadFunction LoadFunction::smooth_ramp(double slope, double duration) {
  if (!(duration > 0)) throw std::invalid_argument("a smooth ramp needs a positive duration");
  LoadFunction f;
  f.kind_ = Kind::smooth_ramp;
  f.value_ = slope;
  f.duration_ = duration;
  return f;
}

double LoadFunction::operator()(double t) const {
  const double pi = std::numbers::pi, T = duration_;
  switch (kind_) {
    case Kind::linear: return value_ * t;
    case Kind::constant: return value_;
    case Kind::smooth_ramp:
      if (t <= 0) return 0.0;
      if (t < T) return 0.5 * value_ * (t - T / pi * std::sin(pi * t / T));
      return value_ * (t - 0.5 * T);
    case Kind::table: break;
  }
  if (t <= points_.front().first) return points_.front().second;
  if (t >= points_.back().first) return points_.back().second;
  const auto hi = std::upper_bound(points_.begin(), points_.end(), t,
                                   [](double v, const auto& p) { return v < p.first; });
  const auto lo = hi - 1;
  const double s = (t - lo->first) / (hi->first - lo->first);
  return (1.0 - s) * lo->second + s * hi->second;
}

double LoadFunction::derivative(double t, int order) const {
  const double pi = std::numbers::pi, T = duration_;
  switch (kind_) {
    case Kind::linear: return order == 1 ? value_ : 0.0;
    case Kind::constant: return 0.0;
    case Kind::smooth_ramp:
      if (t <= 0) return 0.0;
      if (t >= T) return order == 1 ? value_ : 0.0;
      return order == 1 ? 0.5 * value_ * (1 - std::cos(pi * t / T)) : 0.5 * value_ * pi / T * std::sin(pi * t / T);
    case Kind::table: break;
  }
  if (order != 1) return 0.0;
  if (t < points_.front().first || t >= points_.back().first) return 0.0;
  const auto hi = std::upper_bound(points_.begin(), points_.end(), t,
                                   [](double v, const auto& p) { return v < p.first; });
  const auto lo = hi - 1;
  return (hi->second - lo->second) / (hi->first - lo->first);
}

LoadFunctions::LoadFunctions() { functions_.emplace_back("ramp", LoadFunction::linear()); }

int LoadFunctions::add(std::string name, LoadFunction f) {
  const int existing = find(name);
  if (existing >= 0) {
    functions_[existing].second = std::move(f);
    return existing;
  }
  functions_.emplace_back(std::move(name), std::move(f));
  return static_cast<int>(functions_.size()) - 1;
}

int LoadFunctions::find(const std::string& name) const {
  for (std::size_t i = 0; i < functions_.size(); ++i)
    if (functions_[i].first == name) return static_cast<int>(i);
  return -1;
}

std::vector<std::string> LoadFunctions::names() const {
  std::vector<std::string> out;
  for (const auto& f : functions_) out.push_back(f.first);
  return out;
}

}  // namespace fibrane::model
