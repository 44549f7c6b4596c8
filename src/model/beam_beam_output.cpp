// What the beam-beam interaction reports through the Interaction interface: its history quantities, one
// point series per fiber (VTK point cloud and table) and its summary record.
#include <cmath>
#include <limits>

#include "model/beam_beam.hpp"
#include "model/beam_body.hpp"

namespace fibrane::model {

namespace {

void push3(std::vector<double>& v, const Eigen::Vector3d& x) { v.insert(v.end(), {x[0], x[1], x[2]}); }

// summary.json's record of a beam-beam interaction: final_<quantity> at the last step written, and the
// smallest minimum gap over the steps written with its step and t.
class BeamBeamRecord final : public Interaction::RunRecord {
 public:
  explicit BeamBeamRecord(const BeamBeamInteraction& i) : i_(i), final_(i.quantity_names().size(), 0.0) {}
  std::vector<std::string> step(int step, double t) override {
    for (std::size_t k = 0; k < final_.size(); ++k) final_[k] = i_.quantity(k);
    const double g = i_.minimum_gap();
    if (std::isfinite(g) && (smallest_step_ < 0 || g < smallest_)) {
      smallest_ = g;
      smallest_step_ = step;
      smallest_t_ = t;
    }
    return {};
  }
  std::vector<SummaryField> fields() const override {
    const auto names = i_.quantity_names();
    std::vector<SummaryField> out;
    for (std::size_t k = 0; k < final_.size(); ++k) out.push_back({"final_" + names[k], final_[k]});
    // No step with a closest point: null (JSON's value of a non-finite number) and step -1.
    out.push_back({"smallest_gap", smallest_});
    out.push_back({"smallest_gap_step", std::int64_t{smallest_step_}});
    out.push_back({"smallest_gap_t", smallest_step_ < 0 ? std::numeric_limits<double>::quiet_NaN() : smallest_t_});
    return out;
  }

 private:
  const BeamBeamInteraction& i_;
  std::vector<double> final_;
  double smallest_ = std::numeric_limits<double>::infinity(), smallest_t_ = 0;
  int smallest_step_ = -1;
};

}  // namespace

std::pair<std::string, std::string> BeamBeamInteraction::bodies() const {
  return {fiber_[0]->name(), fiber_[1]->name()};
}

std::vector<std::string> BeamBeamInteraction::quantity_names() const {
  std::vector<std::string> out{"energy"};
  if (!self_)
    for (int f = 0; f < 2; ++f)
      for (const char* c : {"_x", "_y", "_z"}) out.push_back("force_" + fiber_[f]->name() + c);
  out.insert(out.end(), {"interacting_pairs", "interacting_points", "minimum_gap"});
  if (!std::isnan(contact_gap_)) out.push_back("contact_length");  // not without a contact gap
  return out;
}

double BeamBeamInteraction::quantity(std::size_t k) const {
  if (k == 0) return energy();
  const std::size_t forces = self_ ? 0 : 6;
  if (k <= forces) return force_on(static_cast<int>((k - 1) / 3))[static_cast<Eigen::Index>((k - 1) % 3)];
  k -= forces;
  if (k == 1) return interacting_pairs();
  if (k == 2) return interacting_points();
  if (k == 3) return minimum_gap();
  return contact_length();
}

std::vector<PointSeries> BeamBeamInteraction::point_series() const {
  if (self_) return {{name_, fiber_[0]->name(), true}};
  return {{name_ + "_" + fiber_[0]->name(), fiber_[0]->name(), true},
          {name_ + "_" + fiber_[1]->name(), fiber_[1]->name(), true}};
}

PointCloud BeamBeamInteraction::point_cloud(std::size_t series) const {
  PointCloud cloud;
  PointField xi{"xi", 1, {}}, s{"s", 1, {}}, gap{"gap", 1, {}}, active{"active", 1, {}},
      density{"energy_density", 1, {}}, f{"force_per_length", 3, {}}, fm{"force_per_length_magnitude", 1, {}};
  for (const auto& p : points_[series]) {
    if (!p.found) continue;
    cloud.positions.push_back(p.position);
    xi.values.push_back(p.xi);
    s.values.push_back(p.s);
    gap.values.push_back(p.gap);
    active.values.push_back(p.active ? 1 : 0);
    density.values.push_back(p.energy_density);
    push3(f.values, p.force);
    fm.values.push_back(p.force.norm());
  }
  cloud.fields = {std::move(xi), std::move(s),       std::move(gap), std::move(active),
                  std::move(density), std::move(f), std::move(fm)};
  return cloud;
}

PointTable BeamBeamInteraction::point_table(std::size_t series) const {
  // Points without a closest point on the other fiber have no gap and no distance: nan.
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  PointTable t;
  for (const char* name : {"xi", "s", "found", "active", "gap", "distance", "energy_density", "energy",
                           "force_per_length_x", "force_per_length_y", "force_per_length_z", "length"})
    t.columns.push_back({name, {}, {}});
  auto& c = t.columns;
  for (const auto& p : points_[series]) {
    c[0].numbers.push_back(p.xi);
    c[1].numbers.push_back(p.s);
    c[2].numbers.push_back(p.found ? 1 : 0);
    c[3].numbers.push_back(p.active ? 1 : 0);
    c[4].numbers.push_back(p.found ? p.gap : nan);
    c[5].numbers.push_back(p.found ? p.distance : nan);
    c[6].numbers.push_back(p.energy_density);
    c[7].numbers.push_back(p.weight * p.energy_density);
    for (int k = 0; k < 3; ++k) c[static_cast<std::size_t>(8 + k)].numbers.push_back(p.force[k]);
    c[11].numbers.push_back(p.length);
  }
  return t;
}

std::unique_ptr<Interaction::RunRecord> BeamBeamInteraction::run_record() const {
  return std::make_unique<BeamBeamRecord>(*this);
}

}  // namespace fibrane::model
