// Loads acting on a shell, integrated into consistent nodal forces by the shell itself (its basis and
// quadrature): surface forces and pressure per unit reference area, line forces along an edge.
#include <map>

#include "model/shell_body.hpp"
#include "spline/quadrature.hpp"

namespace fibrane::model {

Eigen::VectorXd ShellBody::surface_load(const Eigen::Vector3d& force) const { return area_load(force, false); }

Eigen::VectorXd ShellBody::pressure_load(double pressure) const {
  return area_load(Eigen::Vector3d(pressure, 0, 0), true);
}

Eigen::VectorXd ShellBody::area_load(const Eigen::Vector3d& f, bool pressure) const {
  Eigen::VectorXd nodal = Eigen::VectorXd::Zero(3 * num_control_points());
  const auto gu = spline::gauss_legendre(gauss(0)), gv = spline::gauss_legendre(gauss(1));
  for (const auto& el : elements) {
    const double ju = 0.5 * (el.u1 - el.u0), jv = 0.5 * (el.v1 - el.v0);
    for (std::size_t j = 0; j < gv.points.size(); ++j)
      for (std::size_t i = 0; i < gu.points.size(); ++i) {
        const double pu = el.u0 + (gu.points[i] + 1) * ju, pv = el.v0 + (gv.points[j] + 1) * jv;
        const auto b = surface.basis_in(el.span_u, el.span_v, pu, pv);
        Eigen::Vector3d g1 = Eigen::Vector3d::Zero(), g2 = Eigen::Vector3d::Zero();
        for (std::size_t a = 0; a < b.indices.size(); ++a) {
          g1 += b.R(1, a) * surface.control_points()[b.indices[a]];
          g2 += b.R(2, a) * surface.control_points()[b.indices[a]];
        }
        const Eigen::Vector3d area = g1.cross(g2);  // J_S times the reference normal
        const Eigen::Vector3d force = pressure ? Eigen::Vector3d(f.x() * area) : Eigen::Vector3d(f * area.norm());
        const double w = gu.weights[i] * gv.weights[j] * ju * jv;
        for (std::size_t a = 0; a < b.indices.size(); ++a) nodal.segment<3>(3 * b.indices[a]) += w * b.R(0, a) * force;
      }
  }
  return nodal;
}

Eigen::VectorXd ShellBody::edge_load(const std::string& edge, const Eigen::Vector3d& f) const {
  const bool along_v = edge[0] == 'u';  // u0/u1: u fixed, v runs
  const auto& kv = surface.knots(along_v ? 1 : 0);
  const double fixed = edge[1] == '0' ? surface.knots(along_v ? 0 : 1).front() : surface.knots(along_v ? 0 : 1).back();
  const auto g = spline::gauss_legendre(surface.degree(along_v ? 1 : 0) + 1);
  Eigen::VectorXd nodal = Eigen::VectorXd::Zero(3 * num_control_points());
  const auto& ks = kv.knots();
  for (int span : kv.element_spans()) {
    const double a = ks[span], b = ks[span + 1], j = 0.5 * (b - a);
    for (std::size_t q = 0; q < g.points.size(); ++q) {
      const double t = a + (g.points[q] + 1) * j;
      const auto basis = along_v ? surface.basis(fixed, t) : surface.basis(t, fixed);
      Eigen::Vector3d tangent = Eigen::Vector3d::Zero();
      for (std::size_t k = 0; k < basis.indices.size(); ++k)
        tangent += basis.R(along_v ? 2 : 1, k) * surface.control_points()[basis.indices[k]];
      for (std::size_t k = 0; k < basis.indices.size(); ++k)
        nodal.segment<3>(3 * basis.indices[k]) += g.weights[q] * j * tangent.norm() * basis.R(0, k) * f;
    }
  }
  return nodal;
}

std::vector<int> ShellBody::edge_elements(const std::string& edge) const {
  const double u_start = surface.knots(0).front(), u_end = surface.knots(0).back();
  const double v_start = surface.knots(1).front(), v_end = surface.knots(1).back();
  std::vector<int> out;
  for (std::size_t e = 0; e < elements.size(); ++e) {
    const auto& el = elements[e];
    const bool on = (edge == "u0" && el.u0 == u_start) || (edge == "u1" && el.u1 == u_end) ||
                    (edge == "v0" && el.v0 == v_start) || (edge == "v1" && el.v1 == v_end);
    if (on) out.push_back(static_cast<int>(e));
  }
  return out;
}

}  // namespace fibrane::model
