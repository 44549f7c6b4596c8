#include "model/results.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fmt/format.h>

#include "io/atomic_file.hpp"
#include "io/json.hpp"
#include "spline/quadrature.hpp"

namespace fibrane::model {

namespace {

void push3(std::vector<double>& v, const Eigen::Vector3d& x) { v.insert(v.end(), {x[0], x[1], x[2]}); }

}  // namespace

io::VtuMesh shell_vtu(const Model& m, const ShellBody& s, int samples) {
  io::VtuMesh mesh;
  // N_local, M_local: physical section forces per current length in the frame e1 = g1/|g1|, e2 = n x e1
  // (11, 22, 12); N_ab, M_ab: the contravariant components N^ab, M^ab of Eq. (29) (11, 22, 12).
  io::VtuMesh::Field disp{"displacement", 3, {}}, nf{"N_local", 3, {}}, mf{"M_local", 3, {}},
      nc{"N_contravariant", 3, {}}, mc{"M_contravariant", 3, {}};
  const auto& u = m.displacement();
  for (std::size_t e = 0; e < s.elements.size(); ++e) {
    const auto& el = s.elements[e];
    const auto& cps = s.element_control_points[e];
    const Eigen::Matrix3Xd X = s.reference(cps), x = s.current(cps, u, m.dofs);
    const int base = static_cast<int>(mesh.points.size());
    for (int j = 0; j <= samples; ++j)
      for (int i = 0; i <= samples; ++i) {
        const double pu = el.u0 + (el.u1 - el.u0) * i / samples, pv = el.v0 + (el.v1 - el.v0) * j / samples;
        const auto b = s.surface.basis_in(el.span_u, el.span_v, pu, pv);
        const Eigen::Vector3d xr = X * b.R.row(0).transpose(), xc = x * b.R.row(0).transpose();
        mesh.points.push_back(xc);
        push3(disp.values, xc - xr);
        const auto f = shell::section_forces(s.section, b.R, X, x);
        push3(nf.values, {f.N_local(0, 0), f.N_local(1, 1), f.N_local(0, 1)});
        push3(mf.values, {f.M_local(0, 0), f.M_local(1, 1), f.M_local(0, 1)});
        push3(nc.values, {f.N(0, 0), f.N(1, 1), f.N(0, 1)});
        push3(mc.values, {f.M(0, 0), f.M(1, 1), f.M(0, 1)});
      }
    const int n = samples + 1;
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
  const auto gauss = spline::gauss_legendre(b.gauss());
  for (std::size_t e = 0; e < b.elements.size(); ++e) {
    const auto& el = b.elements[e];
    const beam::BeamDofs q = b.current(el.control_points, u, m.dofs);
    // Section quantities are exact at the quadrature points, where the frame states live; each sample
    // shows the value of the nearest quadrature point. Positions, displacement and twist are exact.
    std::vector<beam::BeamPointOutput> at_gauss;
    std::vector<double> gauss_xi;
    for (std::size_t g = 0; g < gauss.points.size(); ++g) {
      const double xi = el.xi0 + 0.5 * (gauss.points[g] + 1.0) * (el.xi1 - el.xi0);
      gauss_xi.push_back(xi);
      at_gauss.push_back(beam::evaluate_point(b.section, b.curve.basis(xi, 2).R.topRows(3), q, b.states[e][g]));
    }
    const int base = static_cast<int>(mesh.points.size());
    for (int i = 0; i <= samples; ++i) {
      // Sample slightly inside the element so the basis belongs to this element's span.
      const double s = std::clamp(static_cast<double>(i) / samples, 1e-12, 1.0 - 1e-12);
      const double xi = el.xi0 + (el.xi1 - el.xi0) * s;
      const auto basis = b.curve.basis(xi, 0);
      Eigen::Vector3d r = Eigen::Vector3d::Zero();
      for (int a = 0; a < basis.R.cols(); ++a) r += basis.R(0, a) * q.col(a).head<3>();
      std::size_t near = 0;
      for (std::size_t g = 1; g < gauss_xi.size(); ++g)
        if (std::abs(gauss_xi[g] - xi) < std::abs(gauss_xi[near] - xi)) near = g;
      const auto& out = at_gauss[near];
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

io::VtuMesh coupling_vtu(const Coupling& c) {
  io::VtuMesh mesh;
  io::VtuMesh::Field xi{"xi", 1, {}}, s{"s", 1, {}}, d{"distance", 1, {}}, cos{"cos_alpha", 1, {}},
      f{"force", 3, {}}, fm{"force_magnitude", 1, {}}, soft{"soft_minimum", 1, {}};
  for (const auto& p : c.points()) {
    if (!p.active) continue;
    mesh.add_cell(io::vtk_cell::vertex, {static_cast<int>(mesh.points.size())});
    mesh.points.push_back(p.position);
    xi.values.push_back(p.xi);
    s.values.push_back(p.s);
    d.values.push_back(p.distance);
    cos.values.push_back(p.cos_alpha);
    push3(f.values, p.force);
    fm.values.push_back(p.force.norm());
    soft.values.push_back(p.soft ? 1 : 0);
  }
  mesh.point_data = {std::move(xi), std::move(s), std::move(d), std::move(cos), std::move(f), std::move(fm),
                     std::move(soft)};
  return mesh;
}

std::vector<std::string> history_columns(const Model& m) {
  std::vector<std::string> columns{"step", "t", "load_factor", "iterations", "residual", "strain_energy"};
  for (const auto& c : m.couplings)
    for (const char* suffix : {"_energy", "_force_x", "_force_y", "_force_z"}) columns.push_back(c.name() + suffix);
  for (const auto& mon : m.monitors) columns.push_back(mon.name);
  return columns;
}

namespace {

// A run into a directory that holds an earlier run's output removes that run's per-step files and summary
// first: otherwise a longer earlier run leaves steps beyond this run's end beside it (ParaView would not
// show them, but a script reading the folder would), and an interrupted run would keep a summary saying
// "completed". Only names this case writes (<name>_<6 digits>.vtu / .csv) are touched.
void remove_earlier_run(const std::filesystem::path& dir, const Case& c) {
  namespace fs = std::filesystem;
  std::vector<std::string> names;
  for (const auto& s : c.model->shells) names.push_back(s.name);
  for (const auto& b : c.model->beams) names.push_back(b.name);
  for (const auto& k : c.model->couplings) names.push_back(k.name());
  auto is_step_file = [&](const fs::path& f, const std::string& ext) {
    const std::string stem = f.stem().string();
    if (f.extension() != ext || stem.size() < 8 || stem[stem.size() - 7] != '_') return false;
    const std::string digits = stem.substr(stem.size() - 6);
    if (digits.find_first_not_of("0123456789") != std::string::npos) return false;
    return std::find(names.begin(), names.end(), stem.substr(0, stem.size() - 7)) != names.end();
  };
  std::error_code ec;
  fs::remove(dir / "summary.json", ec);
  for (const auto& [sub, ext] : {std::pair{"vtk", ".vtu"}, std::pair{"interaction", ".csv"}}) {
    if (!fs::is_directory(dir / sub)) continue;
    for (const auto& entry : fs::directory_iterator(dir / sub))
      if (entry.is_regular_file() && is_step_file(entry.path(), ext)) fs::remove(entry.path(), ec);
  }
}

}  // namespace

RunOutput::RunOutput(const Case& c, std::string directory) : case_(c), dir_(std::move(directory)) {
  namespace fs = std::filesystem;
  remove_earlier_run(dir_, c);
  fs::create_directories(fs::path(dir_) / "vtk");
  if (!c.model->couplings.empty()) fs::create_directories(fs::path(dir_) / "interaction");
  columns_ = history_columns(*c.model);
  history_ = std::make_unique<io::CsvWriter>((fs::path(dir_) / "history.csv").string(), columns_);
  if (c.output.vtk) {
    for (const auto& s : c.model->shells) series_.emplace_back((fs::path(dir_) / (s.name + ".pvd")).string());
    for (const auto& b : c.model->beams) series_.emplace_back((fs::path(dir_) / (b.name + ".pvd")).string());
    for (const auto& k : c.model->couplings) series_.emplace_back((fs::path(dir_) / (k.name() + ".pvd")).string());
  }
}

void RunOutput::write_history(const Model& m, const solve::StepReport& r) {
  std::vector<double> row{static_cast<double>(r.step), r.t, m.functions(0, r.t), static_cast<double>(r.iterations),
                          r.residual_norm, m.strain_energy()};
  for (const auto& c : m.couplings) {
    const Eigen::Vector3d f = c.total_force();
    row.insert(row.end(), {c.energy(), f.x(), f.y(), f.z()});
  }
  for (const auto& mon : m.monitors) row.push_back(m.monitor_value(mon));
  history_->row(row);
  last_row_ = row;
  for (const auto& c : m.couplings) write_coupling_csv(c, r.step);
}

void RunOutput::write_vtk(const Model& m, const solve::StepReport& r) {
  if (!case_.output.vtk) return;
  std::size_t k = 0;
  auto write = [&](const std::string& name, const io::VtuMesh& mesh) {
    const std::string rel = fmt::format("vtk/{}_{:06d}.vtu", name, r.step);
    io::write_vtu((std::filesystem::path(dir_) / rel).string(), mesh);
    series_[k++].add(r.t, rel);
  };
  for (const auto& s : m.shells) write(s.name, shell_vtu(m, s, case_.output.samples));
  for (const auto& b : m.beams) write(b.name, beam_vtu(m, b, case_.output.samples));
  for (const auto& c : m.couplings) write(c.name(), coupling_vtu(c));
  ++steps_written_;
}

double RunOutput::last_value(const std::string& column) const {
  for (std::size_t i = 0; i < columns_.size() && i < last_row_.size(); ++i)
    if (columns_[i] == column) return last_row_[i];
  throw std::invalid_argument("no history column named '" + column + "'");
}

void RunOutput::write_coupling_csv(const Coupling& c, int step) const {
  std::string text = "xi,s,active,distance,cos_alpha,force_x,force_y,force_z,force_magnitude,energy_density,soft_minimum\n";
  for (const auto& p : c.points())
    text += fmt::format("{},{},{},{},{},{},{},{},{},{},{}\n", io::format_double(p.xi), io::format_double(p.s),
                        p.active ? 1 : 0, io::format_double(p.distance), io::format_double(p.cos_alpha),
                        io::format_double(p.force.x()), io::format_double(p.force.y()),
                        io::format_double(p.force.z()), io::format_double(p.force.norm()),
                        io::format_double(p.energy_density), p.soft ? 1 : 0);
  io::write_file_atomic(
      (std::filesystem::path(dir_) / "interaction" / fmt::format("{}_{:06d}.csv", c.name(), step)).string(), text);
}

void RunOutput::write_summary(const Model& m, const solve::ContinuationResult& result, double wall_seconds,
                              const std::string& solver_name) {
  io::JsonValue j = io::JsonValue::object();
  j.set("case", case_.path).set("title", m.title).set("fibrane_version", FIBRANE_VERSION);
  j.set("dofs", m.dofs.size()).set("free_dofs", m.constraints.num_free()).set("elements", m.num_elements());
  j.set("completed", result.completed()).set("message", result.message);
  j.set("t_reached", result.t_reached).set("steps", result.steps).set("newton_iterations", result.total_iterations);
  j.set("wall_seconds", wall_seconds).set("linear_solver", solver_name);
  io::JsonValue monitors = io::JsonValue::object();
  for (const auto& mon : m.monitors) monitors.set(mon.name, m.monitor_value(mon));
  j.set("final_monitors", std::move(monitors));
  io::JsonValue soft = io::JsonValue::object();
  for (const auto& c : m.couplings)
    if (c.soft_points() > 0) soft.set(c.name(), c.soft_points());
  j.set("soft_minimum_points", std::move(soft));
  io::write_file_atomic((std::filesystem::path(dir_) / "summary.json").string(), j.dump(2) + "\n");
}

}  // namespace fibrane::model
