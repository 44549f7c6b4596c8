// The loads of a case file. Distributed loads are integrated by the body they act on
// (ShellBody::surface_load, ..., BeamBody::line_load); here they are only read and attached.
#include <cmath>

#include "case/case_conditions.hpp"
#include "case/case_sites.hpp"

namespace fibrane::casefile {

using model::Model;
using model::NodalLoad;

namespace {

std::string read_edge(const io::YamlNode& entry) {
  const auto at = entry["at"];
  const std::string edge = at["edge"].as_choice({"u0", "u1", "v0", "v1"});
  at.reject_unknown_keys();
  return edge;
}

// A point force at the sites of `at`, spread over their control points with the basis weights.
NodalLoad point_force(const Model& m, const BodyRef& b, const io::YamlNode& entry) {
  const Eigen::Vector3d f = entry["force"].as_vector3();
  NodalLoad load;
  std::vector<double> values;
  for (const auto& site : sites(m, b, entry["at"]))
    for (const auto& [cp, w] : site)
      for (int c = 0; c < 3; ++c) {
        load.dofs.push_back(m.dofs.dof(b.block, cp, c));
        values.push_back(w * f[c]);
      }
  load.values = Eigen::Map<const Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size()));
  return load;
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
    load = NodalLoad::from_nodal(m.dofs, b.block, m.shells[b.index].surface_load(entry["force"].as_vector3()), 3, function);
  } else if (type == "pressure") {
    load = NodalLoad::from_nodal(m.dofs, b.block, m.shells[b.index].pressure_load(entry["value"].as_double()), 3, function);
  } else if (type == "line_force") {
    const std::string edge = read_edge(entry);
    load = NodalLoad::from_nodal(m.dofs, b.block, m.shells[b.index].edge_load(edge, entry["force"].as_vector3()), 3, function);
  } else if (type == "line_moment") {
    const std::string edge = read_edge(entry);
    m.edge_moments.emplace_back(m.shells[b.index], edge, entry["moment"].as_vector3(), function);
  } else if (type == "line_load") {
    load = NodalLoad::from_nodal(m.dofs, b.block, m.beams[b.index].line_load(entry["force"].as_vector3()), 3, function, true);
  } else if (type == "point_force") {
    load = point_force(m, b, entry);
  } else {  // point_moment
    const auto& beam = m.beams[b.index];
    const bool follower = entry.get("follower", false);
    m.moments.emplace_back(beam, beam_parameter(beam, entry["at"]), beam.share * entry["moment"].as_vector3(), function,
                           follower);
  }
  load.function = function;
  if (b.is_beam) load.values *= m.beams[b.index].share;  // loads on a beam count with its share
  entry.reject_unknown_keys();
  if (!load.dofs.empty()) m.nodal_loads.loads.push_back(std::move(load));
}

}  // namespace fibrane::casefile
