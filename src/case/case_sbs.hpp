#pragma once
// The beam-shell SBS coupling (model/coupling.hpp) as an interaction kind of the case format: its keys
// formulation, ff_tangent, the law (lennard_jones: {...} or law: {model: ...}) and soft_minimum.
#include <memory>

#include "case/case_interactions.hpp"

namespace fibrane::casefile {

// The coupling of the request's beam and shell (in either order); InputError located at the entry's keys.
std::unique_ptr<model::Interaction> make_sbs(const InteractionRequest& request);

}  // namespace fibrane::casefile
