#include "case/case_conditions.hpp"

#include <algorithm>
#include <cmath>

#include "case/case_sites.hpp"

namespace fibrane::casefile {

using model::Model;

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

void read_constraint_entry(Model& m, const io::YamlNode& entry);

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
  (void)entry.optional("name");  // read by name_constraint()
  entry.reject_unknown_keys();
  m.constraints.add(lc);
}

// Records the DOFs the constraints added since `first` touch (slaves and masters) under the entry's name.
void name_constraint(Model& m, const io::YamlNode& entry, int first) {
  const auto name = entry.optional("name");
  if (!name) return;
  const std::string n = name->as_string();
  if (m.named_constraints.count(n)) name->fail("a constraint name not used before");
  std::vector<int> dofs;
  for (int i = first; i < m.constraints.num_added(); ++i) {
    const auto& c = m.constraints.added(i);
    dofs.push_back(c.slave);
    for (const auto& [d, coef] : c.masters) dofs.push_back(d);
  }
  std::sort(dofs.begin(), dofs.end());
  dofs.erase(std::unique(dofs.begin(), dofs.end()), dofs.end());
  m.named_constraints[n] = std::move(dofs);
}

}  // namespace

void read_constraint(Model& m, const io::YamlNode& entry) {
  const int first = m.constraints.num_added();
  read_constraint_entry(m, entry);
  name_constraint(m, entry, first);
}

namespace {

void read_constraint_entry(Model& m, const io::YamlNode& entry) {
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
      model::ShellBody& shell = m.shells[b.index];
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
  (void)entry.optional("name");  // read by name_constraint()
  entry.reject_unknown_keys();
}

}  // namespace
}  // namespace fibrane::casefile
