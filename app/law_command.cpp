// `fibrane law KIND ...`: evaluate one interaction law and print a JSON object (docs/laws.md).
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

#include "case/case_laws.hpp"
#include "commands.hpp"
#include "common/error.hpp"
#include "io/yaml_input.hpp"
#include "laws/law_registry.hpp"
#include "laws/disk_plate.hpp"
#include "laws/disk_sphere.hpp"
#include "laws/lennard_jones.hpp"

namespace fibrane::app {
namespace {

struct LawOptions {
  double m = 6, radius = 1, thickness = 1, distance = 0, cosine = 1, epsilon = 1, sigma = 1;
  double density_beam = 1, density_shell = 1, strength = 1, sphere_radius = 1;
  std::string law;  // a YAML flow map {model: NAME, ...} of the law registry
};

std::string number(double x) {
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.17g", x);
  return buffer;
}

// Prints the law's value and derivatives as one JSON line; a non-finite number is a failure of the
// evaluation (exit code 1), never printed.
void print_json(const std::string& law, const laws::LawValue& v, const std::string& extra = "") {
  const std::pair<const char*, double> values[] = {{"value", v.value}, {"d_distance", v.d_d}, {"d_cos", v.d_c},
                                                   {"d2_distance", v.d_dd}, {"d2_cos", v.d_cc},
                                                   {"d2_distance_cos", v.d_dc}, {"reduced_d_cos", v.reduced_c},
                                                   {"reduced_d2_distance_cos", v.reduced_dc}};
  for (const auto& [name, x] : values)
    if (!std::isfinite(x))
      throw std::runtime_error("the " + law + " law gave " + (std::isnan(x) ? "no number" : "an infinite number") +
                               " for " + name + " at these arguments: outside the range where it can be evaluated "
                               "in double precision");
  std::cout << "{\"law\": \"" << law << "\"" << extra << ", \"value\": " << number(v.value)
            << ", \"d_distance\": " << number(v.d_d) << ", \"d_cos\": " << number(v.d_c)
            << ", \"d2_distance\": " << number(v.d_dd) << ", \"d2_cos\": " << number(v.d_cc)
            << ", \"d2_distance_cos\": " << number(v.d_dc)
            << ", \"reduced_d_cos\": " << number(v.reduced_c)
            << ", \"reduced_d2_distance_cos\": " << number(v.reduced_dc) << "}\n";
}

void require(bool ok, const std::string& message) {
  if (!ok) throw InputError(message);
}

// Every numeric option must be a finite number (CLI11 accepts 'nan' and 'inf').
void require_finite(const LawOptions& o) {
  const std::pair<const char*, double> options[] = {
      {"--m", o.m}, {"--radius", o.radius}, {"--thickness", o.thickness}, {"--distance", o.distance},
      {"--cos", o.cosine}, {"--epsilon", o.epsilon}, {"--sigma", o.sigma}, {"--density-beam", o.density_beam},
      {"--density-shell", o.density_shell}, {"--strength", o.strength}, {"--sphere-radius", o.sphere_radius}};
  for (const auto& [name, x] : options) require(std::isfinite(x), std::string(name) + " must be a finite number");
}

void check_disk(const LawOptions& o, double surface_offset) {
  require(std::isfinite(o.radius) && o.radius > 0, "--radius must be positive");
  require(o.cosine >= 0 && o.cosine <= 1, "--cos must lie in [0, 1]");
  require(std::isfinite(o.distance) && o.distance - surface_offset > o.cosine * o.radius,
          "--distance must exceed cos * radius" +
              std::string(surface_offset > 0 ? " + thickness / 2" : "") + " (positive gap)");
}

// Runs the evaluation, turning a law's domain error into bad input (exit code 2).
template <class F>
void run(F evaluate) {
  try {
    evaluate();
  } catch (const std::domain_error& e) {
    throw InputError(e.what());
  }
}

// Prints an interaction law's value and derivatives at (--distance, --cos), and its equilibrium distance
// where it has one.
void evaluate_registry_law(const laws::InteractionLaw& law, const LawOptions& o) {
  require(o.cosine >= 0 && o.cosine <= 1, "--cos must lie in [0, 1]");
  const double contact = law.contact_distance(o.cosine);
  require(std::isfinite(o.distance) && o.distance > contact,
          "--distance must exceed cos * radius + thickness / 2 = " + number(contact) + " (positive gap)");
  std::string extra;
  try {
    extra = ", \"equilibrium_distance\": " + number(law.equilibrium_distance(o.cosine));
  } catch (const std::runtime_error&) {  // a purely attractive or repulsive law has none
  }
  run([&] { print_json(law.name(), law.evaluate(o.distance, o.cosine), extra); });
}

// `fibrane law disk-halfspace` and `fibrane law disk-plate`: the paper's closed-form disk laws.
void add_disk_laws(CLI::App& law, const std::shared_ptr<LawOptions>& o) {
  auto* half = law.add_subcommand("disk-halfspace", "Disk-half-space law, Eq. (55), any m > 3");
  half->add_option("--m", o->m, "Exponent m > 3")->required();
  half->add_option("--radius", o->radius, "Disk radius R")->required();
  half->add_option("--distance", o->distance, "Disk centre to surface distance d")->required();
  half->add_option("--cos", o->cosine, "cos(alpha) in [0, 1]")->required();
  half->callback([o]() {
    require_finite(*o);
    check_disk(*o, 0.0);
    run([&] { print_json("disk-halfspace", laws::DiskHalfSpace(o->m, o->radius).evaluate(o->distance, o->cosine)); });
  });

  auto* plate = law.add_subcommand("disk-plate", "Disk-plate law, Eq. (56), any m > 3");
  plate->add_option("--m", o->m, "Exponent m > 3")->required();
  plate->add_option("--radius", o->radius, "Disk radius R")->required();
  plate->add_option("--thickness", o->thickness, "Plate thickness h")->required();
  plate->add_option("--distance", o->distance, "Disk centre to mid-plane distance d")->required();
  plate->add_option("--cos", o->cosine, "cos(alpha) in [0, 1]")->required();
  plate->callback([o]() {
    require_finite(*o);
    require(o->thickness > 0, "--thickness must be positive");
    check_disk(*o, 0.5 * o->thickness);
    run([&] {
      print_json("disk-plate", laws::DiskPlate(o->m, o->radius, o->thickness).evaluate(o->distance, o->cosine));
    });
  });
}

// `fibrane law lj-disk-plate` and `fibrane law interaction`: laws of the registry, as case files name them.
void add_registry_laws(CLI::App& law, const std::shared_ptr<LawOptions>& o) {
  auto* lj = law.add_subcommand("lj-disk-plate", "Lennard-Jones disk-plate potential per unit length");
  lj->add_option("--radius", o->radius, "Disk radius R")->required();
  lj->add_option("--thickness", o->thickness, "Plate thickness h")->required();
  lj->add_option("--distance", o->distance, "Disk centre to mid-plane distance d")->required();
  lj->add_option("--cos", o->cosine, "cos(alpha) in [0, 1]")->required();
  lj->add_option("--epsilon", o->epsilon, "LJ well depth epsilon")->required();
  lj->add_option("--sigma", o->sigma, "LJ length sigma")->required();
  lj->add_option("--density-beam", o->density_beam, "Beam particle density (default 1)");
  lj->add_option("--density-shell", o->density_shell, "Shell particle density (default 1)");
  lj->add_option("--strength", o->strength, "Interaction-strength factor (default 1)");
  lj->callback([o]() {
    require_finite(*o);
    const MapParameters p("fibrane law lj-disk-plate", {{"epsilon", o->epsilon}, {"sigma", o->sigma},
                                                         {"density_beam", o->density_beam},
                                                         {"density_shell", o->density_shell},
                                                         {"strength", o->strength}});
    evaluate_registry_law(*laws::law_registry().make("lennard_jones", p, {o->radius, o->thickness}), *o);
  });

  auto* any = law.add_subcommand("interaction", "Any interaction law of the registry (case files' law: {model: ...})");
  any->add_option("--law", o->law, "The law as a YAML map, e.g. '{model: inverse_power, exponent: 9, coefficient: -1}'")
      ->required();
  any->add_option("--radius", o->radius, "Disk radius R")->required();
  any->add_option("--thickness", o->thickness, "Plate thickness h")->required();
  any->add_option("--distance", o->distance, "Disk centre to mid-plane distance d")->required();
  any->add_option("--cos", o->cosine, "cos(alpha) in [0, 1]")->required();
  any->callback([o]() {
    require_finite(*o);
    const io::YamlNode spec = io::YamlNode::load_string(o->law, "--law");
    evaluate_registry_law(*casefile::make_law(spec, {o->radius, o->thickness}), *o);
  });
  std::string known;
  for (const auto& e : laws::law_registry().entries()) known += "\n  " + e.name + ": " + e.summary;
  any->footer("Laws:" + known);
}

// `fibrane law disk-sphere`: the disk-sphere law of Appendix F.
void add_sphere_law(CLI::App& law, const std::shared_ptr<LawOptions>& o) {
  auto* sphere = law.add_subcommand("disk-sphere", "Disk-sphere law (App. F, corrected), m = 6");
  sphere->add_option("--radius", o->radius, "Disk radius R_D")->required();
  sphere->add_option("--sphere-radius", o->sphere_radius, "Sphere radius R_S")->required();
  sphere->add_option("--distance", o->distance, "Distance between the centres")->required();
  sphere->callback([o]() {
    require_finite(*o);
    require(o->radius > 0 && o->sphere_radius > 0, "--radius and --sphere-radius must be positive");
    require(o->distance > o->radius + o->sphere_radius, "--distance must exceed radius + sphere-radius");
    run([&] {
      // Perpendicular orientation only: the angle derivatives are reported as zero.
      const laws::ScalarJet j = laws::disk_sphere(o->radius, o->sphere_radius, o->distance);
      laws::LawValue v;
      v.value = j.value;
      v.d_d = j.d1;
      v.d_dd = j.d2;
      print_json("disk-sphere", v);
    });
  });
}

}  // namespace

void register_law_command(CLI::App& app) {
  auto o = std::make_shared<LawOptions>();
  auto* law = app.add_subcommand("law", "Evaluate one interaction law; prints JSON");
  law->require_subcommand(1);
  add_disk_laws(*law, o);
  add_registry_laws(*law, o);
  add_sphere_law(*law, o);
}

}  // namespace fibrane::app
