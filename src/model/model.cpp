#include "model/model.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <omp.h>

#include "common/error.hpp"
#include "linalg/rank_one_terms.hpp"
#include "model/ordered_sum.hpp"

namespace fibrane::model {

ShellBody& Model::add_shell(ShellBody body) {
  body.block = dofs.add_block(body.name(), body.num_control_points(), 3);
  return shells.emplace_back(std::move(body));
}

BeamBody& Model::add_beam(BeamBody body) {
  body.block = dofs.add_block(body.name(), body.num_control_points(), 4);
  body.initialise_states();
  return beams.emplace_back(std::move(body));
}

Interaction& Model::add_interaction(std::unique_ptr<Interaction> i) {
  if (finalized_) throw std::logic_error("Model::add_interaction after finalize");
  return *interactions_.emplace_back(std::move(i));
}

Contribution& Model::add_contribution(std::unique_ptr<Contribution> c) {
  if (finalized_) throw std::logic_error("Model::add_contribution after finalize");
  return *extra_.emplace_back(std::move(c));
}

solve::CurveEval Model::curve_eval() const {
  return [this](int curve, double t) { return functions(curve, t); };
}

void Model::finalize() {
  constraints.finalize(dofs.size());
  // Evaluation order: bodies, interactions, moments, loads, then the others; element ids: the fixed
  // contributions' elements first, then the variable ones (set_variable_elements).
  entries_.clear();
  for (auto& s : shells) entries_.push_back({&s, 0, &PhaseTimes::shell});
  for (auto& b : beams) entries_.push_back({&b, 0, &PhaseTimes::beam});
  for (auto& i : interactions_) entries_.push_back({i.get(), 0, &PhaseTimes::interaction});
  for (auto& m : moments) entries_.push_back({&m, 0, &PhaseTimes::other});
  for (auto& e : edge_moments) entries_.push_back({&e, 0, &PhaseTimes::other});
  entries_.push_back({&nodal_loads, 0, &PhaseTimes::other});
  if (inertia) {
    std::vector<const ShellBody*> s;
    std::vector<const BeamBody*> b;
    for (const auto& x : shells) s.push_back(&x);
    for (const auto& x : beams) b.push_back(&x);
    inertia_ = std::make_unique<Inertia>(s, b, dofs);
    entries_.push_back({inertia_.get(), 0, &PhaseTimes::other});
  }
  for (auto& c : extra_) entries_.push_back({c.get(), 0, &PhaseTimes::other});
  for (auto& e : entries_)
    if (e.contribution->energy_kind() == EnergyKind::external) e.dofs = e.contribution->element_dofs(dofs);
  std::vector<std::vector<int>> element_dofs;
  for (auto& e : entries_) {
    if (e.contribution->variable()) continue;
    e.first_element = static_cast<int>(element_dofs.size());
    for (auto& d : e.contribution->element_dofs(dofs)) element_dofs.push_back(std::move(d));
  }
  owned_.clear();
  share(element_dofs, 0, true);
  assembler_.set_pattern(constraints, element_dofs);
  reference_magnitude_.assign(static_cast<std::size_t>(dofs.size()), 0.0);
  for (const auto& s : shells)
    for (int a = 0; a < s.num_control_points(); ++a)
      for (int c = 0; c < 3; ++c)
        reference_magnitude_[static_cast<std::size_t>(dofs.dof(s.block, a, c))] = std::abs(s.surface.control_points()[a][c]);
  for (const auto& b : beams)
    for (int a = 0; a < b.num_control_points(); ++a) {
      for (int c = 0; c < 3; ++c)
        reference_magnitude_[static_cast<std::size_t>(dofs.dof(b.block, a, c))] = std::abs(b.curve.control_points()[a][c]);
      reference_magnitude_[static_cast<std::size_t>(dofs.dof(b.block, a, 3))] = 1.0;
    }
  constrained_dofs_ = constraints.constrained_dofs();
  u_ = constraints.expand(initial_unknowns(), 0.0, curve_eval());
  for (auto& e : entries_)
    if (e.contribution->variable()) e.contribution->update(state());
  rebuild_variable_elements();
  finalized_ = true;
}

void Model::rebuild_variable_elements() {
  // Only the variable contributions' elements change: the fixed ones keep their pattern.
  std::vector<std::vector<int>> element_dofs;
  for (auto& e : entries_) {
    if (!e.contribution->variable()) continue;
    e.first_element = assembler_.num_fixed_elements() + static_cast<int>(element_dofs.size());
    for (auto& d : e.contribution->element_dofs(dofs)) element_dofs.push_back(std::move(d));
  }
  share(element_dofs, assembler_.num_fixed_elements(), false);
  assembler_.set_variable_elements(element_dofs);
}

void Model::set_distribution(const solve::Distribution* d) {
  if (finalized_) throw std::logic_error("Model::set_distribution after finalize");
  distribution_ = d;
}

void Model::share(std::vector<std::vector<int>>& element_dofs, int first, bool fixed) {
  if (!distribution_) return;
  owned_.resize(static_cast<size_t>(first));
  const int n = constraints.num_free();
  const auto unknowns = solve::element_unknowns(constraints, element_dofs);
  if (fixed) partition_ = solve::partition_elements(unknowns, element_dofs, n, *distribution_);
  for (std::size_t e = 0; e < element_dofs.size(); ++e) {
    const int owner = fixed ? partition_.element_owner[e] : solve::smallest_unknown_owner(unknowns[e], partition_.unknowns);
    owned_.push_back(owner == distribution_->rank());
    if (!owned_.back()) element_dofs[e].clear();
  }
}

void Model::agree(bool with_tangent) {
  std::array<double, 5> sums{energies_[0], energies_[1], energies_[2], energies_[3], status_.valid ? 0.0 : 1.0};
  distribution_->sum(sums);
  std::copy_n(sums.begin(), 4, energies_);
  if (sums[4] > 0) status_ = Status::invalid(distribution_->first_text(status_.valid ? std::string() : status_.reason));
  if (inertia_) distribution_->sum({external_.data(), static_cast<size_t>(external_.size())});
  if (with_tangent) tangent_finite_ = distribution_->all(NonlinearSystem::tangent_finite());
}

bool Model::tangent_finite() const {
  return distribution_ ? tangent_finite_ : NonlinearSystem::tangent_finite();
}

Eigen::VectorXd Model::tangent_times(const Eigen::VectorXd& x) const {
  Eigen::VectorXd y = tangent() * x;
  if (distribution_) distribution_->sum({y.data(), static_cast<size_t>(y.size())});
  return y;
}

// From the contributions themselves rather than the evaluation list, so that both hold before finalize()
// as well (the case reader's memory estimate picks the solver path with them). Inertia is symmetric.
int Model::skew_rows() const {
  int rows = 0;
  const auto add = [&rows](const Contribution& c) {
    const int n = c.skew_rows();
    rows = rows < 0 || n < 0 ? -1 : rows + n;
  };
  for (const auto& c : shells) add(c);
  for (const auto& c : beams) add(c);
  for (const auto& c : interactions_) add(*c);
  for (const auto& c : moments) add(c);
  for (const auto& c : edge_moments) add(c);
  add(nodal_loads);
  for (const auto& c : extra_) add(*c);
  return rows;
}

bool Model::symmetric() const { return skew_rows() == 0; }

std::optional<std::vector<int>> Model::skew_candidates() const {
  if (!finalized_) return std::nullopt;
  std::vector<std::vector<int>> element_dofs;
  for (const auto& e : entries_)
    if (!e.contribution->symmetric())
      for (auto& d : e.contribution->element_dofs(dofs)) element_dofs.push_back(std::move(d));
  std::vector<int> rows;
  for (const auto& unknowns : solve::element_unknowns(constraints, element_dofs))
    rows.insert(rows.end(), unknowns.begin(), unknowns.end());
  std::sort(rows.begin(), rows.end());
  rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
  return rows;
}

void Model::evaluate(const Eigen::VectorXd& q, double t, bool with_tangent) {
  evaluate_elements(q, t, with_tangent, nullptr);
}

void Model::evaluate_elements(const Eigen::VectorXd& q, double t, bool with_tangent, const std::vector<int>* rows,
                              solve::RankOneTerms* apart) {
  if (!finalized_) throw std::logic_error("Model::evaluate before finalize");
  using clock = std::chrono::steady_clock;
  auto lap = [last = clock::now()](double& into) mutable {
    const auto now = clock::now();
    into += std::chrono::duration<double>(now - last).count();
    last = now;
  };
  ++times_.evaluations;
  if (with_tangent) ++(rows ? times_.partial_tangents : times_.tangents);
  t_ = t;
  u_ = constraints.expand(q, t, curve_eval());
  if (!u_.allFinite() || !std::isfinite(t)) {
    evaluate_non_finite(with_tangent);
    return;
  }
  bool changed = false;
  for (auto& e : entries_)
    if (e.contribution->variable()) changed |= e.contribution->update(state());
  lap(times_.projection);
  if (changed) {
    rebuild_variable_elements();
    ++times_.pattern_rebuilds;
  }
  // d r / d t comes with every tangent: the assembler applies the element matrices to dg/dt.
  if (with_tangent)
    prescribed_rate_ = constraints.prescribed_rate(t, [this](int curve, double s) { return functions.derivative(curve, s); });
  assembler_.begin(with_tangent, with_tangent ? &prescribed_rate_ : nullptr);
  lap(times_.pattern);
  for (double& e : energies_) e = 0.0;
  status_ = Status{};
  external_.setZero(dofs.size());
  const State s = state();
  // The elements to evaluate: this process's (distributed), of them those that meet `rows` (partial).
  std::vector<char> meets = rows ? elements_meeting(*rows) : std::vector<char>();
  if (rows && distribution_)
    for (std::size_t k = 0; k < meets.size(); ++k) meets[k] = meets[k] && k < owned_.size() && owned_[k];
  const std::vector<char>* only = rows ? &meets : distribution_ ? &owned_ : nullptr;
  for (auto& e : entries_) {
    ElementSink sink(assembler_, e.first_element, with_tangent, with_tangent, only, distribution_);
    sink.hold_rank_one_apart(apart);
    if (e.contribution->energy_kind() == EnergyKind::external) sink.record_external(&external_, &e.dofs);
    energies_[static_cast<int>(e.contribution->energy_kind())] += e.contribution->evaluate(s, sink, status_);
    lap(times_.*e.time);
  }
  assembler_.end(distribution_);
  if (distribution_) agree(with_tangent);
  if (rows) {
    lap(times_.other);
    return;
  }
  // The reference force level for Newton's relative tolerance: external loads, or, for problems driven by
  // prescribed displacements, the reactions they cause.
  double reaction_sq = 0.0;
  for (int d : constrained_dofs_) reaction_sq += full_residual()[d] * full_residual()[d];
  load_scale_ = std::sqrt(std::max(nodal_loads.squared_norm(s), reaction_sq));
  if (with_tangent) roundoff_floor_ = estimate_roundoff_floor();
  lap(times_.other);
}

void Model::evaluate_non_finite(bool with_tangent) {
  for (double& e : energies_) e = 0.0;
  status_ = Status::invalid("an unknown or the time is not finite (overflow)");
  external_.setZero(dofs.size());
  assembler_.begin(with_tangent, nullptr);
  assembler_.end(distribution_);
  if (distribution_) agree(with_tangent);
  load_scale_ = 0.0;
  roundoff_floor_ = 0.0;
}

double Model::estimate_roundoff_floor() const {
  const auto& k = tangent();
  OrderedSum total;  // static schedule, ordered sum: the same bits in every run with this thread count
#pragma omp parallel if (k.nonZeros() > 200000)
  {
    double part = 0.0;
#pragma omp for schedule(static)
    for (int j = 0; j < static_cast<int>(k.outerSize()); ++j) {
      const auto d = static_cast<std::size_t>(constraints.free_dof(j));
      const double x = reference_magnitude_[d] + std::abs(u_[static_cast<Eigen::Index>(d)]);
      double column = 0.0;
      for (Eigen::SparseMatrix<double>::InnerIterator it(k, j); it; ++it) column += it.value() * it.value();
      part += column * x * x;
    }
    total.set(part);
  }
  double sum = total.total();
  if (distribution_) distribution_->sum({&sum, 1});
  return std::numeric_limits<double>::epsilon() * std::sqrt(sum);
}

void Model::reject() {
  for (auto& e : entries_) e.contribution->reject();
}

void Model::withdraw() {
  for (auto& e : entries_) e.contribution->withdraw();
}

std::vector<double> Model::event_margins() const {
  std::vector<double> margins;
  for (const auto& e : entries_) {
    const std::vector<double> own = e.contribution->event_margins();
    margins.insert(margins.end(), own.begin(), own.end());
  }
  return margins;
}

long Model::model_changes() const {
  long changes = 0;
  for (const auto& e : entries_) changes += e.contribution->model_changes();
  return changes;
}

std::string Model::failure_hint() const {
  std::string hint;
  for (const auto& e : entries_)
    if (const std::string h = e.contribution->failure_hint(); !h.empty()) hint += (hint.empty() ? "" : ". ") + h;
  return hint;
}

void Model::accept(const Eigen::VectorXd& q, double t) {
  t_ = t;
  u_ = constraints.expand(q, t, curve_eval());
  for (auto& e : entries_) e.contribution->accept(state());
}

solve::MethodState Model::save_state() const {
  solve::MethodState state;
  for (std::size_t k = 0; k < entries_.size(); ++k)
    if (auto values = entries_[k].contribution->save_state(); !values.empty())
      state[std::to_string(k) + " " + entries_[k].contribution->name()] = std::move(values);
  return state;
}

void Model::restore_state(const solve::MethodState& state) {
  std::size_t used = 0;
  for (std::size_t k = 0; k < entries_.size(); ++k) {
    const auto it = state.find(std::to_string(k) + " " + entries_[k].contribution->name());
    if (it == state.end()) {
      if (entries_[k].contribution->save_state().empty()) continue;
      throw InputError("checkpoint: it lacks the saved state of " + entries_[k].contribution->name());
    }
    entries_[k].contribution->restore_state(it->second);
    ++used;
  }
  if (used != state.size())
    throw InputError("checkpoint: its saved contributions do not match the case's bodies, interactions and loads");
  rebuild_variable_elements();
}

void Model::begin_step(const solve::StepKinematics* step) {
  if (!inertia_) throw std::logic_error("Model::begin_step: the model has no inertia (enable it before finalize)");
  inertia_->set_step(step);
}

Eigen::VectorXd Model::prescribed_motion(double t, int order) const {
  if (order == 0) return constraints.expand(Eigen::VectorXd::Zero(constraints.num_free()), t, curve_eval());
  return constraints.prescribed_rate(t, [this, order](int curve, double s) { return functions.derivative(curve, s, order); });
}

Eigen::VectorXd Model::mass_times(const Eigen::VectorXd& x) const {
  if (!inertia_) throw std::logic_error("Model::mass_times: the model has no inertia");
  return inertia_->times(x);
}

const Eigen::SparseMatrix<double>& Model::reduced_mass() {
  if (!inertia_) throw std::logic_error("Model::reduced_mass: the model has no inertia");
  if (mass_.rows() == 0) {
    std::vector<std::vector<int>> element_dofs = inertia_->element_dofs(dofs);
    solve::SparseAssembler a;
    a.set_pattern(constraints, element_dofs);
    a.begin(true);
    for (int e = 0; e < inertia_->num_elements(); ++e) {
      const Eigen::MatrixXd m = inertia_->element_matrix(e);
      a.add(e, Eigen::VectorXd::Zero(m.rows()), &m);
    }
    a.end();
    mass_ = a.matrix();
  }
  return mass_;
}

}  // namespace fibrane::model
