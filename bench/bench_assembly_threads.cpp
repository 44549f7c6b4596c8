// How the threads share the assembly, for any case and mesh:
//   bench_assembly_threads CASE.yaml [--rounds R] [--threads N] [--replace FROM TO]...
// evaluates the model's residual and tangent (Model::evaluate with tangent) at a random deformed state
// (free unknowns uniform in +-1e-3), alternating the coloured assembly and the per-thread buffers
// (solve::SparseAssembler::Strategy) for R rounds, and prints per evaluation the median wall and CPU time
// (all threads) of each, the colours, and the buffers' size. One process, one model: the two strategies
// meet the same machine load round by round.
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <fmt/format.h>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "case/case_reader.hpp"
#include "case_edit.hpp"

namespace {

double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace

int run_bench(int argc, char** argv) {
  const char* usage =
      "usage: bench_assembly_threads CASE.yaml [--rounds R] [--threads N] [--replace FROM TO]...\n"
      "  alternates the coloured assembly and the per-thread buffers, R rounds (default 5)\n";
  int rounds = 5, code = 0;
  const auto path = case_arguments(argc, argv, usage, [&](const std::string& a, int& i) {
    if (a != "--rounds" || i + 1 >= argc) return false;
    rounds = std::stoi(argv[++i]);
    return true;
  }, code);
  if (!path) return code;
  auto c = fibrane::casefile::read_case(*path);
  auto& m = *c.model;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uniform(-1e-3, 1e-3);
  const Eigen::VectorXd q = Eigen::VectorXd::NullaryExpr(m.size(), [&] { return uniform(rng); });
  using Strategy = fibrane::solve::SparseAssembler::Strategy;
  const Strategy strategies[2] = {Strategy::Colours, Strategy::ThreadBuffers};
  const char* names[2] = {"colours", "buffers"};
  std::vector<double> wall[2], cpu[2];
  for (int r = 0; r <= rounds; ++r)  // round 0 warms up (first-touch of the matrix and the buffers)
    for (int s = 0; s < 2; ++s) {
      m.set_assembly(strategies[s]);
      const auto t0 = std::chrono::steady_clock::now();
      const double c0 = cpu_seconds();
      m.evaluate(q, 0.01, true);
      if (r == 0) continue;
      cpu[s].push_back(cpu_seconds() - c0);
      wall[s].push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
  fmt::print("case {}: {} free unknowns, {} matrix non-zeros, {} colours, {} threads, {} rounds\n", c.path, m.size(),
             m.tangent().nonZeros(), m.assembly_colours(), omp_get_max_threads(), rounds);
  fmt::print("| assembly | wall per evaluation | CPU per evaluation |\n|---|---|---|\n");
  for (int s = 0; s < 2; ++s)
    fmt::print("| {} | {:.0f} ms | {:.0f} ms |\n", names[s], 1e3 * median(wall[s]), 1e3 * median(cpu[s]));
  fmt::print("buffers held after the buffered rounds: {:.1f} MiB\n", m.assembly_buffer_bytes() / 1048576.0);
  return 0;
}

int main(int argc, char** argv) { return guarded_main(argc, argv, run_bench); }
