#include "case/case_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "common/error.hpp"
#include "common/format.hpp"
#include "io/yaml_guard.hpp"
#include "io/yaml_parameters.hpp"
#include "shell/material.hpp"

#include "case/case_checks.hpp"
#include "case/case_conditions.hpp"
#include "case/case_geometry.hpp"
#include "case/case_interactions.hpp"
#include "case/case_limits.hpp"
#include "case/case_methods.hpp"
#include "case/case_output.hpp"
#include "case/case_steps.hpp"
#include "model/observables.hpp"

namespace fibrane::casefile {

using model::BeamBody;
using model::LoadFunction;
using model::Model;
using model::ShellBody;

namespace {

void read_functions(Model& m, const io::YamlNode& node) {
  if (!node.is_map())
    node.fail("a map of name: {linear: slope} | {constant: value} | {table: [[t, f], ...]} | "
              "{smooth_ramp: {slope, duration}}");
  for (const auto& name : node.keys()) {
    const auto f = node[name];
    if (m.functions.find(name) >= 0)  // only the built-in ones exist before this loop
      f.fail_message("'" + name + "' is a built-in load function (f(t) = t) and cannot be redefined: choose "
                     "another name");
    if (auto l = f.optional("linear")) {
      m.functions.add(name, LoadFunction::linear(l->as_double()));
    } else if (auto c = f.optional("constant")) {
      m.functions.add(name, LoadFunction::constant(c->as_double()));
    } else if (auto r = f.optional("smooth_ramp")) {
      const double slope = (*r)["slope"].as_double(), duration = (*r)["duration"].positive();
      r->reject_unknown_keys();
      m.functions.add(name, LoadFunction::smooth_ramp(slope, duration));
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
      f.fail("one of {linear: slope}, {constant: value}, {table: [[t, f], ...]}, {smooth_ramp: {slope, duration}}");
    }
    f.reject_unknown_keys();
  }
}

// The geometry of a body: `read` builds it; a spline error the reader's own checks did not catch is
// reported at the geometry block.
template <class Read>
auto read_geometry(const io::YamlNode& node, Read&& read) {
  try {
    return read(node["geometry"], node.optional("refine"));
  } catch (const std::invalid_argument& e) {
    node["geometry"].fail_message(std::string("invalid geometry: ") + e.what());
  }
}

void read_shell(Model& m, const io::YamlNode& node) {
  const std::string name = read_safe_name(node["name"]);
  auto surface = read_geometry(node, [&](const io::YamlNode& g, const std::optional<io::YamlNode>& r) {
    return read_surface(g, r, model_size(m));
  });
  check_no_kinks({&surface.knots(0), &surface.knots(1)}, node, "shell");
  shell::ShellSection section;
  section.thickness = node["thickness"].positive();
  const auto mat = node["material"];
  const std::string model = mat.get("model", "svk");
  const auto& materials = shell::material_registry();
  if (!materials.find(model)) mat["model"].fail("one of " + materials.names_text());
  // The density belongs to the body (its inertia), not to the constitutive model.
  const double density = mat.has("density") ? mat["density"].positive() : 0.0;
  section.material = materials.make(model, io::YamlParameters(mat, {"model", "density"}));
  const int degree = std::max(surface.degree(0), surface.degree(1));
  ShellBody body(name, std::move(surface), section);
  body.density = density;
  if (auto g = node.optional("gauss_points")) body.gauss_points[0] = body.gauss_points[1] = read_gauss_points(*g, degree);
  node.reject_unknown_keys();
  m.add_shell(std::move(body));
  check_fits(model_size(m), node["geometry"]);
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

// A beam is a slender body: a section radius above the axis length is no beam.
void check_slender(const io::YamlNode& section, double radius, double length) {
  if (radius <= length) return;
  const auto at = section.has("circle") ? section["circle"]["radius"] : section["area"];
  at.fail_message(fmt::format("the section (radius {}) is larger than the beam's length {}: a beam model needs a "
                              "slender body",
                              format_number(radius), format_number(length)));
}

void read_beam(Model& m, const io::YamlNode& node) {
  const std::string name = read_safe_name(node["name"]);
  auto curve = read_geometry(node, [&](const io::YamlNode& g, const std::optional<io::YamlNode>& r) {
    return read_curve(g, r, model_size(m));
  });
  check_no_kinks({&curve.knots()}, node, "beam");
  const auto mat = node["material"];
  const double young = mat["young"].positive();
  const double poisson = mat["poisson"].in_range(-1.0, 0.5, true, true);
  const double density = mat.has("density") ? mat["density"].positive() : 0.0;
  mat.reject_unknown_keys();
  double radius = 0.0;
  const auto section = read_section(node["section"], young, poisson, radius);
  check_slender(node["section"], radius > 0 ? radius : std::sqrt(section.area / std::numbers::pi), curve_length(curve));
  Eigen::Vector3d director = Eigen::Vector3d::Zero();
  if (auto d = node.optional("director")) {
    director = d->as_vector3();
    if (director.norm() == 0.0) d->fail("a non-zero vector");
    check_director(curve, director, *d);
  }
  const int degree = curve.degree();
  auto body = [&] {
    try {
      return BeamBody(name, std::move(curve), section, director);
    } catch (const InputError& e) {
      node["geometry"].fail_message(e.what());
    }
  }();
  body.section_radius = radius;
  body.density = density;
  if (auto share = node.optional("symmetry_share")) body.share = share->in_range(0.0, 1.0, true, false);
  if (auto g = node.optional("gauss_points")) body.gauss_points = read_gauss_points(*g, degree);
  node.reject_unknown_keys();
  m.add_beam(std::move(body));
  check_fits(model_size(m), node["geometry"]);
}

template <class F>
void for_each_entry(const std::optional<io::YamlNode>& list, F&& f) {
  if (!list) return;
  if (!list->is_sequence()) list->fail("a list");
  for (std::size_t i = 0; i < list->size(); ++i) f(list->at(i));
}

// Checks steps.stop.column against the quantities the run reports.
void check_stop_column(const RunSettings& run, const Model& m, const io::YamlNode& root) {
  if (run.stop_column.empty()) return;
  std::string known;
  for (const auto& o : model::observables(m)) {
    if (o.name == run.stop_column) return;
    known += (known.empty() ? "" : ", ") + o.name;
  }
  root["steps"]["stop"]["column"].fail("a reported quantity (" + known + ")");
}

// Reads the constraints, recording which entry added which of the model's constraints.
ConstraintOrigins read_constraints(Model& m, const io::YamlNode& root) {
  ConstraintOrigins origins;
  for_each_entry(root.optional("constraints"), [&](const io::YamlNode& n) {
    origins.first.push_back(static_cast<std::size_t>(m.constraints.num_added()));
    origins.entries.push_back(n);
    read_constraint(m, n);
  });
  return origins;
}

}  // namespace

Case read_case(const std::string& path, const solve::Distribution* distribution) {
  // Read once: the run never reads the file again.
  return read_case_text(io::read_text_limited(path), path, std::filesystem::path(path).stem().string(), distribution);
}

Case read_case_text(std::string text, const std::string& path, const std::string& name,
                    const solve::Distribution* distribution) {
  Case c;
  c.text = std::move(text);
  const auto root = io::YamlNode::load_string(c.text, path);
  if (!root.is_map()) root.fail("a map with the keys shells, beams, constraints, loads, steps, ...");
  c.path = path;
  c.name = name;
  c.model = std::make_unique<Model>();
  Model& m = *c.model;
  m.title = root.get("title", c.name);
  if (auto f = root.optional("functions")) read_functions(m, *f);
  for_each_entry(root.optional("shells"), [&](const io::YamlNode& n) {
    read_shell(m, n);
    c.body_origins[m.shells.back().name()] = {n.path(), n.line()};
  });
  for_each_entry(root.optional("beams"), [&](const io::YamlNode& n) {
    read_beam(m, n);
    c.body_origins[m.beams.back().name()] = {n.path(), n.line()};
  });
  if (m.shells.empty() && m.beams.empty()) root.fail_message("the case defines no body: add 'shells' or 'beams'");
  check_output_names(m, root);
  const ConstraintOrigins origins = read_constraints(m, root);
  for_each_entry(root.optional("loads"), [&](const io::YamlNode& n) { read_load(m, n); });
  for_each_entry(root.optional("interactions"), [&](const io::YamlNode& n) { read_interaction(m, n); });
  check_output_names(m, root);
  for_each_entry(root.optional("monitors"), [&](const io::YamlNode& n) { read_monitor(m, n); });
  check_monitor_names(m, root);
  read_steps(c.run, root.optional("steps"));
  {  // the whole model's memory on the solver path it will take
    ModelSize size = model_size(m);
    // The distributed path has no low-rank correction: an unsymmetric tangent is an LU there.
    const int skew_rows = m.skew_rows();
    set_solver_path(size, c.run.linear_solver, distribution && skew_rows != 0 ? -1 : skew_rows);
    check_fits(size, root.has("steps") ? root["steps"] : root);
    c.memory_estimate = {size.peak_bytes(machine_memory()), size.path};
    // The limit is the sequential MUMPS's; the parallel one (distributed runs) has none.
    if (!distribution) check_low_rank(size, c.run.linear_solver, root.has("steps") ? root["steps"] : root);
  }
  check_stop_column(c.run, m, root);
  const bool dynamic = method_entry(c.run.method).traits.dynamic;
  if (dynamic) {
    m.inertia = true;
    for (const auto& s : m.shells)
      if (!(s.density > 0)) root.fail_message("a dynamic run needs every body's material density: shell '" + s.name() + "' has none");
    for (const auto& b : m.beams)
      if (!(b.density > 0)) root.fail_message("a dynamic run needs every body's material density: beam '" + b.name() + "' has none");
  }
  read_output(c.output, root.optional("output"), c.name);
  if (c.output.vtk && c.output.sampled)
    for (auto& b : m.beams) b.set_output_samples(c.output.samples);
  root.reject_unknown_keys();
  m.set_distribution(distribution);
  try {
    m.finalize();
  } catch (const solve::ConstraintError& e) {
    throw explain_constraint_error(e, m, origins, path);
  } catch (const InputError& e) {
    throw InputError(path + ": constraints: " + e.what());
  }
  if (!dynamic) check_free_bodies(m, root);  // inertia holds a free body in time
  return c;
}

}  // namespace fibrane::casefile
