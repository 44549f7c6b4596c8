#include "run/limit_points.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace fibrane::run {
namespace {

// Lagrange weights of the parabola through (x0, x1, x2) at x.
std::array<double, 3> lagrange(const double x[3], double at) {
  std::array<double, 3> w{};
  for (int i = 0; i < 3; ++i) {
    w[i] = 1.0;
    for (int j = 0; j < 3; ++j)
      if (j != i) w[i] *= (at - x[j]) / (x[i] - x[j]);
  }
  return w;
}

}  // namespace

bool LimitPointFinder::add(const solve::StepReport& r, const model::Model& m) {
  Row row{r.path_length, r.t, {}};
  for (const auto& o : observables_) row.values.push_back(o.value(m));
  rows_.push_back(std::move(row));
  if (rows_.size() > 3) rows_.erase(rows_.begin());
  if (!r.limit_point || rows_.size() < 3) return false;
  const double s[3] = {rows_[0].s, rows_[1].s, rows_[2].s};
  if (!(s[0] < s[1] && s[1] < s[2])) return false;  // no path coordinate (not an arc-length path)
  // t(s) = a s^2 + b s + c through the three points (divided differences); its vertex.
  const double d01 = (rows_[1].t - rows_[0].t) / (s[1] - s[0]), d12 = (rows_[2].t - rows_[1].t) / (s[2] - s[1]);
  const double a = (d12 - d01) / (s[2] - s[0]);
  if (a == 0) return false;
  const double b = d01 - a * (s[0] + s[1]);
  double vertex = -b / (2 * a);
  vertex = std::clamp(vertex, s[0], s[2]);
  const auto w = lagrange(s, vertex);
  LimitPoint p;
  p.step = r.step;
  p.path_length = vertex;
  p.maximum = a < 0;
  p.t = w[0] * rows_[0].t + w[1] * rows_[1].t + w[2] * rows_[2].t;
  for (std::size_t k = 0; k < observables_.size(); ++k)
    p.values.emplace_back(observables_[k].name,
                          w[0] * rows_[0].values[k] + w[1] * rows_[1].values[k] + w[2] * rows_[2].values[k]);
  found_.push_back(std::move(p));
  return true;
}

}  // namespace fibrane::run
