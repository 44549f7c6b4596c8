#pragma once
// The inertia of the bodies for implicit dynamics (solve/generalized_alpha.hpp): consistent mass matrices
// of the shells (density x thickness per unit reference area) and of the beams (density x area per unit
// reference length for the axis, density x polar moment of area for the twist: the rotary inertia about
// the axis, without which the twist would have no mass), on the full DOF vector. During a time step it
// adds M w(u) to the residual and mass_factor M to the tangent (solve::StepKinematics); outside a step it
// adds nothing.
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include "model/contribution.hpp"
#include "path/newmark.hpp"

namespace fibrane::model {

class ShellBody;
class BeamBody;

class Inertia final : public Contribution {
 public:
  // The mass matrices of every element of the bodies (densities from the bodies).
  Inertia(const std::vector<const ShellBody*>& shells, const std::vector<const BeamBody*>& beams,
          const solve::DofMap& dofs);
  std::string name() const override { return "inertia"; }
  EnergyKind energy_kind() const override { return EnergyKind::kinetic; }
  std::vector<std::vector<int>> element_dofs(const solve::DofMap&) const override { return dofs_; }
  double evaluate(const State& s, ElementSink& sink, Status& status) override;

  void set_step(const solve::StepKinematics* step) { step_ = step; }
  // M x for a full vector x.
  Eigen::VectorXd times(const Eigen::VectorXd& x) const;
  // The element mass matrices (full element DOF order), for assembling M itself.
  int num_elements() const { return static_cast<int>(dofs_.size()); }
  Eigen::MatrixXd element_matrix(int e) const;
  // The total mass of the translational DOFs (rigid-body check: sum of M over x-components of all DOFs).
  double total_mass() const;

 private:
  // Element e: scalar matrix m (nodes x nodes) per node component; the DOFs are node-major with
  // `components` per node, and component c's scalar matrix is scalar_[e] * factor_[e][c].
  std::vector<std::vector<int>> dofs_;
  std::vector<Eigen::MatrixXd> scalar_;
  std::vector<std::vector<double>> factor_;  // per element, per node component
  const solve::StepKinematics* step_ = nullptr;
};

}  // namespace fibrane::model
