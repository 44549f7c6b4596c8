#pragma once
// Everything that adds to the energy, the residual and the tangent of the model is a Contribution: shell
// and beam bodies (Secs. 3.1, 3.2), beam-shell couplings (Sec. 5), loads and moments, inertia. The Model
// evaluates them in one loop (Eq. 7: delta Pi_str - delta Pi_ext + delta Pi_B-S = 0, one term each).
//
// A contribution declares its elements (groups of coupled DOFs) once, or, if `variable()`, again after
// every update() that changed them (the coupling, whose pairs move with the closest points). It writes its
// element vectors and matrices through an ElementSink, which knows where its elements sit in the
// assembler. State kept between evaluations (projections, frames) is committed by accept() after a
// converged step and rolled back by reject() after a failed attempt.
//
// In a distributed run (solve/distribution.hpp) every process holds the whole model and state, and each
// element is evaluated by one process, its owner: evaluate() skips the elements with !sink.owns(e), and
// adds residuals that belong to no element (nodal loads) only where sink.owns_global(). The energies
// returned and the residuals are summed over the processes by the model; state that evaluate() records
// for output (a coupling's point data) is summed with sink.sum(). update(), accept() and reject() run on
// every process for the whole model (the closest points are replicated).
#include <functional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "linalg/forward.hpp"

namespace fibrane::model {

class LoadFunctions;

// The state every contribution evaluates at.
struct State {
  const Eigen::VectorXd& u;          // full displacement, constrained DOFs included (u = T q + g(t))
  double t;                          // load parameter (quasi-time)
  const solve::DofMap& dofs;
  const LoadFunctions& functions;
};

// Whether an evaluation lies inside the model's domain; invalid states (a beam inside the plate, where the
// interaction law has no value) carry a reason, and Newton treats them as a failed iteration.
struct Status {
  bool valid = true;
  std::string reason;
  static Status invalid(std::string why) { return {false, std::move(why)}; }
  // Keeps the first reason.
  void merge(const Status& other) {
    if (valid && !other.valid) *this = other;
  }
};

// Which energy a contribution's energy counts as (history.csv reports them apart).
enum class EnergyKind { strain, interaction, external, kinetic };

// Where a contribution writes: its elements are `first`, `first + 1`, ... in the assembler. With
// `owned` (one flag per assembler element) and `distribution`, a process of a distributed run.
class ElementSink {
 public:
  ElementSink(solve::SparseAssembler& a, int first, bool with_tangent, bool with_rate,
              const std::vector<char>* owned = nullptr, const solve::Distribution* distribution = nullptr)
      : assembler_(a), first_(first), with_tangent_(with_tangent), with_rate_(with_rate), owned_(owned),
        distribution_(distribution) {}
  // Whether this process evaluates element `element` (always, in a serial run). Adding an element that
  // is not owned is a std::logic_error.
  bool owns(int element) const { return !owned_ || (*owned_)[static_cast<std::size_t>(first_ + element)]; }
  // Whether this process adds what belongs to no element (add_vector; add_rate of terms outside the
  // contribution's elements): the first process. add_vector elsewhere is a std::logic_error.
  bool owns_global() const;
  // Whether the run is distributed over several processes (then sum() communicates).
  bool distributed() const;
  // Collective (every process, in the same order): sums `values` over the processes, in place.
  void sum(std::span<double> values) const;
  // Also accumulates -r into `external` (full vector): the external force f_ext of an external
  // contribution (r = -f_ext), whose elements have the DOF lists `element_dofs`. Not thread-safe.
  void record_external(Eigen::VectorXd* external, const std::vector<std::vector<int>>* element_dofs) {
    external_ = external;
    element_dofs_ = element_dofs;
  }
  // Where `terms` is given (a serial partial evaluation for Newton's local updates, Model::
  // evaluate_tangent_on), contributions whose tangent holds a dense rank-one term (soft-minimum points) add
  // it with add_rank_one() instead of into their element matrix.
  void hold_rank_one_apart(solve::RankOneTerms* terms) { rank_one_apart_ = terms; }
  bool holds_rank_one_apart() const { return rank_one_apart_ != nullptr && with_tangent_; }
  // The term c v v^T of element `element`, v on its local DOFs local[0], local[1], ...: recorded reduced
  // (SparseAssembler::reduce) with the element's rows (RankOneTerms::fill_rows), in neither the matrix nor
  // d r / d t. Not thread-safe.
  void add_rank_one(int element, std::span<const int> local, double c, const Eigen::VectorXd& v);
  bool with_tangent() const { return with_tangent_; }
  // Whether d residual / d t is being assembled (arc-length continuation): contributions whose residual
  // depends on t explicitly (loads) add that derivative with add_rate(). The part that prescribed values
  // cause, K dg/dt, the assembler adds by itself.
  bool with_rate() const { return with_rate_; }
  // A contribution's element loop, inside its OpenMP parallel region (every thread of the team calls it, as
  // it would a `#pragma omp for schedule(static, chunk)` over e = 0 .. n - 1): body(e) for every element,
  // shared among the threads in chunks of `chunk`. Where the assembler colours its elements (Strategy::
  // Colours, outermost parallel region, more than one thread), it runs colour by colour with a barrier
  // between colours, and body(e) adds to element e only: those adds write straight into the matrix.
  void for_each_element(int n, int chunk, const std::function<void(int)>& body);
  // Thread-safe. `k` may be null (residual only).
  void add(int element, const Eigen::VectorXd& r, const Eigen::MatrixXd* k);
  // A sub-block of an element: r / k belong to its local DOFs local[0], local[1], ...
  void add(int element, std::span<const int> local, const Eigen::VectorXd& r, const Eigen::MatrixXd* k);
  // Residual at arbitrary DOFs (loads), and its explicit derivative with respect to t.
  void add_vector(std::span<const int> dofs, const Eigen::VectorXd& r);
  void add_rate(std::span<const int> dofs, const Eigen::VectorXd& r_t);

 private:
  solve::SparseAssembler& assembler_;
  int first_;
  bool with_tangent_, with_rate_;
  const std::vector<char>* owned_;
  const solve::Distribution* distribution_;
  solve::RankOneTerms* rank_one_apart_ = nullptr;
  Eigen::VectorXd* external_ = nullptr;
  const std::vector<std::vector<int>>* element_dofs_ = nullptr;
};

class Contribution {
 public:
  virtual ~Contribution() = default;
  virtual std::string name() const = 0;
  virtual EnergyKind energy_kind() const { return EnergyKind::strain; }
  // DOF lists of the elements, in the order evaluate() numbers them.
  virtual std::vector<std::vector<int>> element_dofs(const solve::DofMap& dofs) const = 0;
  // True if the element lists may change between evaluations (then update() says when).
  virtual bool variable() const { return false; }
  // First step of every evaluation, before any contribution assembles: state that depends on u (the
  // closest points of a coupling). Returns true if the element lists changed.
  virtual bool update(const State& /*s*/) { return false; }
  // Adds the residual (and the tangent if sink.with_tangent()) and returns the energy.
  virtual double evaluate(const State& s, ElementSink& sink, Status& status) = 0;
  // After a converged step at state s; after a failed attempt; after a converged attempt that is
  // discarded (solve::NonlinearSystem::withdraw: like a failed one, without learning from it).
  virtual void accept(const State& /*s*/) {}
  virtual void reject() {}
  virtual void withdraw() { reject(); }
  // Events (solve::NonlinearSystem::event_margins): the margins of the last evaluation's state to the
  // contribution's events, the same number at every evaluation (empty: none).
  virtual std::vector<double> event_margins() const { return {}; }
  // How many times its equations have changed (solve::NonlinearSystem::model_changes); never decreases.
  virtual long model_changes() const { return 0; }
  // Restart support: the state kept between steps (what accept() committed), as numbers, and its
  // restoration into a contribution built from the same case (InputError if the numbers do not fit).
  // Empty: the contribution keeps no such state.
  virtual std::vector<double> save_state() const { return {}; }
  virtual void restore_state(const std::vector<double>& /*state*/) {}
  // False if the tangent may be unsymmetric (follower moments, the RF1 coupling).
  virtual bool symmetric() const { return true; }
  // How many rows its tangent's skew part can touch: 0 for a symmetric tangent, -1 for any number.
  // (The solver path and memory estimate use it: a skew part on few rows is a low-rank correction.)
  virtual int skew_rows() const { return symmetric() ? 0 : -1; }
  // What the contribution saw in the last failed attempt that may explain it; empty if nothing.
  virtual std::string failure_hint() const { return {}; }
};

}  // namespace fibrane::model
