#include "model/monitor.hpp"

#include <algorithm>

#include "model/model.hpp"

namespace fibrane::model {

double LinearMonitor::value(const Model& m) const {
  const Eigen::VectorXd& v = source_ == Source::displacement ? m.displacement() : m.reactions();
  double s = offset_;
  for (const auto& [dof, w] : weights_) s += w * v[dof];
  return s;
}

double AppliedLoadMonitor::value(const Model& m) const {
  double sum = 0;
  for (const auto& l : m.nodal_loads.loads) {
    const double f = m.functions(l.function, m.time());
    for (std::size_t k = 0; k < l.dofs.size(); ++k)
      if (std::binary_search(dofs_.begin(), dofs_.end(), l.dofs[k])) sum += f * l.values[static_cast<Eigen::Index>(k)];
  }
  return sum;
}

double BeamPointMonitor::value(const Model& m) const {
  const Eigen::VectorXd& u = m.displacement();
  if (quantity_ == Quantity::twist_angle) return beam_.twist_angle(xi_, probe_, u, m.dofs);
  const beam::BeamPointOutput out = beam_.probe_output(probe_, u, m.dofs);
  switch (quantity_) {
    case Quantity::rotation: return beam_.probe_rotation(probe_, out).dot(axis_);
    case Quantity::tangent: return out.t.dot(axis_);
    case Quantity::director2: return out.a2.dot(axis_);
    case Quantity::director3: return out.a3.dot(axis_);
    case Quantity::axial_force: return out.N;
    case Quantity::torque: return out.M[0];
    case Quantity::bending2: return out.M[1];
    case Quantity::bending3: return out.M[2];
    case Quantity::twist_angle: break;
  }
  return 0.0;
}

}  // namespace fibrane::model
