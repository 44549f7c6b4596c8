#pragma once
// Interaction laws in case files and on the command line: a map {model: NAME, parameters...} naming any
// law of laws::law_registry(), or the short form `lennard_jones: {...}` of an interaction.
#include <memory>

#include "io/yaml_input.hpp"
#include "laws/interaction_law.hpp"

namespace fibrane::casefile {

// `law` is a map {model: NAME, ...}: the registry's law NAME built from the other keys.
std::shared_ptr<const laws::InteractionLaw> make_law(const io::YamlNode& law, const laws::LawGeometry& g);
// The law of an interaction entry: its `lennard_jones: {...}` or its `law: {model: ...}` (exactly one).
std::shared_ptr<const laws::InteractionLaw> read_interaction_law(const io::YamlNode& interaction,
                                                                 const laws::LawGeometry& g);

}  // namespace fibrane::casefile
