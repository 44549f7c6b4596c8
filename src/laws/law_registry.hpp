#pragma once
// The interaction laws a case file (interactions[].law: {model: NAME, ...}) and `fibrane law` can name.
// Adding a law: a class implementing InteractionLaw in its own file, and one line in law_registry.cpp.
#include <memory>

#include "common/registry.hpp"
#include "laws/interaction_law.hpp"

namespace fibrane::laws {

using LawRegistry = Registry<std::shared_ptr<const InteractionLaw>, const LawGeometry&>;

// The registry of laws; mutable so that programs and tests may add their own.
LawRegistry& law_registry();

}  // namespace fibrane::laws
