#pragma once
// summary.json's "partition" of a distributed run: how its elements and unknowns are shared.
#include "io/json.hpp"
#include "linalg/partition.hpp"

namespace fibrane::run {

// {method, note (only when the graph partition fell back), processes, elements, owned_unknowns,
// element_weight (arrays with one entry per process), interface_unknowns, imbalance}.
io::JsonValue partition_json(const solve::ElementPartition& p);

}  // namespace fibrane::run
