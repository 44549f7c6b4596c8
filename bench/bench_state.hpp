#pragma once
// The state a bench program evaluates a case's model at: t = 0 undeformed, or the checkpoint of an unfinished
// run of the same case (`--state DIR`, the run's output directory).
#include <fmt/format.h>

#include <string>

#include "case/case.hpp"
#include "run/checkpoint.hpp"

// Evaluates c's model (with its tangent where asked) at t = 0, or at the checkpoint in `state` (not empty),
// whose step it names on stdout. A checkpoint that is not the case's, or a completed run's, is an InputError.
inline void evaluate_at_state(fibrane::casefile::Case& c, const std::string& state, bool with_tangent) {
  auto& m = *c.model;
  if (state.empty()) {
    m.evaluate(m.initial_unknowns(), 0.0, with_tangent);
    return;
  }
  const fibrane::run::RunCheckpoint checkpoint = fibrane::run::read_checkpoint(state, c);
  m.restore_state(checkpoint.model);
  m.evaluate(checkpoint.q, checkpoint.t, with_tangent);
  fmt::print("state: step {} at t = {} from {}\n", checkpoint.step, checkpoint.t, state);
}
