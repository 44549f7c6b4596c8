#include "model/case_conditions.hpp"

#include <cmath>
#include <map>

#include "model/case_sites.hpp"
#include "spline/quadrature.hpp"

namespace fibrane::model {

int read_function_ref(const Model& m, const io::YamlNode& entry) {
  auto f = entry.optional("function");
  if (!f) return 0;
  const int id = m.functions.find(f->as_string());
  if (id < 0) {
    std::string known;
    for (const auto& n : m.functions.names()) known += (known.empty() ? "" : ", ") + n;
    f->fail("the name of a load function (" + known + ")");
  }
  return id;
}

namespace {

std::vector<int> read_components(const BodyRef& b, const io::YamlNode& node) {
  std::vector<int> out;
  if (node.is_scalar()) {
    out.push_back(component(b, node));
    return out;
  }
  if (!node.is_sequence() || node.size() == 0) node.fail("a list of components such as [x, z]");
  for (std::size_t i = 0; i < node.size(); ++i) out.push_back(component(b, node.at(i)));
  return out;
}

// u(site) component c = value * f(t): a plain fix for a control point, a multi-point constraint otherwise
// (the control point with the largest weight becomes the slave).
void constrain_site(Model& m, const BodyRef& b, const Site& site, int c, double value, int function) {
  if (site.size() == 1 && site[0].second == 1.0) {
    m.constraints.fix(m.dofs.dof(b.block, site[0].first, c), value, function);
    return;
  }
  std::size_t s = 0;
  for (std::size_t k = 1; k < site.size(); ++k)
    if (std::abs(site[k].second) > std::abs(site[s].second)) s = k;
  solve::LinearConstraint lc;
  lc.slave = m.dofs.dof(b.block, site[s].first, c);
  const double ws = site[s].second;
  for (std::size_t k = 0; k < site.size(); ++k)
    if (k != s) lc.masters.emplace_back(m.dofs.dof(b.block, site[k].first, c), -site[k].second / ws);
  lc.value = value / ws;
  lc.curve = function;
  m.constraints.add(lc);
}

// Row 1 follows row 0 in the given components (clamped edge / end, and the slope part of symmetry).
void tie_rows(Model& m, const BodyRef& b, const io::YamlNode& at, const std::vector<int>& comps) {
  const auto row0 = boundary_row(m, b, at, 0), row1 = boundary_row(m, b, at, 1);
  for (std::size_t k = 0; k < row0.size(); ++k)
    for (int c : comps)
      m.constraints.add({m.dofs.dof(b.block, row1[k], c), {{m.dofs.dof(b.block, row0[k], c), 1.0}}, 0.0, -1});
}

int control_point(const Model& m, const BodyRef& b, const io::YamlNode& node) {
  if (b.is_beam) {
    const int i = node.as_int();
    if (i < 0 || i >= m.beams[b.index].num_control_points()) node.fail("a control point index of the beam");
    return i;
  }
  const auto ij = node.as_doubles();
  const auto& s = m.shells[b.index].surface;
  if (ij.size() != 2 || ij[0] < 0 || ij[1] < 0 || ij[0] >= s.num_control_points(0) ||
      ij[1] >= s.num_control_points(1) || ij[0] != std::floor(ij[0]) || ij[1] != std::floor(ij[1]))
    node.fail("[i, j], control point indices within " + std::to_string(s.num_control_points(0)) + " x " +
              std::to_string(s.num_control_points(1)));
  return s.index(static_cast<int>(ij[0]), static_cast<int>(ij[1]));
}

int read_dof(const Model& m, const io::YamlNode& node) {
  const BodyRef b = find_body(m, node["body"]);
  const int cp = control_point(m, b, node["control_point"]);
  const int c = component(b, node["component"]);
  return m.dofs.dof(b.block, cp, c);
}

void read_link(Model& m, const io::YamlNode& link, const io::YamlNode& entry) {
  solve::LinearConstraint lc;
  const auto dof = link["dof"];
  lc.slave = read_dof(m, dof);
  dof.reject_unknown_keys();
  const auto eq = link["equals"];
  if (!eq.is_sequence()) eq.fail("a list of {body, control_point, component, factor}");
  for (std::size_t k = 0; k < eq.size(); ++k) {
    const auto t = eq.at(k);
    lc.masters.emplace_back(read_dof(m, t), t.get("factor", 1.0));
    t.reject_unknown_keys();
  }
  lc.value = link.get("value", 0.0);
  lc.curve = read_function_ref(m, link);
  link.reject_unknown_keys();
  entry.reject_unknown_keys();
  m.constraints.add(lc);
}

}  // namespace

void read_constraint(Model& m, const io::YamlNode& entry) {
  if (auto link = entry.optional("link")) return read_link(m, *link, entry);
  const BodyRef b = find_body(m, entry["body"]);
  const auto at = entry["at"];
  const auto where = sites(m, b, at);
  const int function = read_function_ref(m, entry);
  bool any = false;
  if (auto fix = entry.optional("fix")) {
    for (int c : read_components(b, *fix))
      for (const auto& s : where) constrain_site(m, b, s, c, 0.0, -1);
    any = true;
  }
  if (auto pre = entry.optional("prescribe")) {
    if (!pre->is_map()) pre->fail("a map of component: value, e.g. {z: -0.1}");
    for (const auto& key : pre->keys()) {
      const auto v = (*pre)[key];
      const int c = b.is_beam ? (key == "twist" ? 3 : -1) : -1;
      const int comp = key == "x" ? 0 : key == "y" ? 1 : key == "z" ? 2 : c;
      if (comp < 0) v.fail_message("unknown component '" + key + "' (expected x, y, z" +
                                   std::string(b.is_beam ? " or twist)" : ")"));
      const double value = v.as_double();
      for (const auto& s : where) constrain_site(m, b, s, comp, value, function);
    }
    any = true;
  }
  if (auto clamp = entry.optional("clamp")) {
    if (!at.has("edge") && !at.has("end")) clamp->fail_message("clamp needs 'at: {edge: ...}' or 'at: {end: ...}'");
    if (clamp->is_scalar() && !clamp->as_bool()) clamp->fail("true or a list of components");
    tie_rows(m, b, at, clamp->is_scalar() ? std::vector<int>{0, 1, 2} : read_components(b, *clamp));
    any = true;
  }
  if (auto sym = entry.optional("symmetry")) {
    if (!at.has("edge") && !at.has("end")) sym->fail_message("symmetry needs 'at: {edge: ...}' or 'at: {end: ...}'");
    const int n = component(b, *sym);
    if (n > 2) sym->fail("the normal of the symmetry plane: x, y or z");
    // Mirror symmetry: the boundary row stays in the plane, and the surface (or beam axis) crosses the
    // plane at a right angle. For a C1 spline with an open knot vector the cross-boundary derivative is
    // proportional to (row 1 - row 0), so the components tangent to the plane are tied between the rows.
    std::vector<int> in_plane;
    for (int c = 0; c < 3; ++c)
      if (c != n) in_plane.push_back(c);
    const std::vector<int> row = boundary_row(m, b, at, 0);
    for (int cp : row) m.constraints.fix(m.dofs.dof(b.block, cp, n));
    tie_rows(m, b, at, in_plane);
    if (!b.is_beam) {  // the plane x[n] = the boundary row's coordinate, for the soft minimum's images
      ShellBody& shell = m.shells[b.index];
      shell.mirrors.push_back({n, shell.surface.control_points()[row.front()][n]});
    }
    if (b.is_beam) {
      // Circular sections make a uniform twist a zero-energy mode: the plane fixes the gauge phi = 0,
      // and phi is even about the plane (a rotation about the plane normal is a mirror-invariant
      // pseudovector component), so the next twist value follows.
      for (int cp : boundary_row(m, b, at, 0)) m.constraints.fix(m.dofs.dof(b.block, cp, 3));
      tie_rows(m, b, at, {3});
    }
    any = true;
  }
  if (!any) entry.fail_message("a constraint needs at least one of 'fix', 'prescribe', 'clamp', 'symmetry'");
  entry.reject_unknown_keys();
}

namespace {

void add_load(Model& m, NodalLoad&& load) {
  if (load.dofs.empty()) return;
  m.nodal_loads.push_back(std::move(load));
}

// Consistent nodal forces of a constant force per unit reference area (or pressure along the
// reference normal when `pressure` is true) over a whole shell.
NodalLoad surface_load(const Model& m, const ShellBody& s, const Eigen::Vector3d& f, bool pressure) {
  NodalLoad load;
  Eigen::VectorXd nodal = Eigen::VectorXd::Zero(3 * s.num_control_points());
  const auto gu = spline::gauss_legendre(s.gauss(0)), gv = spline::gauss_legendre(s.gauss(1));
  for (const auto& el : s.elements) {
    const double ju = 0.5 * (el.u1 - el.u0), jv = 0.5 * (el.v1 - el.v0);
    for (std::size_t j = 0; j < gv.points.size(); ++j)
      for (std::size_t i = 0; i < gu.points.size(); ++i) {
        const double pu = el.u0 + (gu.points[i] + 1) * ju, pv = el.v0 + (gv.points[j] + 1) * jv;
        const auto b = s.surface.basis_in(el.span_u, el.span_v, pu, pv);
        Eigen::Vector3d g1 = Eigen::Vector3d::Zero(), g2 = Eigen::Vector3d::Zero();
        for (std::size_t a = 0; a < b.indices.size(); ++a) {
          g1 += b.R(1, a) * s.surface.control_points()[b.indices[a]];
          g2 += b.R(2, a) * s.surface.control_points()[b.indices[a]];
        }
        const Eigen::Vector3d area = g1.cross(g2);  // J_S times the reference normal
        const Eigen::Vector3d force = pressure ? Eigen::Vector3d(f.x() * area) : Eigen::Vector3d(f * area.norm());
        const double w = gu.weights[i] * gv.weights[j] * ju * jv;
        for (std::size_t a = 0; a < b.indices.size(); ++a)
          nodal.segment<3>(3 * b.indices[a]) += w * b.R(0, a) * force;
      }
  }
  for (int cp = 0; cp < s.num_control_points(); ++cp)
    for (int c = 0; c < 3; ++c)
      if (nodal[3 * cp + c] != 0.0) {
        load.dofs.push_back(m.dofs.dof(s.block, cp, c));
        load.values.conservativeResize(load.dofs.size());
        load.values[load.dofs.size() - 1] = nodal[3 * cp + c];
      }
  return load;
}

// Consistent nodal forces of a force per unit reference length along a shell edge.
NodalLoad edge_load(const Model& m, const ShellBody& s, const std::string& edge, const Eigen::Vector3d& f) {
  const bool along_v = edge[0] == 'u';  // u0/u1: u fixed, v runs
  const auto& kv = s.surface.knots(along_v ? 1 : 0);
  const double fixed = edge[1] == '0' ? s.surface.knots(along_v ? 0 : 1).front()
                                      : s.surface.knots(along_v ? 0 : 1).back();
  const auto g = spline::gauss_legendre(s.surface.degree(along_v ? 1 : 0) + 1);
  std::map<int, Eigen::Vector3d> nodal;
  const auto& ks = kv.knots();
  for (int span : kv.element_spans()) {
    const double a = ks[span], b = ks[span + 1], j = 0.5 * (b - a);
    for (std::size_t q = 0; q < g.points.size(); ++q) {
      const double t = a + (g.points[q] + 1) * j;
      const auto basis = along_v ? s.surface.basis(fixed, t) : s.surface.basis(t, fixed);
      Eigen::Vector3d tangent = Eigen::Vector3d::Zero();
      for (std::size_t k = 0; k < basis.indices.size(); ++k)
        tangent += basis.R(along_v ? 2 : 1, k) * s.surface.control_points()[basis.indices[k]];
      for (std::size_t k = 0; k < basis.indices.size(); ++k) {
        const double w = g.weights[q] * j * tangent.norm() * basis.R(0, k);
        if (w == 0.0) continue;
        auto it = nodal.try_emplace(basis.indices[k], Eigen::Vector3d::Zero()).first;
        it->second += w * f;
      }
    }
  }
  NodalLoad load;
  for (const auto& [cp, v] : nodal)
    for (int c = 0; c < 3; ++c) {
      load.dofs.push_back(m.dofs.dof(s.block, cp, c));
      load.values.conservativeResize(load.dofs.size());
      load.values[load.dofs.size() - 1] = v[c];
    }
  return load;
}

// Consistent nodal forces of a force per unit reference length along a whole beam.
NodalLoad beam_line_load(const Model& m, const BeamBody& b, const Eigen::Vector3d& f) {
  Eigen::VectorXd nodal = Eigen::VectorXd::Zero(3 * b.num_control_points());
  const auto g = spline::gauss_legendre(b.gauss());
  for (const auto& el : b.elements) {
    const double j = 0.5 * (el.xi1 - el.xi0);
    for (std::size_t q = 0; q < g.points.size(); ++q) {
      const double xi = el.xi0 + (g.points[q] + 1) * j;
      const auto basis = b.curve.basis(xi, 1);
      const double jb = b.curve.derivative(xi, 1).norm();
      for (int a = 0; a < basis.R.cols(); ++a)
        nodal.segment<3>(3 * (basis.first + a)) += g.weights[q] * j * jb * basis.R(0, a) * f;
    }
  }
  NodalLoad load;
  for (int cp = 0; cp < b.num_control_points(); ++cp)
    for (int c = 0; c < 3; ++c) {
      load.dofs.push_back(m.dofs.dof(b.block, cp, c));
      load.values.conservativeResize(load.dofs.size());
      load.values[load.dofs.size() - 1] = nodal[3 * cp + c];
    }
  return load;
}

double beam_parameter(const BeamBody& b, const io::YamlNode& at) {
  if (auto e = at.optional("end")) {
    const bool start = e->as_choice({"start", "end"}) == "start";
    at.reject_unknown_keys();
    return start ? b.curve.knots().front() : b.curve.knots().back();
  }
  const auto x = at["xi"];
  const double xi = x.as_double();
  if (xi < b.curve.knots().front() || xi > b.curve.knots().back()) x.fail("a parameter inside the beam's knot range");
  at.reject_unknown_keys();
  return xi;
}

}  // namespace

void read_load(Model& m, const io::YamlNode& entry) {
  const BodyRef b = find_body(m, entry["body"]);
  const int function = read_function_ref(m, entry);
  const std::string type = entry["type"].as_choice(
      {"surface_force", "pressure", "line_force", "line_moment", "point_force", "line_load", "point_moment"});
  const bool shell_only =
      type == "surface_force" || type == "pressure" || type == "line_force" || type == "line_moment";
  const bool beam_only = type == "line_load" || type == "point_moment";
  if (shell_only && b.is_beam) entry["type"].fail("a load type for beams (point_force, line_load, point_moment)");
  if (beam_only && !b.is_beam) entry["type"].fail("a load type for shells (surface_force, pressure, line_force, line_moment, point_force)");
  NodalLoad load;
  if (type == "surface_force") {
    load = surface_load(m, m.shells[b.index], entry["force"].as_vector3(), false);
  } else if (type == "pressure") {
    load = surface_load(m, m.shells[b.index], Eigen::Vector3d(entry["value"].as_double(), 0, 0), true);
  } else if (type == "line_force") {
    const auto at = entry["at"];
    const std::string edge = at["edge"].as_choice({"u0", "u1", "v0", "v1"});
    at.reject_unknown_keys();
    load = edge_load(m, m.shells[b.index], edge, entry["force"].as_vector3());
  } else if (type == "line_moment") {
    const auto at = entry["at"];
    EdgeMoment em;
    em.shell = b.index;
    em.edge = at["edge"].as_choice({"u0", "u1", "v0", "v1"});
    at.reject_unknown_keys();
    em.moment = entry["moment"].as_vector3();
    em.function = function;
    const auto& s = m.shells[b.index];
    const double u_end = s.surface.knots(0).back(), v_end = s.surface.knots(1).back();
    for (std::size_t e = 0; e < s.elements.size(); ++e) {
      const auto& el = s.elements[e];
      const bool on = (em.edge == "u0" && el.u0 == s.surface.knots(0).front()) || (em.edge == "u1" && el.u1 == u_end) ||
                      (em.edge == "v0" && el.v0 == s.surface.knots(1).front()) || (em.edge == "v1" && el.v1 == v_end);
      if (on) em.elements.push_back(static_cast<int>(e));
    }
    m.edge_moments.push_back(std::move(em));
  } else if (type == "line_load") {
    load = beam_line_load(m, m.beams[b.index], entry["force"].as_vector3());
  } else if (type == "point_force") {
    const Eigen::Vector3d f = entry["force"].as_vector3();
    for (const auto& site : sites(m, b, entry["at"]))
      for (const auto& [cp, w] : site)
        for (int c = 0; c < 3; ++c) {
          load.dofs.push_back(m.dofs.dof(b.block, cp, c));
          load.values.conservativeResize(load.dofs.size());
          load.values[load.dofs.size() - 1] = w * f[c];
        }
  } else {  // point_moment
    const auto& beam = m.beams[b.index];
    PointMoment pm;
    pm.beam = b.index;
    pm.xi = beam_parameter(beam, entry["at"]);
    pm.moment = beam.share * entry["moment"].as_vector3();
    pm.function = function;
    pm.element = beam.element_of(pm.xi);
    pm.state = beam.state_at(pm.xi);
    m.moments.push_back(pm);
  }
  load.function = function;
  if (b.is_beam) load.values *= m.beams[b.index].share;  // loads on a beam count with its share
  entry.reject_unknown_keys();
  add_load(m, std::move(load));
}

void read_monitor(Model& m, const io::YamlNode& entry) {
  Monitor mon;
  mon.name = entry["name"].as_string();
  for (const auto& other : m.monitors)
    if (other.name == mon.name) entry["name"].fail("a monitor name not used before");
  const std::string type = entry["type"].as_choice({"displacement", "position", "reaction"});
  const BodyRef b = find_body(m, entry["body"]);
  const int c = component(b, entry["component"]);
  const auto where = sites(m, b, entry["at"]);
  if (type == "reaction") {
    mon.source = Monitor::Source::reaction;
    for (const auto& s : where) {
      if (s.size() != 1 || s[0].second != 1.0)
        entry["at"].fail("control points (an edge, a corner, an end or all) for a reaction sum");
      mon.weights.emplace_back(m.dofs.dof(b.block, s[0].first, c), 1.0);
    }
  } else {
    if (where.size() != 1) entry["at"].fail("a single point (a corner, a parametric point, an end or xi)");
    for (const auto& [cp, w] : where[0]) {
      mon.weights.emplace_back(m.dofs.dof(b.block, cp, c), w);
      if (type == "position" && c < 3) {
        const Eigen::Vector3d X = b.is_beam ? m.beams[b.index].curve.control_points()[cp]
                                            : m.shells[b.index].surface.control_points()[cp];
        mon.offset += w * X[c];
      }
    }
  }
  entry.reject_unknown_keys();
  m.monitors.push_back(std::move(mon));
}

}  // namespace fibrane::model
