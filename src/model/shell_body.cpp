#include "model/shell_body.hpp"

#include <omp.h>

#include "model/ordered_sum.hpp"
#include "common/parallel_errors.hpp"
#include "linalg/dof_map.hpp"
#include "spline/basis.hpp"
#include "spline/quadrature.hpp"

namespace fibrane::model {

ShellBody::ShellBody(std::string n, spline::NurbsSurface s, shell::ShellSection sec)
    : surface(std::move(s)), section(sec), name_(std::move(n)) {
  elements = surface.elements();
  element_control_points.reserve(elements.size());
  for (const auto& e : elements) {
    const double uc = 0.5 * (e.u0 + e.u1), vc = 0.5 * (e.v0 + e.v1);
    element_control_points.push_back(surface.basis_in(e.span_u, e.span_v, uc, vc).indices);
  }
}

std::vector<std::vector<int>> ShellBody::element_dofs(const solve::DofMap& dofs) const {
  std::vector<std::vector<int>> out;
  out.reserve(elements.size());
  for (const auto& cps : element_control_points) {
    std::vector<int> d;
    d.reserve(3 * cps.size());
    for (int cp : cps)
      for (int c = 0; c < 3; ++c) d.push_back(dofs.dof(block, cp, c));
    out.push_back(std::move(d));
  }
  return out;
}

Eigen::Matrix3Xd ShellBody::reference(const std::vector<int>& cps) const {
  Eigen::Matrix3Xd X;
  reference(cps, X);
  return X;
}

void ShellBody::reference(const std::vector<int>& cps, Eigen::Matrix3Xd& X) const {
  X.resize(3, static_cast<Eigen::Index>(cps.size()));
  for (std::size_t a = 0; a < cps.size(); ++a) X.col(static_cast<Eigen::Index>(a)) = surface.control_points()[cps[a]];
}

Eigen::Matrix3Xd ShellBody::current(const std::vector<int>& cps, const Eigen::VectorXd& u,
                                    const solve::DofMap& dofs) const {
  Eigen::Matrix3Xd x;
  current(cps, u, dofs, x);
  return x;
}

void ShellBody::current(const std::vector<int>& cps, const Eigen::VectorXd& u, const solve::DofMap& dofs,
                        Eigen::Matrix3Xd& x) const {
  reference(cps, x);
  for (std::size_t a = 0; a < cps.size(); ++a)
    for (int c = 0; c < 3; ++c) x(c, static_cast<Eigen::Index>(a)) += u[dofs.dof(block, cps[a], c)];
}

double ShellBody::evaluate(const State& state, ElementSink& sink, Status& /*status*/) {
  const Eigen::VectorXd& u = state.u;
  const solve::DofMap& dofs = state.dofs;
  const bool with_tangent = sink.with_tangent();
  const auto gu = spline::gauss_legendre(gauss(0));
  const auto gv = spline::gauss_legendre(gauss(1));
  const int n_elements = static_cast<int>(elements.size());
  // The 1-D bases at the Gauss points, per element column (u) and row (v): the tensor product per point
  // is then a few multiplications (evaluating both at every point cost ~28 % of the assembly).
  const int n_u = surface.knots(0).num_elements();
  auto at_gauss = [](const spline::KnotVector& kv, int span, double t0, double t1, double g) {
    return spline::bspline_basis_derivs(kv, span, t0 + (g + 1.0) * 0.5 * (t1 - t0), 2);
  };
  std::vector<Eigen::MatrixXd> along_u, along_v;
  for (int iu = 0; iu < n_u; ++iu)  // the first element row holds every column
    for (double g : gu.points)
      along_u.push_back(at_gauss(surface.knots(0), elements[iu].span_u, elements[iu].u0, elements[iu].u1, g));
  for (int e = 0; e < n_elements; e += n_u)  // the first element of each row
    for (double g : gv.points)
      along_v.push_back(at_gauss(surface.knots(1), elements[e].span_v, elements[e].v0, elements[e].v1, g));
  OrderedSum sum;  // static schedule, ordered sum: the same bits in every run with this thread count
  FirstError error;
#pragma omp parallel
  {
    double energy = 0.0;
    spline::SurfaceBasis basis;
    Eigen::VectorXd r;
    Eigen::MatrixXd k;
    Eigen::Matrix3Xd X, x;
    shell::ElementTangent element_tangent;
    sink.for_each_element(n_elements, 16, [&](int e) { error.run([&] {
      if (!sink.owns(e)) return;
      const auto& el = elements[e];
      const auto& cps = element_control_points[e];
      reference(cps, X);
      current(cps, u, dofs, x);
      const int n = 3 * static_cast<int>(cps.size());
      r.setZero(n);
      if (with_tangent) element_tangent.reset(static_cast<int>(cps.size()));
      const double ju = 0.5 * (el.u1 - el.u0), jv = 0.5 * (el.v1 - el.v0);
      const std::size_t iu = e % n_u, iv = e / n_u;
      for (std::size_t j = 0; j < gv.points.size(); ++j) {
        for (std::size_t i = 0; i < gu.points.size(); ++i) {
          surface.tensor_basis(el.span_u, el.span_v, along_u[iu * gu.points.size() + i],
                               along_v[iv * gv.points.size() + j], basis);
          const double w = gu.weights[i] * gv.weights[j] * ju * jv;
          shell::add_shell_point(section, basis.R, X, x, w, &energy, &r,
                                 with_tangent ? &element_tangent : nullptr);
        }
      }
      if (with_tangent) {
        k.setZero(n, n);
        element_tangent.add_to(k);
      }
      sink.add(e, r, with_tangent ? &k : nullptr);
    }); });
    sum.set(energy);
  }
  error.rethrow();
  return sum.total();
}

Eigen::Vector3d ShellBody::displacement(double pu, double pv, const Eigen::VectorXd& u,
                                        const solve::DofMap& dofs) const {
  const auto basis = surface.basis(pu, pv);
  Eigen::Vector3d d = Eigen::Vector3d::Zero();
  for (std::size_t a = 0; a < basis.indices.size(); ++a)
    for (int c = 0; c < 3; ++c) d[c] += basis.R(0, a) * u[dofs.dof(block, basis.indices[a], c)];
  return d;
}

}  // namespace fibrane::model
