// The monitors of a case file (docs/case-format.md, "monitors"): displacements and positions at points,
// reactions of supports, the applied load, and section quantities of beams.
#include <algorithm>

#include "case/case_conditions.hpp"
#include "case/case_sites.hpp"

namespace fibrane::casefile {

using model::Model;

namespace {

// Reaction: the full residual summed over the DOFs of component c at the sites of `at`, or of the named
// constraint, closed under the constraints (a clamp's tied row, the neighbours a symmetry plane ties).
std::unique_ptr<model::Monitor> reaction(Model& m, const std::string& name, const io::YamlNode& entry) {
  std::vector<int> seeds;
  int c = -1;
  if (auto con = entry.optional("constraint")) {
    const auto it = m.named_constraints.find(con->as_string());
    if (it == m.named_constraints.end()) con->fail("the name of a constraint defined before this monitor");
    const auto comp = entry["component"].as_choice({"x", "y", "z", "twist"});
    c = comp == "twist" ? 3 : comp[0] - 'x';
    for (int d : it->second)
      for (int b = 0; b < m.dofs.num_blocks(); ++b) {
        const int offset = m.dofs.block_offset(b), per = m.dofs.dofs_per_node(b);
        if (d >= offset && d < offset + m.dofs.block_size(b) && (d - offset) % per == c) seeds.push_back(d);
      }
    if (seeds.empty()) entry["component"].fail("a component the constraint acts on");
  } else {
    const BodyRef b = find_body(m, entry["body"]);
    c = component(b, entry["component"]);
    for (const auto& s : sites(m, b, entry["at"])) {
      if (s.size() != 1 || s[0].second != 1.0)
        entry["at"].fail("control points (an edge, a corner, an end or all) for a reaction sum");
      seeds.push_back(m.dofs.dof(b.block, s[0].first, c));
    }
  }
  std::vector<std::pair<int, double>> weights;
  for (int d : m.constraints.linked_dofs(seeds)) weights.emplace_back(d, 1.0);
  return std::make_unique<model::LinearMonitor>(name, model::LinearMonitor::Source::residual, std::move(weights));
}

// A displacement or position at a single point: the basis weights of its control points.
std::unique_ptr<model::Monitor> point_value(Model& m, const std::string& name, const io::YamlNode& entry,
                                            bool position) {
  const BodyRef b = find_body(m, entry["body"]);
  const int c = component(b, entry["component"]);
  const auto where = sites(m, b, entry["at"]);
  if (where.size() != 1) entry["at"].fail("a single point (a corner, a parametric point, an end or xi)");
  std::vector<std::pair<int, double>> weights;
  double offset = 0;
  for (const auto& [cp, w] : where[0]) {
    weights.emplace_back(m.dofs.dof(b.block, cp, c), w);
    if (position && c < 3) {
      const Eigen::Vector3d X = b.is_beam ? m.beams[b.index].curve.control_points()[cp]
                                          : m.shells[b.index].surface.control_points()[cp];
      offset += w * X[c];
    }
  }
  return std::make_unique<model::LinearMonitor>(name, model::LinearMonitor::Source::displacement, std::move(weights),
                                                offset);
}

// The applied load in one direction, on one body or on all.
std::unique_ptr<model::Monitor> applied_load(Model& m, const std::string& name, const io::YamlNode& entry) {
  const int c = entry["component"].as_choice({"x", "y", "z"})[0] - 'x';
  std::vector<int> dofs;
  auto add_block = [&](int block) {
    for (int node = 0; node < m.dofs.num_nodes(block); ++node) dofs.push_back(m.dofs.dof(block, node, c));
  };
  if (entry.has("body")) add_block(find_body(m, entry["body"]).block);
  else
    for (int b = 0; b < m.dofs.num_blocks(); ++b) add_block(b);
  std::sort(dofs.begin(), dofs.end());
  return std::make_unique<model::AppliedLoadMonitor>(name, std::move(dofs));
}


// A section quantity of a beam at one point: rotation, tangent, director2, director3 (a component x, y,
// z or an `axis`), section (quantity: axial_force, torque, bending2, bending3), twist_angle.
std::unique_ptr<model::Monitor> beam_point(Model& m, const std::string& name, const std::string& type,
                                           const io::YamlNode& entry) {
  using Q = model::BeamPointMonitor::Quantity;
  const BodyRef ref = find_body(m, entry["body"]);
  if (!ref.is_beam) entry["body"].fail("the name of a beam (a '" + type + "' monitor is a beam section quantity)");
  model::BeamBody& b = m.beams[ref.index];
  const double xi = beam_parameter(b, entry["at"]);
  Eigen::Vector3d axis = Eigen::Vector3d::Zero();
  Q q = Q::twist_angle;
  if (type == "rotation" || type == "tangent" || type == "director2" || type == "director3") {
    q = type == "rotation" ? Q::rotation : type == "tangent" ? Q::tangent : type == "director2" ? Q::director2 : Q::director3;
    if (auto a = entry.optional("axis")) {
      axis = a->as_vector3();
      if (!(axis.norm() > 0)) a->fail("a non-zero vector");
      axis.normalize();
    } else {
      axis[entry["component"].as_choice({"x", "y", "z"})[0] - 'x'] = 1.0;
    }
  } else if (type == "section") {
    const std::string s = entry["quantity"].as_choice({"axial_force", "torque", "bending2", "bending3"});
    q = s == "axial_force" ? Q::axial_force : s == "torque" ? Q::torque : s == "bending2" ? Q::bending2 : Q::bending3;
  }
  const int probe = q == Q::twist_angle ? b.add_twist_probes(xi) : b.add_probe(xi);
  return std::make_unique<model::BeamPointMonitor>(name, b, q, xi, probe, axis);
}

}  // namespace

void read_monitor(Model& m, const io::YamlNode& entry) {
  const std::string name = entry["name"].as_string();
  for (const auto& other : m.monitors)
    if (other->name() == name) entry["name"].fail("a monitor name not used before");
  const std::string type = entry["type"].as_choice({"displacement", "position", "reaction", "applied_load", "rotation",
                                                    "tangent", "director2", "director3", "section", "twist_angle"});
  std::unique_ptr<model::Monitor> monitor;
  if (type == "reaction") monitor = reaction(m, name, entry);
  else if (type == "applied_load") monitor = applied_load(m, name, entry);
  else if (type == "displacement" || type == "position") monitor = point_value(m, name, entry, type == "position");
  else monitor = beam_point(m, name, type, entry);
  entry.reject_unknown_keys();
  m.monitors.push_back(std::move(monitor));
}

}  // namespace fibrane::casefile
