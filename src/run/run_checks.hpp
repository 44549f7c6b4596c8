#pragma once
// Checks made after a case has been read and before its run computes or writes anything; each failure is
// bad input (fibrane::InputError, exit code 2) naming the case file and what to change.
#include <string>

#include "case/case.hpp"

namespace fibrane::run {

// The output directory must be a directory (or creatable as one: its nearest existing ancestor is a
// directory) and writable; the check creates and removes the first directory the run would create, or a
// file in an existing one. `origin` names where the directory was given (-o, --restart, output.directory).
void check_output_directory(const casefile::Case& c, const std::string& directory, const std::string& origin);

// The model must be finite in its reference state: residual and tangent at t_start (no displacement) and
// the external loads at t_start and t_end. A non-finite value means that material constants, sizes or
// loads are too large for double precision; the message names the first body where it appears, with the
// line of its entry in the case file.
void check_finite_model(casefile::Case& c);

}  // namespace fibrane::run
