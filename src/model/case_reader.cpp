#include "model/case_reader.hpp"

#include <algorithm>
#include <filesystem>

#include "common/error.hpp"

#include "model/case_conditions.hpp"
#include "model/case_geometry.hpp"
#include "model/results.hpp"

namespace fibrane::model {

namespace {

void read_functions(Model& m, const io::YamlNode& node) {
  if (!node.is_map()) node.fail("a map of name: {linear: slope} | {constant: value} | {table: [[t, f], ...]}");
  for (const auto& name : node.keys()) {
    const auto f = node[name];
    if (auto l = f.optional("linear")) {
      m.functions.add(name, LoadFunction::linear(l->as_double()));
    } else if (auto c = f.optional("constant")) {
      m.functions.add(name, LoadFunction::constant(c->as_double()));
    } else if (auto t = f.optional("table")) {
      std::vector<std::pair<double, double>> pts;
      if (!t->is_sequence() || t->size() == 0) t->fail("a list of [t, f] pairs");
      for (std::size_t i = 0; i < t->size(); ++i) {
        const auto row = t->at(i).as_doubles();
        if (row.size() != 2) t->at(i).fail("a pair [t, f]");
        if (!pts.empty() && !(row[0] > pts.back().first)) t->at(i).fail("a time larger than the previous row's");
        pts.emplace_back(row[0], row[1]);
      }
      m.functions.add(name, LoadFunction::table(std::move(pts)));
    } else {
      f.fail("one of {linear: slope}, {constant: value}, {table: [[t, f], ...]}");
    }
    f.reject_unknown_keys();
  }
}

void read_shell(Model& m, const io::YamlNode& node) {
  const std::string name = node["name"].as_string();
  auto surface = read_surface(node["geometry"], node.optional("refine"));
  shell::ShellSection section;
  section.thickness = node["thickness"].positive();
  const auto mat = node["material"];
  section.young = mat["young"].positive();
  section.poisson = mat["poisson"].in_range(-1.0, 0.5, true, true);
  mat.reject_unknown_keys();
  ShellBody body(name, std::move(surface), section);
  if (auto g = node.optional("gauss_points")) {
    body.gauss_points[0] = body.gauss_points[1] = g->positive_int();
  }
  node.reject_unknown_keys();
  m.add_shell(std::move(body));
}

beam::BeamSection read_section(const io::YamlNode& node, double young, double poisson, double& radius) {
  if (auto c = node.optional("circle")) {
    radius = (*c)["radius"].positive();
    c->reject_unknown_keys();
    node.reject_unknown_keys();
    return beam::BeamSection::circular(young, poisson, radius);
  }
  const double area = node["area"].positive();
  const double i2 = node["inertia2"].positive(), i3 = node["inertia3"].positive();
  const double it = node["torsion"].positive();
  node.reject_unknown_keys();
  return beam::BeamSection::general(young, poisson, area, i2, i3, it);
}

void read_beam(Model& m, const io::YamlNode& node) {
  const std::string name = node["name"].as_string();
  auto curve = read_curve(node["geometry"], node.optional("refine"));
  const auto mat = node["material"];
  const double young = mat["young"].positive();
  const double poisson = mat["poisson"].in_range(-1.0, 0.5, true, true);
  mat.reject_unknown_keys();
  double radius = 0.0;
  const auto section = read_section(node["section"], young, poisson, radius);
  Eigen::Vector3d director = Eigen::Vector3d::Zero();
  if (auto d = node.optional("director")) {
    director = d->as_vector3();
    if (director.norm() == 0.0) d->fail("a non-zero vector");
  }
  BeamBody body(name, std::move(curve), section, director);
  body.section_radius = radius;
  if (auto share = node.optional("symmetry_share")) body.share = share->in_range(0.0, 1.0, true, false);
  if (auto g = node.optional("gauss_points")) body.gauss_points = g->positive_int();
  node.reject_unknown_keys();
  m.add_beam(std::move(body));
}

void read_interaction(Model& m, const io::YamlNode& node) {
  const auto beam_node = node["beam"], shell_node = node["shell"];
  int beam = -1, shell = -1;
  for (std::size_t i = 0; i < m.beams.size(); ++i)
    if (m.beams[i].name == beam_node.as_string()) beam = static_cast<int>(i);
  for (std::size_t i = 0; i < m.shells.size(); ++i)
    if (m.shells[i].name == shell_node.as_string()) shell = static_cast<int>(i);
  if (beam < 0) beam_node.fail("the name of a beam defined in this case");
  if (shell < 0) shell_node.fail("the name of a shell defined in this case");
  const auto& b = m.beams[beam];
  if (b.section_radius <= 0.0)
    beam_node.fail_message("beam '" + b.name + "' needs a circular section (section: {circle: {radius: R}}): the "
                           "disk-plate law integrates over a disk");
  const std::string name = node.get("name", b.name + "_" + m.shells[shell].name);
  const std::string f = node.get("formulation", std::string("RF2"));
  if (auto fn = node.optional("formulation")) fn->as_choice({"FF", "RF1", "RF2"});
  const auto formulation = f == "FF" ? interaction::Formulation::FF
                           : f == "RF1" ? interaction::Formulation::RF1 : interaction::Formulation::RF2;
  auto ff_tangent = interaction::FfTangent::exact;
  if (auto t = node.optional("ff_tangent"))
    ff_tangent = t->as_choice({"exact", "rf1"}) == "rf1" ? interaction::FfTangent::rf1 : interaction::FfTangent::exact;
  const auto lj = node["lennard_jones"];
  laws::LennardJonesDiskPlate law;
  law.epsilon = lj["epsilon"].positive();
  law.sigma = lj["sigma"].positive();
  law.density_beam = lj.has("density_beam") ? lj["density_beam"].positive() : 1.0;
  law.density_shell = lj.has("density_shell") ? lj["density_shell"].positive() : 1.0;
  law.strength = lj.has("strength") ? lj["strength"].positive() : 1.0;
  law.disk_radius = b.section_radius;
  law.plate_thickness = m.shells[shell].section.thickness;
  lj.reject_unknown_keys();
  double soft_width = 0, soft_below = 0;
  if (auto soft = node.optional("soft_minimum")) {
    if (formulation != interaction::Formulation::RF2)
      soft->fail_message("the soft minimum is implemented for the RF2 formulation only");
    soft_width = (*soft)["width"].in_range(0.0, 5e-3, true, false);
    soft_below = soft->has("below") ? (*soft)["below"].positive() : 0.05;
    soft->reject_unknown_keys();
  }
  node.reject_unknown_keys();
  for (const auto& c : m.couplings)
    if (c.name() == name) node["name"].fail("an interaction name not used before");
  m.couplings.emplace_back(name, beam, shell, law, formulation, ff_tangent, b, m.shells[shell]);
  if (soft_width > 0) m.couplings.back().enable_soft_minimum(soft_width, soft_below);
}

void check_unique_names(const Model& m, const io::YamlNode& root) {
  std::vector<std::string> names;
  for (const auto& s : m.shells) names.push_back(s.name);
  for (const auto& b : m.beams) names.push_back(b.name);
  for (std::size_t i = 0; i < names.size(); ++i)
    for (std::size_t j = i + 1; j < names.size(); ++j)
      if (names[i] == names[j]) root.fail_message("two bodies are named '" + names[i] + "'");
}

template <class F>
void for_each_entry(const std::optional<io::YamlNode>& list, F&& f) {
  if (!list) return;
  if (!list->is_sequence()) list->fail("a list");
  for (std::size_t i = 0; i < list->size(); ++i) f(list->at(i));
}

void read_steps(RunSettings& run, const std::optional<io::YamlNode>& node) {
  if (!node) return;
  auto& s = run.steps;
  s.t_end = node->get("t_end", s.t_end);
  if (auto v = node->optional("t_end")) v->positive();
  s.dt_initial = node->has("dt") ? (*node)["dt"].positive() : s.dt_initial;
  s.dt_max = node->has("dt_max") ? (*node)["dt_max"].positive() : std::max(s.dt_max, s.dt_initial);
  s.dt_min = node->has("dt_min") ? (*node)["dt_min"].positive() : s.dt_min;
  if (s.dt_min > s.dt_initial) (*node)["dt_min"].fail("dt_min <= dt");
  if (s.dt_max < s.dt_initial) (*node)["dt_max"].fail("dt_max >= dt");
  s.easy_iterations = node->get("easy_iterations", s.easy_iterations);
  s.growth = node->get("growth", s.growth);
  s.cutback = node->get("cutback", s.cutback);
  if (!(s.cutback > 0 && s.cutback < 1)) (*node)["cutback"].fail("a factor in (0, 1)");
  if (!(s.growth >= 1)) (*node)["growth"].fail("a factor >= 1");
  s.max_steps = node->get("max_steps", s.max_steps);
  run.linear = node->get("linear", run.linear);
  if (auto stop = node->optional("stop")) {
    if (stop->has("column") || stop->has("below_fraction_of_peak")) {
      run.stop_column = (*stop)["column"].as_string();
      run.stop_fraction = (*stop)["below_fraction_of_peak"].in_range(0.0, 1.0, true, true);
    }
    run.stop_at_limit_point = stop->get("at_limit_point", false);
    stop->reject_unknown_keys();
  }
  s.extrapolate = node->get("extrapolate", s.extrapolate);
  run.newton.max_iterations = node->get("max_iterations", run.newton.max_iterations);
  run.newton.tol_relative = node->get("tolerance", run.newton.tol_relative);
  run.newton.tol_absolute = node->get("tolerance_absolute", run.newton.tol_absolute);
  run.newton.tol_increment = node->get("tolerance_increment", run.newton.tol_increment);
  if (node->has("line_search")) {
    run.newton.line_search = (*node)["line_search"].as_int();
    if (run.newton.line_search < 0 || run.newton.line_search > 30)
      (*node)["line_search"].fail("the most halvings of a Newton update, an integer in [0, 30] (0: none)");
  }
  if (node->has("reuse_factorization"))
    run.newton.reuse_below = (*node)["reuse_factorization"].in_range(0.0, 1.0, false, true);
  run.linear_solver = node->has("solver") ? (*node)["solver"].as_choice({"auto", "cholmod", "ldlt", "mumps", "umfpack"})
                                          : run.linear_solver;
  node->reject_unknown_keys();
}

void read_output(OutputSettings& out, const std::optional<io::YamlNode>& node, const std::string& name) {
  out.directory = "out/" + name;
  if (!node) return;
  out.directory = node->get("directory", out.directory);
  out.vtk = node->get("vtk", out.vtk);
  out.vtk_every = node->has("vtk_every") ? (*node)["vtk_every"].positive_int() : out.vtk_every;
  out.samples = node->has("samples") ? (*node)["samples"].positive_int() : out.samples;
  node->reject_unknown_keys();
}

}  // namespace

Case read_case(const std::string& path) {
  const auto root = io::YamlNode::load_file(path);
  if (!root.is_map()) root.fail("a map with the keys shells, beams, constraints, loads, steps, ...");
  Case c;
  c.path = path;
  c.name = std::filesystem::path(path).stem().string();
  c.model = std::make_unique<Model>();
  Model& m = *c.model;
  m.title = root.get("title", c.name);
  if (auto f = root.optional("functions")) read_functions(m, *f);
  for_each_entry(root.optional("shells"), [&](const io::YamlNode& n) { read_shell(m, n); });
  for_each_entry(root.optional("beams"), [&](const io::YamlNode& n) { read_beam(m, n); });
  if (m.shells.empty() && m.beams.empty()) root.fail_message("the case defines no body: add 'shells' or 'beams'");
  check_unique_names(m, root);
  for_each_entry(root.optional("constraints"), [&](const io::YamlNode& n) { read_constraint(m, n); });
  for_each_entry(root.optional("loads"), [&](const io::YamlNode& n) { read_load(m, n); });
  for_each_entry(root.optional("interactions"), [&](const io::YamlNode& n) { read_interaction(m, n); });
  for_each_entry(root.optional("monitors"), [&](const io::YamlNode& n) { read_monitor(m, n); });
  read_steps(c.run, root.optional("steps"));
  if (!c.run.stop_column.empty()) {
    const auto columns = history_columns(m);
    if (std::find(columns.begin(), columns.end(), c.run.stop_column) == columns.end()) {
      std::string known;
      for (const auto& k : columns) known += (known.empty() ? "" : ", ") + k;
      root["steps"]["stop"]["column"].fail("a history column (" + known + ")");
    }
  }
  read_output(c.output, root.optional("output"), c.name);
  root.reject_unknown_keys();
  try {
    m.finalize();
  } catch (const InputError& e) {
    throw InputError(path + ": constraints: " + e.what());
  }
  return c;
}

}  // namespace fibrane::model
