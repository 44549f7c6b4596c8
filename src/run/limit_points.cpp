#include "run/limit_points.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "common/error.hpp"

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

bool LimitPointFinder::hermite_extremum(const Row& a, const Row& b, double& s, double& t) {
  if (!std::isfinite(a.dt_ds) || !std::isfinite(b.dt_ds) || !(a.dt_ds * b.dt_ds < 0)) return false;
  // t(x) on x in [0, 1], h = b.s - a.s: Hermite basis with slopes h m_a, h m_b. t'(x) is quadratic:
  //   t'(x) = 6 (x - x^2)(t_b - t_a) + (1 - 4x + 3x^2) h m_a + (3x^2 - 2x) h m_b.
  const double h = b.s - a.s, ma = h * a.dt_ds, mb = h * b.dt_ds, d = b.t - a.t;
  const double c2 = -6 * d + 3 * ma + 3 * mb, c1 = 6 * d - 4 * ma - 2 * mb, c0 = ma;
  double x = -1;
  if (std::abs(c2) < 1e-14 * (std::abs(c1) + std::abs(c0))) {
    x = -c0 / c1;
  } else {
    const double disc = c1 * c1 - 4 * c2 * c0;
    if (disc < 0) return false;
    for (double root : {(-c1 + std::sqrt(disc)) / (2 * c2), (-c1 - std::sqrt(disc)) / (2 * c2)})
      if (root >= 0 && root <= 1) x = root;
  }
  if (!(x >= 0 && x <= 1)) return false;
  const double h00 = 2 * x * x * x - 3 * x * x + 1, h10 = x * x * x - 2 * x * x + x, h01 = -2 * x * x * x + 3 * x * x,
               h11 = x * x * x - x * x;
  s = a.s + x * h;
  t = h00 * a.t + h10 * ma + h01 * b.t + h11 * mb;
  return true;
}

bool LimitPointFinder::add(const solve::StepReport& r, const model::Model& m) {
  Row row{r.path_length, r.t, r.dt_ds, {}};
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
  LimitPoint p;
  p.step = r.step;
  p.maximum = a < 0;
  double hermite_s = 0, hermite_t = 0;
  const bool hermite =
      hermite_extremum(rows_[1], rows_[2], hermite_s, hermite_t) || hermite_extremum(rows_[0], rows_[1], hermite_s, hermite_t);
  if (hermite) vertex = hermite_s;
  const auto w = lagrange(s, vertex);
  p.path_length = vertex;
  p.t = hermite ? hermite_t : w[0] * rows_[0].t + w[1] * rows_[1].t + w[2] * rows_[2].t;
  for (std::size_t k = 0; k < observables_.size(); ++k)
    p.values.emplace_back(observables_[k].name,
                          w[0] * rows_[0].values[k] + w[1] * rows_[1].values[k] + w[2] * rows_[2].values[k]);
  found_.push_back(std::move(p));
  return true;
}

std::vector<double> LimitPointFinder::save() const {
  std::vector<double> out{static_cast<double>(observables_.size()), static_cast<double>(rows_.size())};
  for (const Row& row : rows_) {
    out.insert(out.end(), {row.s, row.t, row.dt_ds});
    out.insert(out.end(), row.values.begin(), row.values.end());
  }
  out.push_back(static_cast<double>(found_.size()));
  for (const LimitPoint& p : found_) {
    out.insert(out.end(), {static_cast<double>(p.step), p.t, p.path_length, p.maximum ? 1.0 : 0.0});
    for (const auto& value : p.values) out.push_back(value.second);
  }
  return out;
}

void LimitPointFinder::restore(const std::vector<double>& state) {
  std::size_t pos = 0;
  auto next = [&]() {
    if (pos >= state.size()) throw InputError("checkpoint: the limit points' state is too short for the case");
    return state[pos++];
  };
  const std::size_t n = observables_.size();
  if (static_cast<std::size_t>(next()) != n)
    throw InputError("checkpoint: the limit points were saved with another set of history columns");
  rows_.assign(static_cast<std::size_t>(next()), Row{});
  for (Row& row : rows_) {
    row.s = next(), row.t = next(), row.dt_ds = next();
    for (std::size_t k = 0; k < n; ++k) row.values.push_back(next());
  }
  found_.assign(static_cast<std::size_t>(next()), LimitPoint{});
  for (LimitPoint& p : found_) {
    p.step = static_cast<int>(next()), p.t = next(), p.path_length = next(), p.maximum = next() != 0.0;
    for (std::size_t k = 0; k < n; ++k) p.values.emplace_back(observables_[k].name, next());
  }
  if (pos != state.size()) throw InputError("checkpoint: the limit points' state is longer than the case needs");
}

}  // namespace fibrane::run
