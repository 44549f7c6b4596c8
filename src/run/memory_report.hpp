#pragma once
// summary.json's "memory" of a run: the case's estimate beside what the run took.
#include "case/case.hpp"
#include "common/memory_watch.hpp"
#include "io/json.hpp"
#include "linalg/distribution.hpp"

namespace fibrane::run {

// {estimated_bytes, solver_path, peak_bytes (the peak resident set, getrusage), peak_allocated_bytes
// (InUsePeak's)}; a distributed run's peaks are sums over its processes, beside `processes` and each
// peak's largest process. Collective in a distributed run (d non-null).
io::JsonValue memory_json(const casefile::Case::MemoryEstimate& estimate, InUsePeak& in_use,
                          const solve::Distribution* d);

}  // namespace fibrane::run
