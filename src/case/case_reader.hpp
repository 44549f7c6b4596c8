#pragma once
// Reads a YAML case file (docs/case-format.md) into a Case. Bad input throws fibrane::InputError naming
// the file, line, key and what was expected; nothing is written before the whole case has been read and
// checked.
#include <string>

#include "case/case.hpp"
#include "linalg/forward.hpp"

namespace fibrane::casefile {

// With a distribution (a distributed run; it must outlive the case) the model shares its elements among
// the processes (model::Model::set_distribution).
Case read_case(const std::string& path, const solve::Distribution* distribution = nullptr);

// The same from case text already in memory (the Python module's cases): `source` stands in for the file
// name in messages and summary.json, `name` for its stem (the default title and output directory).
Case read_case_text(std::string text, const std::string& source, const std::string& name,
                    const solve::Distribution* distribution = nullptr);

}  // namespace fibrane::casefile
