#include "model/load_function.hpp"

#include <algorithm>
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

double LoadFunction::operator()(double t) const {
  switch (kind_) {
    case Kind::linear: return value_ * t;
    case Kind::constant: return value_;
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

double LoadFunction::derivative(double t) const {
  switch (kind_) {
    case Kind::linear: return value_;
    case Kind::constant: return 0.0;
    case Kind::table: break;
  }
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
