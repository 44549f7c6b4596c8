#include "model/beam_body.hpp"

#include <algorithm>
#include <cmath>

#include "common/error.hpp"
#include "common/format.hpp"
#include "model/ordered_sum.hpp"
#include "common/parallel_errors.hpp"
#include "model/saved_state.hpp"
#include "linalg/dof_map.hpp"
#include "spline/quadrature.hpp"

namespace fibrane::model {

namespace {
beam::BasisDerivs basis_matrix(const spline::CurveBasis& b) { return b.R.topRows(3); }
}  // namespace

BeamBody::BeamBody(std::string n, spline::NurbsCurve c, beam::BeamSection s, Eigen::Vector3d d)
    : curve(std::move(c)), section(s), director(d), name_(std::move(n)) {
  const auto& kv = curve.knots();
  const int p = curve.degree();
  // The bending energy (Eq. 46) needs a C1 axis: at a C0 knot the displacement field may kink at no cost,
  // a hinge that makes the tangent singular (the case reader rejects such axes with a located message
  // first: casefile::check_no_kinks).
  const auto unique = kv.unique_knots();
  for (std::size_t k = 1; k + 1 < unique.size(); ++k)
    if (kv.multiplicity(unique[k]) >= p)
      throw InputError("beam '" + name_ + "': the axis is only C0 at xi = " + format_number(unique[k]) +
                       " (a knot of multiplicity " + std::to_string(kv.multiplicity(unique[k])) + " for degree " +
                       std::to_string(p) + "); a Bernoulli-Euler beam needs a C1 axis: use an arc of less than 360 "
                       "degrees or a NURBS axis without C0 knots");
  for (int span : kv.element_spans()) {
    BeamElement e;
    e.span = span;
    e.xi0 = kv.knots()[span];
    e.xi1 = kv.knots()[span + 1];
    for (int a = 0; a <= p; ++a) e.control_points.push_back(span - p + a);
    elements.push_back(std::move(e));
  }
  if (director.norm() == 0.0) build_rotation_minimising_frame();
}

void BeamBody::build_rotation_minimising_frame() {
  // Double reflection (Wang et al. 2008) on a fine sampling of the axis; a2 between samples is the
  // sample value projected onto the local normal plane, which is accurate to the sampling error.
  const int samples = 64 * static_cast<int>(elements.size()) + 1;
  const double a = curve.knots().front(), b = curve.knots().back();
  rmf_xi_.resize(samples);
  rmf_a2_.resize(samples);
  Eigen::Vector3d t0 = curve.derivative(a, 1).normalized();
  Eigen::Vector3d seed = std::abs(t0.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  if (std::abs(t0.z()) < std::abs(t0.dot(seed))) seed = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d r = (seed - seed.dot(t0) * t0).normalized();
  Eigen::Vector3d x0 = curve.point(a);
  rmf_xi_[0] = a;
  rmf_a2_[0] = r;
  for (int i = 1; i < samples; ++i) {
    const double xi = a + (b - a) * i / (samples - 1);
    const Eigen::Vector3d x1 = curve.point(xi), t1 = curve.derivative(xi, 1).normalized();
    const Eigen::Vector3d v1 = x1 - x0;
    const double c1 = v1.squaredNorm();
    Eigen::Vector3d rl = r, tl = t0;
    if (c1 > 0) {
      rl = r - (2.0 / c1) * v1.dot(r) * v1;
      tl = t0 - (2.0 / c1) * v1.dot(t0) * v1;
    }
    const Eigen::Vector3d v2 = t1 - tl;
    const double c2 = v2.squaredNorm();
    r = c2 > 0 ? Eigen::Vector3d(rl - (2.0 / c2) * v2.dot(rl) * v2) : rl;
    r = (r - r.dot(t1) * t1).normalized();
    rmf_xi_[i] = xi;
    rmf_a2_[i] = r;
    x0 = x1;
    t0 = t1;
  }
}

Eigen::Vector3d BeamBody::reference_director(double xi) const {
  const Eigen::Vector3d t = curve.derivative(xi, 1).normalized();
  Eigen::Vector3d d = director;
  if (director.norm() == 0.0) {
    const auto it = std::lower_bound(rmf_xi_.begin(), rmf_xi_.end(), xi);
    const std::size_t i = std::min<std::size_t>(it - rmf_xi_.begin(), rmf_xi_.size() - 1);
    d = rmf_a2_[i];
  }
  return (d - d.dot(t) * t).normalized();
}

int BeamBody::element_of(double xi) const {
  const int span = curve.knots().find_span(xi);
  // Elements are in increasing span order.
  const auto it = std::lower_bound(elements.begin(), elements.end(), span,
                                   [](const BeamElement& e, int s) { return e.span < s; });
  if (it != elements.end() && it->span == span) return static_cast<int>(it - elements.begin());
  return static_cast<int>(elements.size()) - 1;
}

beam::BeamPointState BeamBody::state_at(double xi) const {
  const auto b = curve.basis(xi, 2);
  const auto& cps = elements[element_of(xi)].control_points;
  Eigen::Matrix3Xd X(3, cps.size());
  for (std::size_t a = 0; a < cps.size(); ++a) X.col(a) = curve.control_points()[cps[a]];
  return beam::make_point_state(basis_matrix(b), X, reference_director(xi));
}

void BeamBody::initialise_states() {
  const auto g = spline::gauss_legendre(gauss());
  states.assign(elements.size(), {});
  for (std::size_t e = 0; e < elements.size(); ++e) {
    const auto& el = elements[e];
    for (double gp : g.points) {
      const double xi = el.xi0 + 0.5 * (gp + 1.0) * (el.xi1 - el.xi0);
      states[e].push_back(state_at(xi));
    }
  }
}

std::vector<std::vector<int>> BeamBody::element_dofs(const solve::DofMap& dofs) const {
  std::vector<std::vector<int>> out;
  for (const auto& el : elements) {
    std::vector<int> d;
    for (int cp : el.control_points)
      for (int c = 0; c < 4; ++c) d.push_back(dofs.dof(block, cp, c));
    out.push_back(std::move(d));
  }
  return out;
}

beam::BeamDofs BeamBody::current(const std::vector<int>& cps, const Eigen::VectorXd& u,
                                 const solve::DofMap& dofs) const {
  beam::BeamDofs q(4, cps.size());
  for (std::size_t a = 0; a < cps.size(); ++a) {
    q.col(a).head<3>() = curve.control_points()[cps[a]];
    q(3, a) = 0.0;  // the twist has no reference value
    for (int c = 0; c < 4; ++c) q(c, a) += u[dofs.dof(block, cps[a], c)];
  }
  return q;
}

double BeamBody::evaluate(const State& state, ElementSink& sink, Status& /*status*/) {
  const Eigen::VectorXd& u = state.u;
  const solve::DofMap& dofs = state.dofs;
  const bool with_tangent = sink.with_tangent();
  const auto g = spline::gauss_legendre(gauss());
  const int n_elements = static_cast<int>(elements.size());
  OrderedSum sum;  // static schedule, ordered sum: the same bits in every run with this thread count
  FirstError error;
#pragma omp parallel
  {
    double energy = 0.0;
    Eigen::VectorXd r;
    Eigen::MatrixXd k;
    sink.for_each_element(n_elements, 8, [&](int e) { error.run([&] {
      if (!sink.owns(e)) return;
      const auto& el = elements[e];
      const beam::BeamDofs q = current(el.control_points, u, dofs);
      const int n = 4 * static_cast<int>(el.control_points.size());
      r.setZero(n);
      if (with_tangent) k.setZero(n, n);
      const double j = 0.5 * (el.xi1 - el.xi0);
      for (std::size_t i = 0; i < g.points.size(); ++i) {
        const double xi = el.xi0 + (g.points[i] + 1.0) * j;
        const auto b = curve.basis(xi, 2);
        beam::add_beam_point(section, basis_matrix(b), q, states[e][i], share * g.weights[i] * j, &energy, &r,
                             with_tangent ? &k : nullptr);
      }
      sink.add(e, r, with_tangent ? &k : nullptr);
    }); });
    sum.set(energy);
  }
  error.rethrow();
  return sum.total();
}

void BeamBody::accept(const State& state) {
  const Eigen::VectorXd& u = state.u;
  const solve::DofMap& dofs = state.dofs;
  for (std::size_t p = 0; p < probe_xi_.size(); ++p) {
    const beam::BeamDofs q = current(elements[element_of(probe_xi_[p])].control_points, u, dofs);
    beam::update_point_state(probe_states_[p], basis_matrix(curve.basis(probe_xi_[p], 2)), q);
  }
  const auto g = spline::gauss_legendre(gauss());
  for (std::size_t e = 0; e < elements.size(); ++e) {
    const auto& el = elements[e];
    const beam::BeamDofs q = current(el.control_points, u, dofs);
    for (std::size_t i = 0; i < g.points.size(); ++i) {
      const double xi = el.xi0 + 0.5 * (g.points[i] + 1.0) * (el.xi1 - el.xi0);
      beam::update_point_state(states[e][i], basis_matrix(curve.basis(xi, 2)), q);
    }
  }
}

std::vector<double> BeamBody::save_state() const {
  StateWriter w;
  for (const auto& element : states)
    for (const auto& s : element) w.add(s);
  for (const auto& s : probe_states_) w.add(s);
  return w.take();
}

void BeamBody::restore_state(const std::vector<double>& state) {
  StateReader r(state, "beam '" + name_ + "'");
  for (auto& element : states)
    for (auto& s : element) s = r.next_point_state();
  for (auto& s : probe_states_) s = r.next_point_state();
  r.finish();
}

int BeamBody::add_probe(double xi) {
  probe_xi_.push_back(xi);
  probe_states_.push_back(state_at(xi));
  const auto& st = probe_states_.back();
  Eigen::Matrix3d reference;
  reference << st.frame_t, st.frame_d2, st.frame_d3;
  probe_reference_.push_back(reference);
  return static_cast<int>(probe_xi_.size()) - 1;
}

void BeamBody::set_output_samples(int samples) {
  output_samples_ = samples;
  output_first_ = static_cast<int>(probe_xi_.size());
  for (const auto& el : elements)
    for (int i = 0; i <= samples; ++i) {
      // Just inside the element, so that the basis (and the frame) belong to its span.
      const double s = std::clamp(static_cast<double>(i) / samples, 1e-12, 1.0 - 1e-12);
      add_probe(el.xi0 + (el.xi1 - el.xi0) * s);
    }
}

int BeamBody::add_twist_probes(double xi) {
  const auto g = spline::gauss_legendre(gauss());
  const double a = elements[element_of(xi)].xi0, j = 0.5 * (xi - a);
  int first = -1;
  for (double gp : g.points) {
    const int p = add_probe(a + (gp + 1.0) * j);
    if (first < 0) first = p;
  }
  return first;
}

beam::BeamPointOutput BeamBody::probe_output(int probe, const Eigen::VectorXd& u, const solve::DofMap& dofs) const {
  const double xi = probe_xi_[probe];
  const beam::BeamDofs q = current(elements[element_of(xi)].control_points, u, dofs);
  return beam::evaluate_point(section, basis_matrix(curve.basis(xi, 2)), q, probe_states_[probe]);
}

Eigen::Vector3d BeamBody::probe_rotation(int probe, const beam::BeamPointOutput& out) const {
  Eigen::Matrix3d current;
  current << out.t, out.a2, out.a3;
  const Eigen::AngleAxisd rotation(Eigen::Matrix3d(current * probe_reference_[probe].transpose()));
  return rotation.angle() * rotation.axis();
}

double BeamBody::twist_angle(double xi, int first_twist_probe, const Eigen::VectorXd& u,
                             const solve::DofMap& dofs) const {
  const auto g = spline::gauss_legendre(gauss());
  const int last = element_of(xi);
  double angle = 0;
  for (int e = 0; e < last; ++e) {  // whole elements before xi: their quadrature points
    const auto& el = elements[e];
    const beam::BeamDofs q = current(el.control_points, u, dofs);
    const double j = 0.5 * (el.xi1 - el.xi0);
    for (std::size_t i = 0; i < g.points.size(); ++i) {
      const double x = el.xi0 + (g.points[i] + 1.0) * j;
      angle += g.weights[i] * j * arc_length_weight(x) *
               beam::evaluate_point(section, basis_matrix(curve.basis(x, 2)), q, states[e][i]).kappa[0];
    }
  }
  const double j = 0.5 * (xi - elements[last].xi0);  // the part of xi's element: the twist probes
  for (std::size_t i = 0; i < g.points.size(); ++i) {
    const int p = first_twist_probe + static_cast<int>(i);
    angle += g.weights[i] * j * arc_length_weight(probe_xi_[p]) * probe_output(p, u, dofs).kappa[0];
  }
  return angle;
}

Eigen::VectorXd BeamBody::line_load(const Eigen::Vector3d& f) const {
  Eigen::VectorXd nodal = Eigen::VectorXd::Zero(3 * num_control_points());
  const auto g = spline::gauss_legendre(gauss());
  for (const auto& el : elements) {
    const double j = 0.5 * (el.xi1 - el.xi0);
    for (std::size_t q = 0; q < g.points.size(); ++q) {
      const double xi = el.xi0 + (g.points[q] + 1) * j;
      const auto basis = curve.basis(xi, 1);
      const double jb = curve.derivative(xi, 1).norm();
      for (int a = 0; a < basis.R.cols(); ++a)
        nodal.segment<3>(3 * (basis.first + a)) += g.weights[q] * j * jb * basis.R(0, a) * f;
    }
  }
  return nodal;
}

}  // namespace fibrane::model
