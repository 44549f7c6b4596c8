#pragma once
// Running the parts of a factorisation side by side on threads (the split Cholesky's domains and fronts,
// cholmod_split.hpp).
#include <algorithm>
#include <atomic>
#include <functional>
#include <vector>

#include "linalg/linear_solver.hpp"

namespace fibrane::solve {

// The time of `work` items on `threads` threads, each item to the thread that is free first, the largest
// items first (what a dynamic schedule of the items in that order gives).
inline double makespan(std::vector<double> work, int threads) {
  std::sort(work.begin(), work.end(), std::greater<>());
  std::vector<double> load(static_cast<std::size_t>(std::max(threads, 1)), 0.0);
  for (const double w : work) *std::min_element(load.begin(), load.end()) += w;
  return *std::max_element(load.begin(), load.end());
}

// Runs body(k) for every k of `items`, side by side on up to `threads` threads with one BLAS thread each
// where there are at least half as many items as threads, one after the other with the configured BLAS
// threads where there are fewer (a few large dense fronts); false where a body returned false. Each item
// goes to the thread that is free first, in the order given.
// `share` true: once a single item is left unfinished, it runs alone, and its further BLAS calls get the
// configured threads back (OpenBLAS's thread count is global, so it is raised only when one body alone
// calls the BLAS). When that happens depends on timing, so a body that shares gives last bits that vary
// from run to run wherever its BLAS calls' results depend on the thread count (OpenBLAS's dgemv and dtrsv,
// and a dense front's dpotrf, dtrsm and dsyrk: tests/solve/test_side_by_side.cpp).
template <class Body>
bool side_by_side(const std::vector<int>& items, int threads, Body&& body, bool share = false) {
  const int n = static_cast<int>(items.size());
  if (2 * n < threads || n == 1) {
    for (const int k : items)
      if (!body(k)) return false;
    return true;
  }
  int failed = 0;
  std::atomic<int> next{0}, unfinished{n};
  BlasThreadsForFactor one_blas_thread(0);
#pragma omp parallel num_threads(std::min(threads, n)) reduction(+ : failed)
  for (int i = next++; i < n; i = next++) {
    failed += body(items[static_cast<std::size_t>(i)]) ? 0 : 1;
    if (--unfinished == 1 && share) one_blas_thread.restore();
  }
  return failed == 0;
}

}  // namespace fibrane::solve
