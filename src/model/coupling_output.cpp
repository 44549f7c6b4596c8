// What the SBS coupling reports through the Interaction interface: its history quantities, the point
// data along the beam (VTK point cloud and table), its summary record and the soft-minimum section.
#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <limits>

#include "model/beam_body.hpp"
#include "model/coupling.hpp"
#include "model/shell_body.hpp"

namespace fibrane::model {

namespace {

const char* status_name(CouplingPoint::Status s) {
  switch (s) {
    case CouplingPoint::Status::interior: return "interior";
    case CouplingPoint::Status::soft: return "soft";
    case CouplingPoint::Status::outside: return "outside";
    case CouplingPoint::Status::failed: return "failed";
  }
  return "failed";
}

void push3(std::vector<double>& v, const Eigen::Vector3d& x) { v.insert(v.end(), {x[0], x[1], x[2]}); }

// summary.json's record of a coupling: the values of the last step written and the first step with the
// most lost points; a warning at the first step with lost points.
class CouplingRecord final : public Interaction::RunRecord {
 public:
  explicit CouplingRecord(const Coupling& c) : c_(c) {}
  std::vector<std::string> step(int step, double t) override {
    energy_ = c_.energy();
    force_ = c_.total_force();
    lost_ = c_.lost_points();
    if (most_lost_step_ < 0 || lost_ > most_lost_) {  // the first step with the largest count
      most_lost_ = lost_;
      most_lost_step_ = step;
      most_lost_t_ = t;
    }
    if (lost_ == 0 || warned_) return {};
    warned_ = true;
    return {fmt::format("at step {} (t = {}), {} of the {} beam quadrature points of interaction '{}' have no closest "
                        "point on shell '{}' (outside the patch or no converged projection) and carry no interaction; "
                        "history.csv counts them per step ({}_lost_points), the interaction CSV marks them (status)",
                        step, format_t(t), lost_, c_.quadrature_points(), c_.name(), c_.shell().name(), c_.name())};
  }
  std::vector<SummaryField> fields() const override {
    return {{"final_energy", energy_},
            {"final_force", std::vector<double>{force_.x(), force_.y(), force_.z()}},
            {"final_lost_points", std::int64_t{lost_}},
            {"quadrature_points", std::int64_t{c_.quadrature_points()}},
            {"max_lost_points", std::int64_t{most_lost_}},
            {"max_lost_points_step", std::int64_t{most_lost_step_}},
            {"max_lost_points_t", most_lost_t_}};
  }

 private:
  // t as the shortest text that reads back to the same double (like the history's columns).
  static std::string format_t(double t) {
    char buffer[32];
    return std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, t).ptr);
  }
  const Coupling& c_;
  double energy_ = 0;
  Eigen::Vector3d force_ = Eigen::Vector3d::Zero();
  int lost_ = 0, most_lost_ = 0, most_lost_step_ = -1;
  double most_lost_t_ = 0;
  bool warned_ = false;
};

}  // namespace

std::pair<std::string, std::string> Coupling::bodies() const { return {beam_.name(), shell_.name()}; }

std::vector<std::string> Coupling::quantity_names() const {
  return {"energy", "force_x", "force_y", "force_z", "lost_points"};
}

double Coupling::quantity(std::size_t k) const {
  if (k == 0) return energy();
  if (k <= 3) return total_force()[static_cast<Eigen::Index>(k - 1)];
  return static_cast<double>(lost_points());
}

std::vector<PointSeries> Coupling::point_series() const { return {{name_, beam_.name(), true}}; }

PointCloud Coupling::point_cloud(std::size_t /*series*/) const {
  PointCloud cloud;
  PointField xi{"xi", 1, {}}, s{"s", 1, {}}, d{"distance", 1, {}}, cos{"cos_alpha", 1, {}}, f{"force", 3, {}},
      fm{"force_magnitude", 1, {}}, soft{"soft_minimum", 1, {}};
  for (const auto& p : points_) {
    if (!p.active) continue;
    cloud.positions.push_back(p.position);
    xi.values.push_back(p.xi);
    s.values.push_back(p.s);
    d.values.push_back(p.distance);
    cos.values.push_back(p.cos_alpha);
    push3(f.values, p.force);
    fm.values.push_back(p.force.norm());
    soft.values.push_back(p.soft ? 1 : 0);
  }
  cloud.fields = {std::move(xi), std::move(s), std::move(d), std::move(cos), std::move(f), std::move(fm),
                  std::move(soft)};
  return cloud;
}

PointTable Coupling::point_table(std::size_t /*series*/) const {
  // Lost points (outside, failed) have no distance and no angle: nan; their force and energy density are 0
  // (they carry no interaction). Soft points have no closest point: cos_alpha is nan.
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  PointTable t;
  for (const char* name : {"xi", "s", "active", "status", "distance", "cos_alpha", "force_x", "force_y", "force_z",
                           "force_magnitude", "energy_density", "soft_minimum"})
    t.columns.push_back({name, {}, {}});
  auto& c = t.columns;
  for (const auto& p : points_) {
    c[0].numbers.push_back(p.xi);
    c[1].numbers.push_back(p.s);
    c[2].numbers.push_back(p.active ? 1 : 0);
    c[3].texts.emplace_back(status_name(p.status));
    c[4].numbers.push_back(p.active ? p.distance : nan);
    c[5].numbers.push_back(p.active && !p.soft ? p.cos_alpha : nan);
    for (int k = 0; k < 3; ++k) c[static_cast<std::size_t>(6 + k)].numbers.push_back(p.force[k]);
    c[9].numbers.push_back(p.force.norm());
    c[10].numbers.push_back(p.energy_density);
    c[11].numbers.push_back(p.soft ? 1 : 0);
  }
  return t;
}

std::unique_ptr<Interaction::RunRecord> Coupling::run_record() const { return std::make_unique<CouplingRecord>(*this); }

std::vector<SummaryField> Coupling::summary_sections() const {
  if (soft_points() == 0) return {};
  return {{"soft_minimum_points", std::int64_t{soft_points()}}};
}

}  // namespace fibrane::model
