#pragma once
// The discrete model: bodies with their DOF blocks, constraints, loads and monitors. It is the
// NonlinearSystem that Newton and the continuation of src/solve drive: given the free unknowns q and the
// quasi-time t it assembles the reduced residual and tangent of Eq. (7).
#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <string>
#include <vector>

#include "model/beam_body.hpp"
#include "model/coupling.hpp"
#include "model/load_function.hpp"
#include "model/shell_body.hpp"
#include "solve/assembler.hpp"
#include "solve/constraints.hpp"
#include "solve/dof_map.hpp"
#include "solve/nonlinear.hpp"

namespace fibrane::model {

// A configuration-independent load: fixed values at DOFs, scaled by a load function.
struct NodalLoad {
  std::vector<int> dofs;
  Eigen::VectorXd values;
  int function = 0;
};

// A point moment on a beam (Eq. 54), scaled by a load function.
struct PointMoment {
  int beam = 0;
  double xi = 0.0;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  int function = 0;
  int element = 0;
  beam::BeamPointState state;
};

// A moment per unit reference length along a shell edge (see shell/edge_moment.hpp).
struct EdgeMoment {
  int shell = 0;
  std::string edge;        // u0, u1, v0, v1
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  int function = 0;
  std::vector<int> elements;  // shell elements along the edge
};

// A monitor is a linear functional of the displacement or of the full residual (reaction forces).
struct Monitor {
  enum class Source { displacement, reaction };
  std::string name;
  Source source = Source::displacement;
  std::vector<std::pair<int, double>> weights;
  double offset = 0.0;
};

// Wall time spent in each phase of evaluate(), accumulated (seconds), for bench/ and the summary.
struct PhaseTimes {
  double shell = 0, beam = 0, projection = 0, interaction = 0, pattern = 0, other = 0;
  int evaluations = 0, tangents = 0, pattern_rebuilds = 0;
};

class Model : public solve::NonlinearSystem {
 public:
  std::string title;
  std::vector<ShellBody> shells;
  std::vector<BeamBody> beams;
  LoadFunctions functions;
  std::vector<NodalLoad> nodal_loads;
  std::vector<PointMoment> moments;
  std::vector<EdgeMoment> edge_moments;
  std::vector<Monitor> monitors;
  std::vector<Coupling> couplings;
  solve::DofMap dofs;
  solve::ConstraintSet constraints;

  int add_shell(ShellBody body);
  int add_beam(BeamBody body);
  // Call once after bodies, constraints and loads are in place.
  void finalize();

  solve::CurveEval curve_eval() const;
  Eigen::VectorXd initial_unknowns() const { return Eigen::VectorXd::Zero(constraints.num_free()); }

  // NonlinearSystem
  int size() const override { return constraints.num_free(); }
  void evaluate(const Eigen::VectorXd& q, double t, bool with_tangent) override;
  const Eigen::VectorXd& residual() const override { return assembler_.reduced_residual(); }
  const Eigen::SparseMatrix<double>& tangent() const override { return assembler_.matrix(); }
  int pattern_version() const override { return assembler_.pattern_version(); }
  void accept(const Eigen::VectorXd& q, double t) override;
  void reject() override;
  std::string failure_hint() const override;
  double residual_scale() const override { return load_scale_; }
  bool symmetric() const override;

  // State of the last evaluate().
  const Eigen::VectorXd& displacement() const { return u_; }
  const Eigen::VectorXd& full_residual() const { return assembler_.full_residual(); }
  double strain_energy() const { return energy_; }
  double time() const { return t_; }
  double monitor_value(const Monitor& m) const;
  int num_elements() const { return assembler_.num_elements(); }
  const PhaseTimes& times() const { return times_; }
  void reset_times() { times_ = PhaseTimes{}; }

 private:
  solve::SparseAssembler assembler_;
  std::vector<int> shell_first_element_, beam_first_element_;
  int moment_first_element_ = 0;
  std::vector<int> edge_moment_first_element_;
  std::vector<int> constrained_dofs_;
  std::vector<int> coupling_first_element_;
  void rebuild_pattern();
  void assemble_edge_moment(const EdgeMoment& em, int first_element, bool with_tangent);
  Eigen::VectorXd u_;
  double t_ = 0.0, energy_ = 0.0, load_scale_ = 0.0;
  bool finalized_ = false;
  PhaseTimes times_;
};

}  // namespace fibrane::model
