#include "path/event_locator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fibrane::solve {

namespace {
// A step that would cross the earliest estimate ends this fraction of the way before it, at least half a
// tolerance: a margin that falls faster and faster (a relative curvature toward the threshold) crosses
// before its linear extrapolation says, and a withdrawn attempt costs a whole Newton solve.
constexpr double kEarly = 0.05;
constexpr double kNone = std::numeric_limits<double>::quiet_NaN();

double at(const std::vector<double>& g, std::size_t k) { return k < g.size() ? g[k] : kNone; }
}  // namespace

double EventLocator::earliest() const {
  double first = kNone;
  const bool bracket = !g_far_.empty() && t_far_ > t_last_;
  const std::size_t n = bracket ? g_far_.size() : g_last_.size();
  for (std::size_t k = 0; k < n; ++k) {
    double t = kNone;
    if (bracket) {
      const double near = at(g_last_, k), far = g_far_[k];
      if (!(far <= 0)) continue;  // not crossed before t_far (or happened before)
      if (k < g_last_.size() && std::isnan(near)) continue;  // happened since t_far bounded the bracket
      t = std::isfinite(near) && near > 0 ? t_last_ + (t_far_ - t_last_) * near / (near - far)  // regula falsi
                                          : 0.5 * (t_last_ + t_far_);  // no margin known at t_last: bisect
    } else {
      const double now = g_last_[k], then = at(g_before_, k);
      if (now > 0 && std::isfinite(now) && std::isfinite(then) && then > now && t_last_ > t_before_)
        t = t_last_ + (t_last_ - t_before_) * now / (then - now);
    }
    if (t > t_last_ && !(t >= first)) first = t;
  }
  return first;
}

double EventLocator::step(double t, double dt) const {
  if (!(tolerance_ > 0)) return dt;
  const double room = earliest() - t;
  if (!(room > 0)) return dt;
  if (room <= tolerance_) return std::min(dt, tolerance_);  // cross it within a tolerance
  const double land = room - std::max(0.5 * tolerance_, kEarly * room);
  return std::min(dt, land);
}

bool EventLocator::crossed(const std::vector<double>& g) const {
  for (std::size_t k = 0; k < g.size(); ++k)
    if (g[k] <= 0 && !(at(g_last_, k) <= 0)) return true;  // NaN before: unknown there (or nothing known yet)
  return false;
}

bool EventLocator::withdraw(double t, double t_new, const std::vector<double>& g) {
  if (!(tolerance_ > 0) || t_new - t <= tolerance_ * (1 + 1e-9) || !crossed(g)) return false;
  t_far_ = t_new;
  g_far_ = g;
  near_moves_ = 0;
  return true;
}

bool EventLocator::located(const std::vector<double>& g) const { return tolerance_ > 0 && crossed(g); }

void EventLocator::accepted(double t, const std::vector<double>& g_next) {
  if (!g_far_.empty() && t_far_ > t) {
    if (++near_moves_ >= 2)
      for (double& g : g_far_)
        if (g <= 0) g *= 0.5;  // Illinois
  } else {
    g_far_.clear();
    near_moves_ = 0;
  }
  t_before_ = t_last_;
  g_before_ = std::move(g_last_);
  t_last_ = t;
  g_last_ = g_next;
}

void EventLocator::save(MethodState& s) const {
  s["events_t"] = {t_last_, t_before_, t_far_, static_cast<double>(near_moves_)};
  s["events_last"] = g_last_;
  s["events_before"] = g_before_;
  s["events_far"] = g_far_;
}

void EventLocator::start(double t) {
  *this = EventLocator(tolerance_);
  t_last_ = t_before_ = t_far_ = t;
}

void EventLocator::restore(const MethodState& s, double t) {
  start(t);
  const auto it = s.find("events_t");
  if (it == s.end() || it->second.size() != 4) return;
  t_last_ = it->second[0];
  t_before_ = it->second[1];
  t_far_ = it->second[2];
  near_moves_ = static_cast<int>(it->second[3]);
  g_last_ = s.at("events_last");
  g_before_ = s.at("events_before");
  g_far_ = s.at("events_far");
}

}  // namespace fibrane::solve
