#include "run/memory_report.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <vector>

namespace fibrane::run {

io::JsonValue memory_json(const casefile::Case::MemoryEstimate& estimate, InUsePeak& in_use,
                          const solve::Distribution* d) {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const int processes = d ? d->size() : 1;
  const int rank = d ? d->rank() : 0;
  std::vector<double> resident(processes, 0.0), allocated(processes, 0.0);
  resident[rank] = 1024.0 * static_cast<double>(usage.ru_maxrss);
  allocated[rank] = static_cast<double>(in_use.peak());
  if (d) {
    d->sum(resident);
    d->sum(allocated);
  }
  const auto bytes = [](double b) { return static_cast<std::int64_t>(std::llround(b)); };
  const auto sum = [&](const std::vector<double>& v) { return bytes(std::accumulate(v.begin(), v.end(), 0.0)); };
  const auto largest = [&](const std::vector<double>& v) { return bytes(*std::max_element(v.begin(), v.end())); };
  io::JsonValue j = io::JsonValue::object();
  j.set("estimated_bytes", bytes(estimate.bytes)).set("solver_path", estimate.path);
  j.set("peak_bytes", sum(resident)).set("peak_allocated_bytes", sum(allocated));
  if (d)
    j.set("processes", processes)
        .set("largest_process_peak_bytes", largest(resident))
        .set("largest_process_peak_allocated_bytes", largest(allocated));
  return j;
}

}  // namespace fibrane::run
