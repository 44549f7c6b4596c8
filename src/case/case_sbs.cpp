#include "case/case_sbs.hpp"

#include <stdexcept>

#include <fmt/format.h>

#include "case/case_laws.hpp"
#include "model/coupling.hpp"

namespace fibrane::casefile {

namespace {

struct SoftMinimum {
  double width = 0, below = 0, below_on_failure = 0;  // width 0: off
};

// below_on_failure's default as a multiple of below: on the 278 k full membrane the points whose closest
// points jumped in the failed attempt had relative curvature 0.12-0.18 at the last converged state, where
// below is 0.05 (docs/interaction.md, section 7).
constexpr double kBelowOnFailure = 4.0;

SoftMinimum read_soft_minimum(const io::YamlNode& entry, interaction::Formulation formulation,
                              const laws::InteractionLaw& law) {
  SoftMinimum out;
  auto soft = entry.optional("soft_minimum");
  if (!soft) return out;
  if (formulation != interaction::Formulation::RF2)
    soft->fail_message("the soft minimum is implemented for the RF2 formulation only");
  out.width = (*soft)["width"].in_range(0.0, 5e-3, true, false);
  out.below = soft->has("below") ? (*soft)["below"].positive() : 0.05;
  out.below_on_failure = kBelowOnFailure * out.below;
  if (auto on_failure = soft->optional("below_on_failure")) {
    out.below_on_failure = on_failure->as_double();
    if (!(out.below_on_failure >= out.below))
      on_failure->fail(fmt::format("a relative curvature no smaller than below ({:g})", out.below));
  }
  soft->reject_unknown_keys();
  try {
    law.equilibrium_distance(1.0);
  } catch (const std::runtime_error& e) {
    soft->fail_message(std::string("the soft minimum's width is relative to the law's equilibrium distance: ") + e.what());
  }
  return out;
}

}  // namespace

std::unique_ptr<model::Interaction> make_sbs(const InteractionRequest& request) {
  const io::YamlNode& node = request.entry;
  const bool beam_first = request.a.beam != nullptr;
  const InteractionBody& beam = beam_first ? request.a : request.b;
  const InteractionBody& shell = beam_first ? request.b : request.a;
  if (!beam.beam || !shell.shell)
    (beam.beam ? beam.at : shell.at)
        .fail_message("the SBS coupling acts between a beam and a shell; '" + request.a.name() + "' and '" +
                      request.b.name() + "' are not");
  if (beam.beam->section_radius <= 0.0)
    beam.at.fail_message("beam '" + beam.name() + "' needs a circular section (section: {circle: {radius: R}}): the "
                         "disk-plate law integrates over a disk");
  const std::string f = node.get("formulation", std::string("RF2"));
  if (auto fn = node.optional("formulation")) fn->as_choice({"FF", "RF1", "RF2"});
  const auto formulation = f == "FF" ? interaction::Formulation::FF
                           : f == "RF1" ? interaction::Formulation::RF1 : interaction::Formulation::RF2;
  auto ff_tangent = interaction::FfTangent::exact;
  if (auto t = node.optional("ff_tangent")) {
    if (formulation != interaction::Formulation::FF)
      t->fail_message("ff_tangent chooses the tangent of the FF formulation only; this interaction uses " + f);
    ff_tangent = t->as_choice({"exact", "rf1"}) == "rf1" ? interaction::FfTangent::rf1 : interaction::FfTangent::exact;
  }
  auto law = read_interaction_law(node, {beam.beam->section_radius, shell.shell->section.thickness});
  const SoftMinimum soft = read_soft_minimum(node, formulation, *law);
  auto coupling = std::make_unique<model::Coupling>(request.name, std::move(law), formulation, ff_tangent,
                                                    *beam.beam, *shell.shell);
  if (soft.width > 0) coupling->enable_soft_minimum(soft.width, soft.below, soft.below_on_failure);
  return coupling;
}

}  // namespace fibrane::casefile
