#pragma once
// The fiber-fiber interaction (model/beam_beam.hpp) as an interaction kind of the case format, beam_beam:
// its keys law ({model: NAME, ...} of laws::section_law_registry()) and, for a beam with itself,
// exclusion (the reference arc length around a section that its closest point may not lie in) and
// contact_gap (the gap of the contact length; default twice the law's equilibrium gap, required for a law
// without one) and end_taper (the fraction of the other fiber's length over which sections fade out
// towards its ends; default 0, none).
#include <memory>

#include "case/case_interactions.hpp"

namespace fibrane::casefile {

// The interaction of the request's two beams (the same beam twice: self-interaction); InputError located
// at the entry's keys.
std::unique_ptr<model::Interaction> make_beam_beam(const InteractionRequest& request);

}  // namespace fibrane::casefile
