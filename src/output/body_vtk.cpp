#include "output/body_vtk.hpp"

#include <stdexcept>

#include "io/bezier_vtu.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "common/parallel_errors.hpp"
#include "spline/basis.hpp"
#include "spline/quadrature.hpp"

namespace fibrane::output {

using model::BeamBody;
using model::Model;
using model::ShellBody;

namespace {

void push3(std::vector<double>& v, const Eigen::Vector3d& x) { v.insert(v.end(), {x[0], x[1], x[2]}); }

// Point p's three components of a field.
void set3(std::vector<double>& v, std::size_t p, const Eigen::Vector3d& x) {
  v[3 * p] = x[0];
  v[3 * p + 1] = x[1];
  v[3 * p + 2] = x[2];
}

}  // namespace

io::VtuMesh shell_vtu(const Model& m, const ShellBody& s, int samples) {
  io::VtuMesh mesh;
  // N_local, M_local: physical section forces per current length in the frame e1 = g1/|g1|, e2 = n x e1
  // (11, 22, 12); N_ab, M_ab: the contravariant components N^ab, M^ab of Eq. (29) (11, 22, 12).
  io::VtuMesh::Field disp{"displacement", 3, {}}, nf{"N_local", 3, {}}, mf{"M_local", 3, {}},
      nc{"N_contravariant", 3, {}}, mc{"M_contravariant", 3, {}};
  const auto& u = m.displacement();
  const int n = samples + 1;
  const auto elements = static_cast<std::int64_t>(s.elements.size());
  const auto points = static_cast<std::size_t>(elements) * static_cast<std::size_t>(n * n);
  mesh.points.resize(points);
  for (auto* f : {&disp, &nf, &mf, &nc, &mc}) f->values.resize(3 * points);
  // Each element's (samples + 1)^2 points in their own rows, the elements side by side on the run's
  // threads. The 1-D basis functions are evaluated once per sample row and column, and the points' bases
  // reuse one storage per thread: a malloc per point would serialise the threads on the allocator's lock
  // (one arena: run/process_environment.cpp).
  FirstError error;
#pragma omp parallel
  {
    std::vector<Eigen::MatrixXd> nu(static_cast<std::size_t>(n)), nv(static_cast<std::size_t>(n));
    spline::SurfaceBasis b;
#pragma omp for schedule(dynamic, 16)
    for (std::int64_t e = 0; e < elements; ++e) error.run([&] {
      const auto& el = s.elements[static_cast<std::size_t>(e)];
      const auto& cps = s.element_control_points[static_cast<std::size_t>(e)];
      const Eigen::Matrix3Xd X = s.reference(cps), x = s.current(cps, u, m.dofs);
      for (int k = 0; k <= samples; ++k) {
        nu[static_cast<std::size_t>(k)] =
            spline::bspline_basis_derivs(s.surface.knots(0), el.span_u, el.u0 + (el.u1 - el.u0) * k / samples, 2);
        nv[static_cast<std::size_t>(k)] =
            spline::bspline_basis_derivs(s.surface.knots(1), el.span_v, el.v0 + (el.v1 - el.v0) * k / samples, 2);
      }
      for (int j = 0; j <= samples; ++j)
        for (int i = 0; i <= samples; ++i) {
          const std::size_t p = static_cast<std::size_t>(e) * static_cast<std::size_t>(n * n) +
                                static_cast<std::size_t>(j * n + i);
          s.surface.tensor_basis(el.span_u, el.span_v, nu[static_cast<std::size_t>(i)], nv[static_cast<std::size_t>(j)], b);
          const Eigen::Vector3d xr = X * b.R.row(0).transpose(), xc = x * b.R.row(0).transpose();
          mesh.points[p] = xc;
          const auto f = shell::section_forces(s.section, b.R, X, x);
          set3(disp.values, p, xc - xr);
          set3(nf.values, p, {f.N_local(0, 0), f.N_local(1, 1), f.N_local(0, 1)});
          set3(mf.values, p, {f.M_local(0, 0), f.M_local(1, 1), f.M_local(0, 1)});
          set3(nc.values, p, {f.N(0, 0), f.N(1, 1), f.N(0, 1)});
          set3(mc.values, p, {f.M(0, 0), f.M(1, 1), f.M(0, 1)});
        }
    });
  }
  error.rethrow();
  for (std::int64_t e = 0; e < elements; ++e) {
    const int base = static_cast<int>(e) * n * n;
    for (int j = 0; j < samples; ++j)
      for (int i = 0; i < samples; ++i) {
        const int a = base + j * n + i;
        mesh.add_cell(io::vtk_cell::quad, {a, a + 1, a + n + 1, a + n});
      }
  }
  mesh.point_data = {std::move(disp), std::move(nf), std::move(mf), std::move(nc), std::move(mc)};
  return mesh;
}

io::VtuMesh beam_vtu(const Model& m, const BeamBody& b, int samples) {
  io::VtuMesh mesh;
  io::VtuMesh::Field disp{"displacement", 3, {}}, twist{"twist", 1, {}}, t{"tangent", 3, {}},
      a2{"director2", 3, {}}, a3{"director3", 3, {}}, nf{"N", 1, {}}, mf{"M", 3, {}};
  const auto& u = m.displacement();
  const int probes = b.output_probes(samples);
  if (probes < 0) throw std::logic_error("beam_vtu: the beam has no output probes for " + std::to_string(samples) + " samples");
  for (std::size_t e = 0; e < b.elements.size(); ++e) {
    const auto& el = b.elements[e];
    const beam::BeamDofs q = b.current(el.control_points, u, m.dofs);
    const int base = static_cast<int>(mesh.points.size());
    for (int i = 0; i <= samples; ++i) {
      // Sample slightly inside the element so the basis belongs to this element's span (the probes
      // sit at the same points, with their own frames: section quantities are exact there).
      const double s = std::clamp(static_cast<double>(i) / samples, 1e-12, 1.0 - 1e-12);
      const double xi = el.xi0 + (el.xi1 - el.xi0) * s;
      const auto basis = b.curve.basis(xi, 0);
      Eigen::Vector3d r = Eigen::Vector3d::Zero();
      for (int a = 0; a < basis.R.cols(); ++a) r += basis.R(0, a) * q.col(a).head<3>();
      const auto out = b.probe_output(probes + static_cast<int>(e) * (samples + 1) + i, u, m.dofs);
      mesh.points.push_back(r);
      push3(disp.values, r - b.curve.point(xi));
      twist.values.push_back(q.row(3).dot(basis.R.row(0)));
      push3(t.values, out.t);
      push3(a2.values, out.a2);
      push3(a3.values, out.a3);
      nf.values.push_back(out.N);
      push3(mf.values, {out.M[0], out.M[1], out.M[2]});
    }
    mesh.connectivity.reserve(mesh.connectivity.size() + samples + 1);
    for (int i = 0; i <= samples; ++i) mesh.connectivity.push_back(base + i);
    mesh.offsets.push_back(static_cast<int>(mesh.connectivity.size()));
    mesh.types.push_back(io::vtk_cell::poly_line);
  }
  mesh.point_data = {std::move(disp), std::move(twist), std::move(t), std::move(a2), std::move(a3),
                     std::move(nf), std::move(mf)};
  return mesh;
}

io::VtuMesh point_cloud_vtu(const model::PointCloud& cloud) {
  io::VtuMesh mesh;
  for (const auto& x : cloud.positions) {
    mesh.add_cell(io::vtk_cell::vertex, {static_cast<int>(mesh.points.size())});
    mesh.points.push_back(x);
  }
  for (const auto& f : cloud.fields) mesh.point_data.push_back({f.name, f.components, f.values});
  return mesh;
}

io::VtuMesh shell_bezier_vtu(const Model& m, const ShellBody& s) {
  const auto& u = m.displacement();
  std::vector<Eigen::Vector3d> current = s.surface.control_points();
  io::VtuMesh::Field disp{"displacement", 3, {}};
  for (int cp = 0; cp < s.num_control_points(); ++cp) {
    const Eigen::Vector3d d(u[m.dofs.dof(s.block, cp, 0)], u[m.dofs.dof(s.block, cp, 1)], u[m.dofs.dof(s.block, cp, 2)]);
    current[cp] += d;
    push3(disp.values, d);
  }
  return io::bezier_surface_vtu(s.surface, current, {disp});
}

io::VtuMesh beam_bezier_vtu(const Model& m, const BeamBody& b) {
  const auto& u = m.displacement();
  std::vector<Eigen::Vector3d> current = b.curve.control_points();
  io::VtuMesh::Field disp{"displacement", 3, {}}, twist{"twist", 1, {}};
  for (int cp = 0; cp < b.num_control_points(); ++cp) {
    const Eigen::Vector3d d(u[m.dofs.dof(b.block, cp, 0)], u[m.dofs.dof(b.block, cp, 1)], u[m.dofs.dof(b.block, cp, 2)]);
    current[cp] += d;
    push3(disp.values, d);
    twist.values.push_back(u[m.dofs.dof(b.block, cp, 3)]);
  }
  return io::bezier_curve_vtu(b.curve, current, {disp, twist});
}

double series_timestep(const solve::StepReport& r, bool by_path_length) {
  return by_path_length ? r.path_length : r.t;
}

std::vector<io::VtuMesh::Field> step_field_data(const solve::StepReport& r, bool by_path_length) {
  std::vector<io::VtuMesh::Field> fields{{"step", 1, {static_cast<double>(r.step)}}, {"t", 1, {r.t}}};
  if (by_path_length) fields.push_back({"path_length", 1, {r.path_length}});
  return fields;
}

}  // namespace fibrane::output
