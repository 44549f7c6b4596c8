#include "case/case_laws.hpp"

#include "io/yaml_parameters.hpp"
#include "laws/law_registry.hpp"

namespace fibrane::casefile {

std::shared_ptr<const laws::InteractionLaw> make_law(const io::YamlNode& law, const laws::LawGeometry& g) {
  if (!law.is_map()) law.fail("a map {model: NAME, parameters...}");
  const auto model = law["model"];
  const std::string name = model.as_string();
  if (!laws::law_registry().find(name)) model.fail("one of " + laws::law_registry().names_text());
  return laws::law_registry().make(name, io::YamlParameters(law, {"model"}), g);
}

std::shared_ptr<const laws::InteractionLaw> read_interaction_law(const io::YamlNode& node, const laws::LawGeometry& g) {
  const bool lj = node.has("lennard_jones"), general = node.has("law");
  if (lj == general)
    node.fail_message("give the interaction law either as 'lennard_jones: {...}' or as 'law: {model: ...}'");
  if (lj) return laws::law_registry().make("lennard_jones", io::YamlParameters(node["lennard_jones"]), g);
  return make_law(node["law"], g);
}

}  // namespace fibrane::casefile
