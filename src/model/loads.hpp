#pragma once
// External loads as contributions (the -delta Pi_ext term of Eq. 7), each scaled by a load function of
// the load parameter t: configuration-independent nodal forces (already integrated by the body they act
// on), point moments on beams (Eq. 54, configuration-dependent) and moments along shell edges.
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "beam/beam.hpp"
#include "model/contribution.hpp"

namespace fibrane::model {

class BeamBody;
class ShellBody;

// Fixed values at DOFs, scaled by the load function `function`.
struct NodalLoad {
  std::vector<int> dofs;
  Eigen::VectorXd values;
  int function = 0;
  // The non-zero entries of `nodal` (`dofs_per_node` values per node of DOF block `block`, node-major,
  // `per_node` of them used) as a nodal load.
  static NodalLoad from_nodal(const solve::DofMap& dofs, int block, const Eigen::VectorXd& nodal, int per_node,
                              int function, bool keep_zeros = false);
};

// All configuration-independent loads of a model: residual -f(t) F, external energy -f(t) F . u.
class NodalLoads final : public Contribution {
 public:
  std::vector<NodalLoad> loads;
  std::string name() const override { return "nodal loads"; }
  EnergyKind energy_kind() const override { return EnergyKind::external; }
  std::vector<std::vector<int>> element_dofs(const solve::DofMap&) const override { return {}; }
  double evaluate(const State& s, ElementSink& sink, Status& status) override;
  // |f(t) F|^2 summed over the loads: the reference force level of Newton's relative tolerance.
  double squared_norm(const State& s) const;
};

// A point moment on a beam (Eq. 54): a fixed spatial vector, or, with `follower`, components along the
// current section triad (t, a2, a3) that turn with the section. Its load stiffness (B8-B9) is unsymmetric
// in general.
class PointMoment final : public Contribution {
 public:
  PointMoment(const BeamBody& beam, double xi, Eigen::Vector3d moment, int function, bool follower = false);
  std::string name() const override { return "point moment"; }
  EnergyKind energy_kind() const override { return EnergyKind::external; }
  std::vector<std::vector<int>> element_dofs(const solve::DofMap& dofs) const override;
  double evaluate(const State& s, ElementSink& sink, Status& status) override;
  void accept(const State& s) override;  // the frame state's incremental update, like the beam's
  std::vector<double> save_state() const override;  // the frame state
  void restore_state(const std::vector<double>& state) override;
  bool symmetric() const override { return false; }
  int skew_rows() const override;  // the DOFs of the beam element it acts on

 private:
  const BeamBody& beam_;
  double xi_;
  Eigen::Vector3d moment_;
  int function_, element_;
  bool follower_;
  beam::BeamPointState state_;
  // The kernel of the moment's kind: adds the residual (and tangent) of the moment vector `m`.
  void add(const Eigen::Vector3d& m, const beam::BasisDerivs& basis, const beam::BeamDofs& q, Eigen::VectorXd* r,
           Eigen::MatrixXd* k) const;
};

// A moment per unit reference length along a shell edge (shell/edge_moment.hpp).
class EdgeMoment final : public Contribution {
 public:
  EdgeMoment(const ShellBody& shell, std::string edge, Eigen::Vector3d moment, int function);
  std::string name() const override { return "edge moment"; }
  EnergyKind energy_kind() const override { return EnergyKind::external; }
  std::vector<std::vector<int>> element_dofs(const solve::DofMap& dofs) const override;
  double evaluate(const State& s, ElementSink& sink, Status& status) override;

 private:
  // Residual and tangent of the moment `m` on the edge element k.
  void element(int k, const Eigen::Vector3d& m, const State& s, Eigen::VectorXd& r, Eigen::MatrixXd* kt) const;
  const ShellBody& shell_;
  std::string edge_;  // u0, u1, v0, v1
  Eigen::Vector3d moment_;
  int function_;
  std::vector<int> elements_;  // shell elements along the edge
};

}  // namespace fibrane::model
