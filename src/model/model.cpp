#include "model/model.hpp"

#include "shell/edge_moment.hpp"
#include "spline/quadrature.hpp"

#include <chrono>
#include <cmath>
#include <limits>
#include <span>
#include <stdexcept>

namespace fibrane::model {

int Model::add_shell(ShellBody body) {
  body.block = dofs.add_block(body.name, body.num_control_points(), 3);
  shells.push_back(std::move(body));
  return static_cast<int>(shells.size()) - 1;
}

int Model::add_beam(BeamBody body) {
  body.block = dofs.add_block(body.name, body.num_control_points(), 4);
  body.initialise_states();
  beams.push_back(std::move(body));
  return static_cast<int>(beams.size()) - 1;
}

solve::CurveEval Model::curve_eval() const {
  return [this](int curve, double t) { return functions(curve, t); };
}

void Model::finalize() {
  constraints.finalize(dofs.size());
  std::vector<std::vector<int>> element_dofs;  // the fixed elements: shells, beams, loads
  for (const auto& s : shells) {
    shell_first_element_.push_back(static_cast<int>(element_dofs.size()));
    for (auto& d : s.element_dofs(dofs)) element_dofs.push_back(std::move(d));
  }
  for (const auto& b : beams) {
    beam_first_element_.push_back(static_cast<int>(element_dofs.size()));
    for (auto& d : b.element_dofs(dofs)) element_dofs.push_back(std::move(d));
  }
  moment_first_element_ = static_cast<int>(element_dofs.size());
  for (const auto& m : moments) {
    const auto all = beams[m.beam].element_dofs(dofs);
    element_dofs.push_back(all[m.element]);
  }
  for (const auto& em : edge_moments) {
    edge_moment_first_element_.push_back(static_cast<int>(element_dofs.size()));
    const auto all = shells[em.shell].element_dofs(dofs);
    for (int e : em.elements) element_dofs.push_back(all[e]);
  }
  assembler_.set_pattern(constraints, element_dofs);
  constrained_dofs_ = constraints.constrained_dofs();
  u_ = constraints.expand(initial_unknowns(), 0.0, curve_eval());
  for (auto& c : couplings) c.project(beams[c.beam()], shells[c.shell()], u_, dofs);
  rebuild_pattern();
  finalized_ = true;
}

void Model::rebuild_pattern() {
  // Only the coupling elements change: the shell, beam and load elements keep their pattern.
  std::vector<std::vector<int>> coupling_dofs;
  coupling_first_element_.clear();
  for (const auto& c : couplings) {
    coupling_first_element_.push_back(assembler_.num_fixed_elements() + static_cast<int>(coupling_dofs.size()));
    for (auto& d : c.pair_dofs(beams[c.beam()], shells[c.shell()], dofs)) coupling_dofs.push_back(std::move(d));
  }
  assembler_.set_variable_elements(coupling_dofs);
}

bool Model::symmetric() const {
  // The load stiffness of a point moment (Eq. 54, B8-B9) is not symmetric: M . delta omega is not the
  // variation of a potential for a fixed spatial M.
  if (!moments.empty()) return false;
  for (const auto& c : couplings)
    if (!c.symmetric()) return false;
  return true;
}

void Model::evaluate(const Eigen::VectorXd& q, double t, bool with_tangent) {
  if (!finalized_) throw std::logic_error("Model::evaluate before finalize");
  using clock = std::chrono::steady_clock;
  auto lap = [last = clock::now()](double& into) mutable {
    const auto now = clock::now();
    into += std::chrono::duration<double>(now - last).count();
    last = now;
  };
  ++times_.evaluations;
  if (with_tangent) ++times_.tangents;
  t_ = t;
  u_ = constraints.expand(q, t, curve_eval());
  bool pairs_changed = false;
  for (auto& c : couplings) pairs_changed |= c.project(beams[c.beam()], shells[c.shell()], u_, dofs);
  lap(times_.projection);
  if (pairs_changed) {
    rebuild_pattern();
    ++times_.pattern_rebuilds;
  }
  assembler_.begin(with_tangent);
  lap(times_.pattern);
  energy_ = 0.0;
  for (std::size_t i = 0; i < shells.size(); ++i)
    energy_ += shells[i].assemble(u_, dofs, assembler_, shell_first_element_[i], with_tangent);
  lap(times_.shell);
  for (std::size_t i = 0; i < beams.size(); ++i)
    energy_ += beams[i].assemble(u_, dofs, assembler_, beam_first_element_[i], with_tangent);
  lap(times_.beam);
  bool invalid = false;
  for (std::size_t i = 0; i < couplings.size(); ++i) {
    auto& c = couplings[i];
    bool bad = false;
    c.assemble(beams[c.beam()], shells[c.shell()], u_, dofs, assembler_, coupling_first_element_[i], with_tangent, bad);
    invalid |= bad;
  }
  lap(times_.interaction);
  for (std::size_t i = 0; i < moments.size(); ++i) {
    const auto& m = moments[i];
    const auto& b = beams[m.beam];
    const auto& cps = b.elements[m.element].control_points;
    const beam::BeamDofs qe = b.current(cps, u_, dofs);
    const int n = 4 * static_cast<int>(cps.size());
    Eigen::VectorXd r = Eigen::VectorXd::Zero(n);
    Eigen::MatrixXd k = Eigen::MatrixXd::Zero(n, n);
    const beam::BasisDerivs basis = b.curve.basis(m.xi, 2).R.topRows(3);
    beam::add_point_moment(functions(m.function, t) * m.moment, basis, qe, m.state, &r,
                           with_tangent ? &k : nullptr);
    assembler_.add(moment_first_element_ + static_cast<int>(i), r, with_tangent ? &k : nullptr);
  }
  for (std::size_t i = 0; i < edge_moments.size(); ++i)
    assemble_edge_moment(edge_moments[i], edge_moment_first_element_[i], with_tangent);
  if (invalid) {
    // A state outside the interaction law's domain (the beam inside the plate) has no residual: report a
    // non-finite one so that Newton fails cleanly and the continuation cuts the step back.
    const int dof0 = 0;
    assembler_.add_vector(std::span<const int>(&dof0, 1),
                          Eigen::VectorXd::Constant(1, std::numeric_limits<double>::quiet_NaN()));
  }
  double load_sq = 0.0;
  for (const auto& l : nodal_loads) {
    const double f = functions(l.function, t);
    assembler_.add_vector(l.dofs, -f * l.values);
    load_sq += f * f * l.values.squaredNorm();
  }
  assembler_.end();
  // The reference force level for Newton's relative tolerance: external loads, or, for problems driven by
  // prescribed displacements, the reactions they cause.
  double reaction_sq = 0.0;
  for (int d : constrained_dofs_) reaction_sq += full_residual()[d] * full_residual()[d];
  load_scale_ = std::sqrt(std::max(load_sq, reaction_sq));
  lap(times_.other);
}

void Model::assemble_edge_moment(const EdgeMoment& em, int first_element, bool with_tangent) {
  const auto& s = shells[em.shell];
  const bool u_edge = em.edge[0] == 'u';  // the edge lies at fixed u; v runs along it
  const bool at_end = em.edge[1] == '1';
  const int across = u_edge ? 1 : 2, along = u_edge ? 2 : 1;
  const double sign = at_end ? 1.0 : -1.0;  // outward derivative
  const auto g = spline::gauss_legendre(s.surface.degree(u_edge ? 1 : 0) + 1);
  const Eigen::Vector3d moment = functions(em.function, t_) * em.moment;
  for (std::size_t k = 0; k < em.elements.size(); ++k) {
    const auto& el = s.elements[em.elements[k]];
    const auto& cps = s.element_control_points[em.elements[k]];
    const Eigen::Matrix3Xd X = s.reference(cps), x = s.current(cps, u_, dofs);
    const int n = 3 * static_cast<int>(cps.size());
    Eigen::VectorXd r = Eigen::VectorXd::Zero(n);
    Eigen::MatrixXd kt = Eigen::MatrixXd::Zero(n, n);
    const double a = u_edge ? el.v0 : el.u0, b = u_edge ? el.v1 : el.u1, j = 0.5 * (b - a);
    const double fixed = u_edge ? (at_end ? el.u1 : el.u0) : (at_end ? el.v1 : el.v0);
    for (std::size_t q = 0; q < g.points.size(); ++q) {
      const double t = a + (g.points[q] + 1.0) * j;
      const auto basis = u_edge ? s.surface.basis_in(el.span_u, el.span_v, fixed, t)
                                : s.surface.basis_in(el.span_u, el.span_v, t, fixed);
      const double length = (X * basis.R.row(along).transpose()).norm();
      const Eigen::RowVectorXd dR = sign * basis.R.row(across);
      shell::add_edge_moment_point(moment, dR, x, g.weights[q] * j * length, &r, with_tangent ? &kt : nullptr);
    }
    assembler_.add(first_element + static_cast<int>(k), r, with_tangent ? &kt : nullptr);
  }
}

void Model::reject() {
  for (auto& c : couplings) c.reject();
}

std::string Model::failure_hint() const {
  std::string hint;
  for (const auto& c : couplings)
    if (const std::string h = c.failure_hint(); !h.empty()) hint += (hint.empty() ? "" : ". ") + h;
  return hint;
}

void Model::accept(const Eigen::VectorXd& q, double t) {
  u_ = constraints.expand(q, t, curve_eval());
  for (auto& b : beams) b.accept(u_, dofs);
  for (auto& c : couplings) c.accept();
  for (auto& m : moments) {
    const auto& b = beams[m.beam];
    const beam::BeamDofs qe = b.current(b.elements[m.element].control_points, u_, dofs);
    beam::update_point_state(m.state, b.curve.basis(m.xi, 2).R.topRows(3), qe);
  }
}

double Model::monitor_value(const Monitor& m) const {
  const Eigen::VectorXd& v = m.source == Monitor::Source::displacement ? u_ : full_residual();
  double s = m.offset;
  for (const auto& [dof, w] : m.weights) s += w * v[dof];
  return s;
}

}  // namespace fibrane::model
