#include "case/case_checks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "case/case_limits.hpp"
#include "model/observables.hpp"

namespace fibrane::casefile {
namespace {

// The YAML node of body `name`: its entry under 'shells' or 'beams'.
std::optional<io::YamlNode> body_entry(const io::YamlNode& root, const std::string& name) {
  for (const char* list : {"shells", "beams"}) {
    if (!root.has(list)) continue;
    const auto entries = root[list];
    for (std::size_t i = 0; i < entries.size(); ++i)
      if (entries.at(i).has("name") && entries.at(i)["name"].as_string() == name) return entries.at(i)["name"];
  }
  return std::nullopt;
}

}  // namespace

void check_output_names(const model::Model& m, const io::YamlNode& root) {
  // Every series name a body or interaction writes, with who writes it.
  std::vector<std::pair<std::string, std::string>> used;
  auto claim = [&](const std::string& name, const std::string& owner, const io::YamlNode& at) {
    for (const auto& [other, who] : used)
      if (other == name)
        at.fail_message(fmt::format("the output files of {} would be named like those of {} ('{}'): rename one",
                                    owner, who, name));
    used.emplace_back(name, owner);
  };
  std::vector<std::string> bodies;
  for (const auto& s : m.shells) bodies.push_back(s.name());
  for (const auto& b : m.beams) bodies.push_back(b.name());
  for (std::size_t k = 0; k < bodies.size(); ++k) {
    const std::string owner = "body '" + bodies[k] + "'";
    const auto at = body_entry(root, bodies[k]);
    for (std::size_t j = 0; j < k; ++j)
      if (bodies[j] == bodies[k]) (at ? *at : root).fail_message("two bodies are named '" + bodies[k] + "'");
    claim(bodies[k], owner, at ? *at : root);
    claim(bodies[k] + "_sampled", owner, at ? *at : root);
  }
  for (std::size_t i = 0; i < m.interactions().size(); ++i) {
    const auto entry = root["interactions"].at(i);
    const std::string owner = "interaction '" + m.interactions()[i]->name() + "'";
    for (const auto& series : m.interactions()[i]->point_series())
      claim(series.name, owner, entry.has("name") ? entry["name"] : entry);
  }
}

void check_monitor_names(const model::Model& m, const io::YamlNode& root) {
  if (m.monitors.empty()) return;
  const auto entries = root["monitors"];
  // The columns output::history_columns writes besides the observables (the energy account in dynamic runs).
  std::set<std::string> builtin{"step", "t", "load_factor", "iterations", "residual", "negative_eigenvalues",
                                "limit_point", "kinetic_energy", "interaction_energy", "external_work",
                                "prescribed_work", "damping_work", "energy_balance"};
  const auto observed = model::observables(m);  // the built-in ones, then one per monitor
  for (std::size_t k = 0; k + m.monitors.size() < observed.size(); ++k) builtin.insert(observed[k].name);
  std::set<std::string> seen;
  for (std::size_t i = 0; i < m.monitors.size(); ++i) {
    const auto node = entries.at(i)["name"];
    read_safe_name(node);
    if (builtin.count(m.monitors[i]->name()))
      node.fail("a monitor name other than the built-in history columns (step, t, load_factor, iterations, "
                "residual, negative_eigenvalues, limit_point, strain_energy, the interactions' <interaction>_<quantity> "
                "(SBS: _energy, _force_x/y/z, _lost_points), and the energy account of dynamic runs)");
    if (!seen.insert(m.monitors[i]->name()).second) node.fail("a monitor name not used before");
  }
}

std::string describe_dof(const model::Model& m, int dof) {
  for (int b = 0; b < m.dofs.num_blocks(); ++b) {
    const int local = dof - m.dofs.block_offset(b);
    if (local < 0 || local >= m.dofs.block_size(b)) continue;
    const int per = m.dofs.dofs_per_node(b), node = local / per, c = local % per;
    const std::string& name = m.dofs.block_name(b);
    std::string point = std::to_string(node);
    for (const auto& s : m.shells)
      if (s.name() == name) {
        const int nu = s.surface.num_control_points(0);
        point = fmt::format("[{}, {}]", node % nu, node / nu);
      }
    static const char* const components[] = {"x", "y", "z", "twist"};
    return fmt::format("body '{}' control point {} component {}", name, point, c < 4 ? components[c] : "?");
  }
  return fmt::format("DOF {}", dof);
}

InputError explain_constraint_error(const solve::ConstraintError& e, const model::Model& m,
                                    const ConstraintOrigins& origins, const std::string& file) {
  std::string what = e.what();
  const auto colon = what.find(" on DOF");
  std::string kind = what.substr(0, colon == std::string::npos ? what.find(':') : colon);
  std::string dofs;
  for (int d : e.dofs) dofs += (dofs.empty() ? "" : ", ") + describe_dof(m, d);
  std::string entries;
  int line = 0;
  for (std::size_t c : e.constraints) {
    const auto it = std::upper_bound(origins.first.begin(), origins.first.end(), c);
    if (it == origins.first.begin()) continue;
    const auto& node = origins.entries[static_cast<std::size_t>(it - origins.first.begin()) - 1];
    const std::string text = fmt::format("{} (line {})", node.path(), node.line());
    if (entries.find(text) == std::string::npos) entries += (entries.empty() ? "" : " and ") + text;
    line = std::max(line, node.line());
  }
  return InputError(fmt::format("{}:{}: constraints: {} on {}{}", file, line, kind, dofs,
                                entries.empty() ? "" : ": from " + entries));
}

void check_free_bodies(const model::Model& m, const io::YamlNode& root) {
  const auto& cs = m.constraints;
  auto block_of = [&](int d) {
    for (int b = 0; b < m.dofs.num_blocks(); ++b)
      if (d >= m.dofs.block_offset(b) && d < m.dofs.block_offset(b) + m.dofs.block_size(b)) return b;
    return -1;
  };
  // held[d]: a uniform translation of d's body along d's component cannot pass through DOF d: it is fixed,
  // tied to another body or component, scaled, or another body depends on it.
  std::vector<char> held(static_cast<std::size_t>(m.dofs.size()), 0);
  for (int d : cs.constrained_dofs()) {
    const auto& row = cs.expansion(d);
    double sum = 0.0;
    bool outside = false;
    for (const auto& [free, coef] : row) {
      const int master = cs.free_dof(free);
      sum += coef;
      if (block_of(master) != block_of(d) || (master - d) % m.dofs.dofs_per_node(block_of(d)) != 0) {
        outside = true;
        held[static_cast<std::size_t>(master)] = 1;
      }
    }
    held[static_cast<std::size_t>(d)] = row.empty() || outside || std::abs(sum - 1.0) > 1e-9;
  }
  for (int b = 0; b < m.dofs.num_blocks(); ++b) {
    const std::string& name = m.dofs.block_name(b);
    bool interacts = false;
    for (const auto& i : m.interactions()) interacts |= i->bodies().first == name || i->bodies().second == name;
    if (interacts) continue;
    std::string free;
    for (int c = 0; c < 3; ++c) {
      bool any = false;
      for (int node = 0; node < m.dofs.num_nodes(b) && !any; ++node) any = held[static_cast<std::size_t>(m.dofs.dof(b, node, c))];
      if (!any) free += (free.empty() ? "" : ", ") + std::string(1, static_cast<char>('x' + c));
    }
    if (free.empty()) continue;
    const auto at = body_entry(root, name);
    (at ? *at : root).fail_message(fmt::format(
        "body '{}' is free to translate in {}: no constraint holds that component and no interaction acts on "
        "the body, so its stiffness is singular; add a constraint (e.g. fix it at an edge, corner or end)",
        name, free));
  }
}

}  // namespace fibrane::casefile
