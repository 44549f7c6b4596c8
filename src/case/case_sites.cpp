#include "case/case_sites.hpp"

#include <algorithm>
#include <cmath>

namespace fibrane::casefile {

BodyRef find_body(const Model& m, const io::YamlNode& name_node) {
  const std::string name = name_node.as_string();
  for (std::size_t i = 0; i < m.shells.size(); ++i)
    if (m.shells[i].name() == name) return {false, static_cast<int>(i), m.shells[i].block, 3};
  for (std::size_t i = 0; i < m.beams.size(); ++i)
    if (m.beams[i].name() == name) return {true, static_cast<int>(i), m.beams[i].block, 4};
  name_node.fail("the name of a shell or beam defined in this case");
}

namespace {

Site single(int cp) { return Site{{cp, 1.0}}; }

std::vector<Site> shell_sites(const model::ShellBody& s, const io::YamlNode& at) {
  std::vector<Site> out;
  if (auto e = at.optional("edge")) {
    const std::string edge = e->as_choice({"u0", "u1", "v0", "v1"});
    for (int cp : s.surface.edge_indices(edge, 0)) out.push_back(single(cp));
  } else if (auto c = at.optional("corner")) {
    const auto ij = c->as_doubles();
    if (ij.size() != 2 || (ij[0] != 0 && ij[0] != 1) || (ij[1] != 0 && ij[1] != 1))
      c->fail("[i, j] with i, j in {0, 1} (0: start, 1: end of each parameter direction)");
    const int i = ij[0] == 0 ? 0 : s.surface.num_control_points(0) - 1;
    const int j = ij[1] == 0 ? 0 : s.surface.num_control_points(1) - 1;
    out.push_back(single(s.surface.index(i, j)));
  } else if (auto p = at.optional("point")) {
    const auto uv = p->as_doubles();
    const auto& ku = s.surface.knots(0);
    const auto& kv = s.surface.knots(1);
    if (uv.size() != 2 || uv[0] < ku.front() || uv[0] > ku.back() || uv[1] < kv.front() || uv[1] > kv.back())
      p->fail("[u, v] inside the parameter domain of shell '" + s.name() + "'");
    const auto basis = s.surface.basis(uv[0], uv[1]);
    Site site;
    for (std::size_t a = 0; a < basis.indices.size(); ++a)
      if (std::abs(basis.R(0, a)) > 1e-14) site.emplace_back(basis.indices[a], basis.R(0, a));
    out.push_back(site);
  } else if (auto all = at.optional("all")) {
    for (int cp = 0; cp < s.num_control_points(); ++cp) out.push_back(single(cp));
  } else {
    at.fail("one of 'edge', 'corner', 'point' or 'all' for shell '" + s.name() + "'");
  }
  at.reject_unknown_keys();
  return out;
}

std::vector<Site> beam_sites(const model::BeamBody& b, const io::YamlNode& at) {
  std::vector<Site> out;
  if (auto e = at.optional("end")) {
    const std::string end = e->as_choice({"start", "end"});
    out.push_back(single(end == "start" ? 0 : b.num_control_points() - 1));
  } else if (auto x = at.optional("xi")) {
    const double xi = x->as_double();
    if (xi < b.curve.knots().front() || xi > b.curve.knots().back())
      x->fail("a parameter inside the knot range of beam '" + b.name() + "'");
    const auto basis = b.curve.basis(xi, 0);
    Site site;
    for (int a = 0; a < basis.R.cols(); ++a)
      if (std::abs(basis.R(0, a)) > 1e-14) site.emplace_back(basis.first + a, basis.R(0, a));
    out.push_back(site);
  } else if (auto all = at.optional("all")) {
    for (int cp = 0; cp < b.num_control_points(); ++cp) out.push_back(single(cp));
  } else {
    at.fail("one of 'end', 'xi' or 'all' for beam '" + b.name() + "'");
  }
  at.reject_unknown_keys();
  return out;
}

}  // namespace

std::vector<Site> sites(const Model& m, const BodyRef& b, const io::YamlNode& at) {
  if (at.is_sequence()) {  // a list of places: their union, in order
    if (at.size() == 0) at.fail("a non-empty list of places such as [{edge: u0}, {corner: [1, 1]}]");
    std::vector<Site> all;
    for (std::size_t i = 0; i < at.size(); ++i)
      for (auto& s : sites(m, b, at.at(i))) all.push_back(std::move(s));
    return all;
  }
  if (!at.is_map()) at.fail("a map such as {edge: u0}, or a list of such maps");
  return b.is_beam ? beam_sites(m.beams[b.index], at) : shell_sites(m.shells[b.index], at);
}

std::vector<int> boundary_row(const Model& m, const BodyRef& b, const io::YamlNode& at, int row) {
  if (b.is_beam) {
    const auto& beam = m.beams[b.index];
    const std::string end = at["end"].as_choice({"start", "end"});
    const int n = beam.num_control_points();
    return {end == "start" ? row : n - 1 - row};
  }
  const std::string edge = at["edge"].as_choice({"u0", "u1", "v0", "v1"});
  return m.shells[b.index].surface.edge_indices(edge, row);
}

int component(const BodyRef& b, const io::YamlNode& node) {
  const std::string c = b.is_beam ? node.as_choice({"x", "y", "z", "twist"}) : node.as_choice({"x", "y", "z"});
  if (c == "twist") return 3;
  return c[0] - 'x';
}

double beam_parameter(const model::BeamBody& b, const io::YamlNode& at) {
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

}  // namespace fibrane::casefile
