#include "case/case_beam_beam.hpp"

#include "io/yaml_parameters.hpp"
#include "laws/section_law_registry.hpp"
#include "model/beam_beam.hpp"

namespace fibrane::casefile {

namespace {

// A fiber of the interaction: a beam with a circular section.
const model::BeamBody& fiber(const InteractionBody& body) {
  if (!body.beam)
    body.at.fail_message("the beam-beam interaction acts between beams; '" + body.name() + "' is a shell");
  if (body.beam->section_radius <= 0.0)
    body.at.fail_message("beam '" + body.name() + "' needs a circular section (section: {circle: {radius: R}}): the "
                         "section-beam law integrates over a disk");
  return *body.beam;
}

}  // namespace

std::unique_ptr<model::Interaction> make_beam_beam(const InteractionRequest& request) {
  const io::YamlNode& node = request.entry;
  const model::BeamBody& a = fiber(request.a);
  const model::BeamBody& b = fiber(request.b);
  const bool self = &a == &b;
  double exclusion = 0;
  if (self) {
    if (!node.has("exclusion"))
      node.fail_message("a beam interacting with itself needs 'exclusion': the reference arc length around a "
                        "section within which it does not interact with its own fiber (a few section diameters)");
    exclusion = node["exclusion"].positive();
  } else if (auto e = node.optional("exclusion")) {
    e->fail_message("'exclusion' applies to a beam interacting with itself; '" + a.name() + "' and '" + b.name() +
                    "' are two beams");
  }
  const auto law = node["law"];
  if (!law.is_map()) law.fail("a map {model: NAME, parameters...} with NAME one of " +
                              laws::section_law_registry().names_text());
  const auto model_node = law["model"];
  const std::string name = model_node.as_string();
  if (!laws::section_law_registry().find(name)) model_node.fail("one of " + laws::section_law_registry().names_text());
  auto section_law = laws::section_law_registry().make(name, io::YamlParameters(law, {"model"}),
                                                       laws::SectionGeometry{a.section_radius, b.section_radius});
  // NaN (a law without an equilibrium gap, and no contact_gap): no contact length.
  double contact_gap = model::BeamBeamInteraction::default_contact_gap(*section_law);
  if (auto c = node.optional("contact_gap")) contact_gap = c->positive();
  double end_taper = 0;
  if (auto t = node.optional("end_taper")) end_taper = t->in_range(0.0, 0.5, false, true);
  return std::make_unique<model::BeamBeamInteraction>(request.name, std::move(section_law), a, b, exclusion,
                                                      contact_gap, end_taper);
}

}  // namespace fibrane::casefile
