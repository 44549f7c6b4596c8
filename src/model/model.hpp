#pragma once
// The discrete model: DOF blocks, constraints, load functions and the contributions (bodies, interactions,
// loads) whose sum is the weak form Eq. (7). It is the NonlinearSystem that Newton and the continuation
// methods of src/path drive: given the free unknowns q and the load parameter t it assembles the reduced
// residual, tangent and load derivative in one loop over its contributions.
#include <deque>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/Sparse>

#include "model/beam_body.hpp"
#include "model/contribution.hpp"
#include "model/inertia.hpp"
#include "model/interaction.hpp"
#include "model/load_function.hpp"
#include "model/loads.hpp"
#include "model/monitor.hpp"
#include "model/shell_body.hpp"
#include "linalg/assembler.hpp"
#include "linalg/constraints.hpp"
#include "linalg/distribution.hpp"
#include "linalg/dof_map.hpp"
#include "linalg/partition.hpp"
#include "path/generalized_alpha.hpp"
#include "path/nonlinear.hpp"

namespace fibrane::model {

// Wall time spent in each phase of evaluate(), accumulated (seconds), for bench/ and the summary.
struct PhaseTimes {
  double shell = 0, beam = 0, projection = 0, interaction = 0, pattern = 0, other = 0;
  // tangents: evaluations with the whole tangent; partial_tangents: with the tangent of the elements a
  // local first update needs (evaluate_tangent_on), their times counted in the phases above as well.
  int evaluations = 0, tangents = 0, partial_tangents = 0, pattern_rebuilds = 0;
};

class Model : public solve::TransientSystem {
 public:
  std::string title;
  LoadFunctions functions;
  solve::DofMap dofs;
  solve::ConstraintSet constraints;
  // The contributions by kind, in the order they are evaluated (deques: their addresses stay valid).
  std::deque<ShellBody> shells;
  std::deque<BeamBody> beams;
  std::deque<PointMoment> moments;
  std::deque<EdgeMoment> edge_moments;
  NodalLoads nodal_loads;
  std::vector<std::unique_ptr<Monitor>> monitors;
  // The DOFs each named constraint of the case fixes, prescribes or ties (slaves and masters), sorted.
  std::map<std::string, std::vector<int>> named_constraints;

  // With inertia (set before finalize()): the bodies' mass matrices take part, for dynamics.
  bool inertia = false;

  // Bodies get their DOF block here: 3 per shell control point, 4 (x, y, z, twist) per beam control point.
  ShellBody& add_shell(ShellBody body);
  BeamBody& add_beam(BeamBody body);
  // Interactions between bodies (model/interaction.hpp), evaluated after the beams in the order added.
  Interaction& add_interaction(std::unique_ptr<Interaction> i);
  const std::vector<std::unique_ptr<Interaction>>& interactions() const { return interactions_; }
  // The interactions of type T, in order (a kind's own tools and tests).
  template <class T>
  std::vector<const T*> interactions_of() const {
    std::vector<const T*> out;
    for (const auto& i : interactions_)
      if (const auto* t = dynamic_cast<const T*>(i.get())) out.push_back(t);
    return out;
  }
  // Any other contribution (evaluated after the built-in kinds, in the order added).
  Contribution& add_contribution(std::unique_ptr<Contribution> c);
  // Call once after bodies, constraints and loads are in place.
  void finalize();
  // A distributed run (solve/distribution.hpp; set before finalize(), kept alive by the caller): each
  // element is evaluated by one process, chosen by the distribution's partitioning (linalg/partition.hpp),
  // and the residuals, energies, external forces and the validity of a state are summed or agreed over the
  // processes after every evaluation. Everything the model reports is then the same on every process
  // except tangent(), this process's summand. Null: serial.
  void set_distribution(const solve::Distribution* d);
  const solve::Distribution* distribution() const { return distribution_; }
  // Distributed: the sharing of the elements and unknowns that finalize() made (its `unknowns` give the
  // distributed solver's row numbering); empty in a serial run.
  const solve::ElementPartition& partition() const { return partition_; }

  solve::CurveEval curve_eval() const;
  Eigen::VectorXd initial_unknowns() const { return Eigen::VectorXd::Zero(constraints.num_free()); }

  // NonlinearSystem
  int size() const override { return constraints.num_free(); }
  void evaluate(const Eigen::VectorXd& q, double t, bool with_tangent) override;
  const Eigen::VectorXd& residual() const override { return assembler_.reduced_residual(); }
  const Eigen::SparseMatrix<double>& tangent() const override { return assembler_.matrix(); }
  // Only the elements whose free unknowns meet `rows` (model_local.cpp); distributed, those this process
  // owns. With `apart` in a serial run, the soft-minimum points' rank-one terms are held apart.
  void evaluate_tangent_on(const Eigen::VectorXd& q, double t, const std::vector<int>& rows,
                           solve::RankOneTerms* apart) override;
  // The beams' free unknowns (model_local.cpp): a fiber's end is where a finely meshed model's global
  // Newton updates stall, and a local solve must move the fiber with it.
  std::vector<int> local_solve_rows() const override;
  void unite_flags(std::vector<char>& flags) const override;
  // Distributed: the processes' parts gathered as (column, row, value) entries and summed in the order of
  // the processes' ranks, the same on every process.
  Eigen::SparseMatrix<double> sum_over_processes(Eigen::SparseMatrix<double> part) const override;
  bool tangent_finite() const override;
  Eigen::VectorXd tangent_times(const Eigen::VectorXd& x) const override;
  bool distributed() const override { return distribution_ && distribution_->size() > 1; }
  const Eigen::VectorXd& load_derivative() const override { return assembler_.reduced_rate(); }
  int pattern_version() const override { return assembler_.pattern_version(); }
  std::string invalid_state() const override { return status_.valid ? std::string() : status_.reason; }
  void accept(const Eigen::VectorXd& q, double t) override;
  void reject() override;
  void withdraw() override;
  std::vector<double> event_margins() const override;  // the contributions' events in their order
  long model_changes() const override;                  // the contributions' changes, summed
  // Restart support: the state every contribution keeps between steps (Contribution::save_state), keyed
  // "<evaluation index> <name>", and its restoration into a model built from the same case, which also
  // rebuilds the variable contributions' elements. InputError if the keys do not match this model's.
  solve::MethodState save_state() const;
  void restore_state(const solve::MethodState& state);
  std::string failure_hint() const override;
  double residual_scale() const override { return load_scale_; }
  double roundoff_floor() const override { return roundoff_floor_; }
  bool symmetric() const override;
  // The rows its tangent's skew part can touch: the contributions' together (-1: any number).
  int skew_rows() const;
  // Which rows those are at the current pattern: the free unknowns of the elements of the contributions
  // that may be unsymmetric (an element's tangent lies on its own DOFs), through the constraints.
  std::optional<std::vector<int>> skew_candidates() const override;

  // TransientSystem (needs `inertia`): the time step the next evaluations belong to, the prescribed
  // motion g(t) and its derivatives, the mass matrix.
  void begin_step(const solve::StepKinematics* step) override;
  const solve::ConstraintSet& constraint_set() const override { return constraints; }
  Eigen::VectorXd prescribed_motion(double t, int order) const override;
  const Eigen::VectorXd& external_force() const override { return external_; }
  Eigen::VectorXd mass_times(const Eigen::VectorXd& x) const override;
  double stored_energy() const override { return strain_energy() + energy(EnergyKind::interaction); }
  const Eigen::SparseMatrix<double>& reduced_mass() override;

  // State of the last evaluate().
  const Eigen::VectorXd& displacement() const override { return u_; }
  const Eigen::VectorXd& full_residual() const override { return assembler_.full_residual(); }
  // The forces the supports exert at the constrained DOFs: the full residual, or, in a dynamic run, the
  // reactions the time integrator computed (inertia included), once set with set_reactions().
  const Eigen::VectorXd& reactions() const { return reactions_ ? *reactions_ : full_residual(); }
  void set_reactions(const Eigen::VectorXd* reactions) { reactions_ = reactions; }
  double strain_energy() const { return energy(EnergyKind::strain); }
  double energy(EnergyKind kind) const { return energies_[static_cast<int>(kind)]; }
  double time() const { return t_; }
  int num_elements() const { return assembler_.num_elements(); }
  // How threads share the assembly (solve::SparseAssembler::Strategy; Colours unless set).
  void set_assembly(solve::SparseAssembler::Strategy s) { assembler_.set_strategy(s); }
  // Bytes the assembly holds in per-thread buffers (solve::SparseAssembler::buffer_bytes).
  std::size_t assembly_buffer_bytes() const { return assembler_.buffer_bytes(); }
  // Colours of the assembly's elements (solve::SparseAssembler::num_colours).
  int assembly_colours() const { return assembler_.num_colours(); }
  const PhaseTimes& times() const { return times_; }
  void reset_times() { times_ = PhaseTimes{}; }

 private:
  struct Entry {
    Contribution* contribution;
    int first_element;
    double PhaseTimes::*time;  // the phase its evaluation counts towards
    std::vector<std::vector<int>> dofs = {};  // element DOF lists of external contributions (f_ext)
  };
  void rebuild_variable_elements();
  // Distributed: records which of the elements first, first + 1, ... this process owns (owned_) and
  // empties the DOF lists of the others, so that its assembler holds only its own elements. The fixed
  // elements (`fixed`) are partitioned (partition_); the variable ones follow the unknowns' owners.
  void share(std::vector<std::vector<int>>& element_dofs, int first, bool fixed);
  // Distributed, after the assembly: energies, status and external forces over the processes.
  void agree(bool with_tangent);
  // eps * sqrt(sum_ij (K_ij x_j)^2) of the current tangent, x_j = |reference coordinate| + |u_j| (twists:
  // max(1, |u_j|)): the residual that rounding the configuration alone causes.
  // Distributed: the sum over the processes of their summands' column sums (the same value everywhere).
  double estimate_roundoff_floor() const;
  // evaluate() at a state with a non-finite unknown or time (an overflowing step): no contribution is
  // evaluated (their kernels would throw or spread NaN), the state is invalid, residual and tangent are zero.
  void evaluate_non_finite(bool with_tangent);
  // evaluate() of the elements whose free unknowns meet `rows` (all where null; serial runs only). A
  // partial evaluation keeps the last load scale and round-off floor.
  // `apart`: where the evaluation's sinks hold rank-one terms apart (ElementSink::hold_rank_one_apart).
  void evaluate_elements(const Eigen::VectorXd& q, double t, bool with_tangent, const std::vector<int>* rows,
                         solve::RankOneTerms* apart = nullptr);
  // Per assembler element id (fixed, then variable): whether its free unknowns meet `rows` (model_local.cpp).
  std::vector<char> elements_meeting(const std::vector<int>& rows) const;
  State state() const { return {u_, t_, dofs, functions}; }
  std::vector<Entry> entries_;
  std::vector<std::unique_ptr<Interaction>> interactions_;
  std::vector<std::unique_ptr<Contribution>> extra_;
  solve::SparseAssembler assembler_;
  std::vector<int> constrained_dofs_;
  Eigen::VectorXd u_, prescribed_rate_, external_;
  std::unique_ptr<Inertia> inertia_;
  Eigen::SparseMatrix<double> mass_;
  const Eigen::VectorXd* reactions_ = nullptr;
  std::vector<double> reference_magnitude_;  // per DOF: |reference coordinate|, 1 for a twist
  double t_ = 0.0, load_scale_ = 0.0, roundoff_floor_ = 0.0;
  double energies_[4] = {0, 0, 0, 0};
  Status status_;
  bool finalized_ = false;
  PhaseTimes times_;
  const solve::Distribution* distribution_ = nullptr;
  std::vector<char> owned_;     // per assembler element: evaluated by this process (distributed only)
  solve::ElementPartition partition_;
  bool tangent_finite_ = true;  // agreed over the processes at the last evaluation with the tangent
};

}  // namespace fibrane::model
