#include "model/loads.hpp"

#include "model/beam_body.hpp"
#include "model/load_function.hpp"
#include "model/saved_state.hpp"
#include "model/shell_body.hpp"
#include "shell/edge_moment.hpp"
#include "linalg/dof_map.hpp"
#include "spline/quadrature.hpp"

namespace fibrane::model {

NodalLoad NodalLoad::from_nodal(const solve::DofMap& dofs, int block, const Eigen::VectorXd& nodal, int per_node,
                                int function, bool keep_zeros) {
  NodalLoad load;
  load.function = function;
  std::vector<double> values;
  const int nodes = static_cast<int>(nodal.size()) / per_node;
  for (int node = 0; node < nodes; ++node)
    for (int c = 0; c < per_node; ++c)
      if (keep_zeros || nodal[per_node * node + c] != 0.0) {
        load.dofs.push_back(dofs.dof(block, node, c));
        values.push_back(nodal[per_node * node + c]);
      }
  load.values = Eigen::Map<const Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size()));
  return load;
}

double NodalLoads::evaluate(const State& s, ElementSink& sink, Status& /*status*/) {
  double energy = 0;
  if (!sink.owns_global()) return energy;
  for (const auto& l : loads) {
    const double f = s.functions(l.function, s.t);
    sink.add_vector(l.dofs, -f * l.values);  // residual = internal - external
    if (sink.with_rate()) sink.add_rate(l.dofs, -s.functions.derivative(l.function, s.t) * l.values);
    for (std::size_t k = 0; k < l.dofs.size(); ++k) energy -= f * l.values[static_cast<Eigen::Index>(k)] * s.u[l.dofs[k]];
  }
  return energy;
}

double NodalLoads::squared_norm(const State& s) const {
  double sum = 0;
  for (const auto& l : loads) {
    const double f = s.functions(l.function, s.t);
    sum += f * f * l.values.squaredNorm();
  }
  return sum;
}

PointMoment::PointMoment(const BeamBody& beam, double xi, Eigen::Vector3d moment, int function, bool follower)
    : beam_(beam), xi_(xi), moment_(std::move(moment)), function_(function), element_(beam.element_of(xi)),
      follower_(follower), state_(beam.state_at(xi)) {}

void PointMoment::add(const Eigen::Vector3d& m, const beam::BasisDerivs& basis, const beam::BeamDofs& q,
                      Eigen::VectorXd* r, Eigen::MatrixXd* k) const {
  if (follower_) beam::add_follower_point_moment(m, basis, q, state_, r, k);
  else beam::add_point_moment(m, basis, q, state_, r, k);
}

std::vector<std::vector<int>> PointMoment::element_dofs(const solve::DofMap& dofs) const {
  return {beam_.element_dofs(dofs)[static_cast<std::size_t>(element_)]};
}

int PointMoment::skew_rows() const {
  return 4 * static_cast<int>(beam_.elements[static_cast<std::size_t>(element_)].control_points.size());
}

double PointMoment::evaluate(const State& s, ElementSink& sink, Status& /*status*/) {
  if (!sink.owns(0)) return 0.0;
  const auto& cps = beam_.elements[element_].control_points;
  const beam::BeamDofs qe = beam_.current(cps, s.u, s.dofs);
  const int n = 4 * static_cast<int>(cps.size());
  const beam::BasisDerivs basis = beam_.curve.basis(xi_, 2).R.topRows(3);
  Eigen::VectorXd r = Eigen::VectorXd::Zero(n);
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(n, n);
  add(s.functions(function_, s.t) * moment_, basis, qe, &r, sink.with_tangent() ? &k : nullptr);
  sink.add(0, r, sink.with_tangent() ? &k : nullptr);
  if (sink.with_rate()) {  // the residual is linear in the moment
    Eigen::VectorXd r_t = Eigen::VectorXd::Zero(n);
    add(s.functions.derivative(function_, s.t) * moment_, basis, qe, &r_t, nullptr);
    sink.add_rate(element_dofs(s.dofs).front(), r_t);
  }
  return 0.0;  // a follower moment has no potential
}

void PointMoment::accept(const State& s) {
  const beam::BeamDofs qe = beam_.current(beam_.elements[element_].control_points, s.u, s.dofs);
  beam::update_point_state(state_, beam_.curve.basis(xi_, 2).R.topRows(3), qe);
}

std::vector<double> PointMoment::save_state() const {
  StateWriter w;
  w.add(state_);
  return w.take();
}

void PointMoment::restore_state(const std::vector<double>& state) {
  StateReader r(state, "a point moment");
  state_ = r.next_point_state();
  r.finish();
}

EdgeMoment::EdgeMoment(const ShellBody& shell, std::string edge, Eigen::Vector3d moment, int function)
    : shell_(shell), edge_(std::move(edge)), moment_(std::move(moment)), function_(function),
      elements_(shell.edge_elements(edge_)) {}

std::vector<std::vector<int>> EdgeMoment::element_dofs(const solve::DofMap& dofs) const {
  const auto all = shell_.element_dofs(dofs);
  std::vector<std::vector<int>> out;
  for (int e : elements_) out.push_back(all[static_cast<std::size_t>(e)]);
  return out;
}

void EdgeMoment::element(int k, const Eigen::Vector3d& m, const State& s, Eigen::VectorXd& r,
                         Eigen::MatrixXd* kt) const {
  const bool u_edge = edge_[0] == 'u';  // the edge lies at fixed u; v runs along it
  const bool at_end = edge_[1] == '1';
  const int across = u_edge ? 1 : 2, along = u_edge ? 2 : 1;
  const double sign = at_end ? 1.0 : -1.0;  // outward derivative
  const auto g = spline::gauss_legendre(shell_.surface.degree(u_edge ? 1 : 0) + 1);
  const auto& el = shell_.elements[elements_[k]];
  const auto& cps = shell_.element_control_points[elements_[k]];
  const Eigen::Matrix3Xd X = shell_.reference(cps), x = shell_.current(cps, s.u, s.dofs);
  const int n = 3 * static_cast<int>(cps.size());
  r = Eigen::VectorXd::Zero(n);
  if (kt) *kt = Eigen::MatrixXd::Zero(n, n);
  const double a = u_edge ? el.v0 : el.u0, b = u_edge ? el.v1 : el.u1, j = 0.5 * (b - a);
  const double fixed = u_edge ? (at_end ? el.u1 : el.u0) : (at_end ? el.v1 : el.v0);
  for (std::size_t q = 0; q < g.points.size(); ++q) {
    const double t = a + (g.points[q] + 1.0) * j;
    const auto basis = u_edge ? shell_.surface.basis_in(el.span_u, el.span_v, fixed, t)
                              : shell_.surface.basis_in(el.span_u, el.span_v, t, fixed);
    const double length = (X * basis.R.row(along).transpose()).norm();
    const Eigen::RowVectorXd dR = sign * basis.R.row(across);
    shell::add_edge_moment_point(m, dR, x, g.weights[q] * j * length, &r, kt);
  }
}

double EdgeMoment::evaluate(const State& s, ElementSink& sink, Status& /*status*/) {
  const Eigen::Vector3d m = s.functions(function_, s.t) * moment_;
  const auto dofs = sink.with_rate() ? element_dofs(s.dofs) : std::vector<std::vector<int>>{};
  Eigen::VectorXd r;
  Eigen::MatrixXd kt;
  for (std::size_t k = 0; k < elements_.size(); ++k) {
    if (!sink.owns(static_cast<int>(k))) continue;
    element(static_cast<int>(k), m, s, r, sink.with_tangent() ? &kt : nullptr);
    sink.add(static_cast<int>(k), r, sink.with_tangent() ? &kt : nullptr);
    if (sink.with_rate()) {  // the residual is linear in the moment
      element(static_cast<int>(k), s.functions.derivative(function_, s.t) * moment_, s, r, nullptr);
      sink.add_rate(dofs[k], r);
    }
  }
  return 0.0;  // the edge rotation's potential is not tracked (its angle is never formed)
}

}  // namespace fibrane::model
