#include "model/inertia.hpp"

#include "common/parallel_errors.hpp"
#include "model/beam_body.hpp"
#include "model/shell_body.hpp"
#include "linalg/dof_map.hpp"
#include "spline/quadrature.hpp"

namespace fibrane::model {
namespace {

// int N_A N_B dA over a shell element (reference area, the body's quadrature).
Eigen::MatrixXd shell_scalar_mass(const ShellBody& s, std::size_t e) {
  const auto& el = s.elements[e];
  const int n = static_cast<int>(s.element_control_points[e].size());
  const auto gu = spline::gauss_legendre(s.gauss(0)), gv = spline::gauss_legendre(s.gauss(1));
  const double ju = 0.5 * (el.u1 - el.u0), jv = 0.5 * (el.v1 - el.v0);
  const Eigen::Matrix3Xd X = s.reference(s.element_control_points[e]);
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(n, n);
  for (std::size_t j = 0; j < gv.points.size(); ++j)
    for (std::size_t i = 0; i < gu.points.size(); ++i) {
      const double pu = el.u0 + (gu.points[i] + 1) * ju, pv = el.v0 + (gv.points[j] + 1) * jv;
      const auto b = s.surface.basis_in(el.span_u, el.span_v, pu, pv);
      const Eigen::Vector3d g1 = X * b.R.row(1).transpose(), g2 = X * b.R.row(2).transpose();
      const double w = gu.weights[i] * gv.weights[j] * ju * jv * g1.cross(g2).norm();
      m += w * b.R.row(0).transpose() * b.R.row(0);
    }
  return m;
}

// int N_A N_B ds over a beam element (reference arc length).
Eigen::MatrixXd beam_scalar_mass(const BeamBody& b, std::size_t e) {
  const auto& el = b.elements[e];
  const int n = static_cast<int>(el.control_points.size());
  const auto g = spline::gauss_legendre(b.gauss());
  const double j = 0.5 * (el.xi1 - el.xi0);
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(n, n);
  for (std::size_t q = 0; q < g.points.size(); ++q) {
    const double xi = el.xi0 + (g.points[q] + 1) * j;
    const auto basis = b.curve.basis(xi, 1);
    const double w = g.weights[q] * j * b.curve.derivative(xi, 1).norm();
    m += w * basis.R.row(0).transpose() * basis.R.row(0);
  }
  return m;
}

}  // namespace

Inertia::Inertia(const std::vector<const ShellBody*>& shells, const std::vector<const BeamBody*>& beams,
                 const solve::DofMap& dofs) {
  for (const ShellBody* s : shells) {
    const auto element_dofs = s->element_dofs(dofs);
    const double per_area = s->density * s->section.thickness;
    for (std::size_t e = 0; e < s->elements.size(); ++e) {
      dofs_.push_back(element_dofs[e]);
      scalar_.push_back(shell_scalar_mass(*s, e));
      factor_.push_back({per_area, per_area, per_area});
    }
  }
  for (const BeamBody* b : beams) {
    const auto element_dofs = b->element_dofs(dofs);
    // A beam lying in a symmetry plane of the model carries its share of the mass, as of its stiffness.
    const double per_length = b->share * b->density * b->section.area;
    const double polar = b->share * b->density * (b->section.inertia2 + b->section.inertia3);
    for (std::size_t e = 0; e < b->elements.size(); ++e) {
      dofs_.push_back(element_dofs[e]);
      scalar_.push_back(beam_scalar_mass(*b, e));
      factor_.push_back({per_length, per_length, per_length, polar});
    }
  }
}

Eigen::MatrixXd Inertia::element_matrix(int e) const {
  const auto& m = scalar_[e];
  const int c = static_cast<int>(factor_[e].size()), n = static_cast<int>(m.rows());
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(n * c, n * c);
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b)
      for (int i = 0; i < c; ++i) k(c * a + i, c * b + i) = factor_[e][i] * m(a, b);
  return k;
}

double Inertia::evaluate(const State& s, ElementSink& sink, Status& /*status*/) {
  if (!step_) return 0.0;
  const int n_elements = num_elements();
  FirstError error;
#pragma omp parallel
  sink.for_each_element(n_elements, 16, [&](int e) { error.run([&] {
    if (!sink.owns(e)) return;
    const auto& d = dofs_[e];
    Eigen::VectorXd w(static_cast<Eigen::Index>(d.size()));
    for (std::size_t i = 0; i < d.size(); ++i) w[static_cast<Eigen::Index>(i)] = step_->inertia(d[i], s.u[d[i]]);
    const Eigen::MatrixXd m = element_matrix(e);
    const Eigen::VectorXd r = m * w;
    if (sink.with_tangent()) {
      const Eigen::MatrixXd k = step_->mass_factor * m;
      sink.add(e, r, &k);
    } else {
      sink.add(e, r, nullptr);
    }
  }); });
  error.rethrow();
  return 0.0;  // the kinetic energy needs the velocity: the time integrator keeps it
}

Eigen::VectorXd Inertia::times(const Eigen::VectorXd& x) const {
  Eigen::VectorXd y = Eigen::VectorXd::Zero(x.size());
  for (int e = 0; e < num_elements(); ++e) {
    const auto& d = dofs_[e];
    Eigen::VectorXd xe(static_cast<Eigen::Index>(d.size()));
    for (std::size_t i = 0; i < d.size(); ++i) xe[static_cast<Eigen::Index>(i)] = x[d[i]];
    const Eigen::VectorXd ye = element_matrix(e) * xe;
    for (std::size_t i = 0; i < d.size(); ++i) y[d[i]] += ye[static_cast<Eigen::Index>(i)];
  }
  return y;
}

double Inertia::total_mass() const {
  double sum = 0;
  for (std::size_t e = 0; e < scalar_.size(); ++e) sum += factor_[e][0] * scalar_[e].sum();
  return sum;
}

}  // namespace fibrane::model
