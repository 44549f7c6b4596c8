// The coupling's state between steps, saved to a checkpoint and restored from it: per quadrature point
// the warm start of the next projection (the last converged one and the last evaluated one) and the beam
// point's last position; the pairs' pattern; the soft-minimum points and the switches requested at the
// last accept(); each point's relative curvature there (the switches after a failed attempt read it).
#include <algorithm>

#include "common/error.hpp"
#include "model/coupling.hpp"
#include "model/saved_state.hpp"

namespace fibrane::model {
namespace {

void add_optional(StateWriter& w, const std::optional<Eigen::Vector2d>& p) {
  w.add(p ? 1.0 : 0.0);
  w.add(p ? p->x() : 0.0);
  w.add(p ? p->y() : 0.0);
}

std::optional<Eigen::Vector2d> next_optional(StateReader& r) {
  const bool present = r.next() != 0.0;
  const double u = r.next(), v = r.next();
  return present ? std::optional<Eigen::Vector2d>(Eigen::Vector2d(u, v)) : std::nullopt;
}

}  // namespace

std::vector<double> Coupling::save_state() const {
  StateWriter w;
  w.add(static_cast<double>(quad_.size()));
  for (std::size_t i = 0; i < quad_.size(); ++i) {
    add_optional(w, warm_[i]);
    add_optional(w, last_[i]);
    w.add(beam_points_[i]);
  }
  w.add(static_cast<double>(pairs_.size()));
  for (const auto& [beam_element, shell_element] : pairs_) {
    w.add(static_cast<double>(beam_element));
    w.add(static_cast<double>(shell_element));
  }
  w.add(static_cast<double>(soft_.size()));
  for (const SoftPoint& sp : soft_) {
    w.add(static_cast<double>(sp.point));
    w.add(sp.centre);
    w.add(sp.offset);
    w.add(sp.calibrated ? 1.0 : 0.0);
  }
  w.add(static_cast<double>(soft_requests_.size()));
  for (const auto& [point, centre] : soft_requests_) {
    w.add(static_cast<double>(point));
    w.add(centre);
  }
  w.add(soft_changed_ ? 1.0 : 0.0);
  for (double lambda : converged_curvature_) w.add(lambda);
  return w.take();
}

void Coupling::restore_state(const std::vector<double>& state) {
  StateReader r(state, "interaction '" + name_ + "'");
  const int n = static_cast<int>(quad_.size());
  if (r.next_int() != n) throw InputError("checkpoint: interaction '" + name_ + "' has another number of beam points");
  for (int i = 0; i < n; ++i) {
    warm_[i] = next_optional(r);
    last_[i] = next_optional(r);
    beam_points_[i] = r.next3();
  }
  pairs_.resize(static_cast<std::size_t>(r.next_int()));
  for (auto& [beam_element, shell_element] : pairs_) {
    beam_element = r.next_int();
    shell_element = r.next_int();
  }
  soft_.clear();
  soft_of_.assign(quad_.size(), -1);
  const int n_soft = r.next_int();
  for (int k = 0; k < n_soft; ++k) {
    SoftPoint sp;
    sp.point = r.next_int();
    if (sp.point < 0 || sp.point >= n || soft_width_ <= 0)
      throw InputError("checkpoint: interaction '" + name_ + "' has a soft-minimum point the case does not allow");
    sp.centre.x() = r.next();
    sp.centre.y() = r.next();
    sp.offset = r.next();
    sp.calibrated = r.next() != 0.0;
    sp.window = soft_window(sp.centre);
    soft_of_[sp.point] = k;
    soft_.push_back(std::move(sp));
  }
  soft_requests_.resize(static_cast<std::size_t>(r.next_int()));
  for (auto& [point, centre] : soft_requests_) {
    point = r.next_int();
    if (point < 0 || point >= n) throw InputError("checkpoint: interaction '" + name_ + "' names a beam point it lacks");
    centre.x() = r.next();
    centre.y() = r.next();
  }
  soft_changed_ = r.next() != 0.0;
  for (double& lambda : converged_curvature_) lambda = r.next();
  r.finish();
  build_soft_elements();
  std::fill(jump_.begin(), jump_.end(), 0.0);
  failed_jumps_.clear();
}

}  // namespace fibrane::model
