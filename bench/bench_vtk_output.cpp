// What a step's VTK output of a case's shells costs, on one thread and on the run's threads: the sampled
// mesh with its section forces (output::shell_vtu), the exact Bezier mesh (output::shell_bezier_vtu), and
// each one's document, whose arrays are zlib-compressed in 32 KiB blocks (io::vtu_document). Nothing is
// written to disk. The state is the undeformed one, or a run's checkpoint (--state DIR: the output directory
// of an unfinished run of the same case), whose section forces compress as a run's do.
//   bench_vtk_output CASE.yaml [--threads N] [--replace FROM TO]... [--samples S] [--rounds R] [--state DIR]
// (S: sampling points per element edge, by default the case's output.samples)
#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <string>

#include "case/case_reader.hpp"
#include "bench_state.hpp"
#include "case_edit.hpp"
#include "output/body_vtk.hpp"
#include "run/process_environment.hpp"

namespace {

using Clock = std::chrono::steady_clock;

// The best wall time of `rounds` calls, in seconds.
double best_of(int rounds, const std::function<void()>& f) {
  double best = 1e300;
  for (int r = 0; r < rounds; ++r) {
    const auto t0 = Clock::now();
    f();
    best = std::min(best, std::chrono::duration<double>(Clock::now() - t0).count());
  }
  return best;
}

// One shell's four parts on the current OpenMP thread count; bytes: the two documents' sizes.
struct ShellOutputTimes {
  double sampled = 0, sampled_document = 0, bezier = 0, bezier_document = 0;
  std::size_t bytes = 0;
};

ShellOutputTimes time_shell(const fibrane::model::Model& m, const fibrane::model::ShellBody& s, int samples,
                            int rounds) {
  ShellOutputTimes t;
  fibrane::io::VtuMesh sampled, bezier;
  t.sampled = best_of(rounds, [&] { sampled = fibrane::output::shell_vtu(m, s, samples); });
  t.bezier = best_of(rounds, [&] { bezier = fibrane::output::shell_bezier_vtu(m, s); });
  std::string document;
  t.sampled_document = best_of(rounds, [&] { document = fibrane::io::vtu_document(sampled); });
  t.bytes = document.size();
  t.bezier_document = best_of(rounds, [&] { document = fibrane::io::vtu_document(bezier); });
  t.bytes += document.size();
  return t;
}

int run_bench(int argc, char** argv) {
  fibrane::run::configure_process_environment(argc, argv);  // the environment of `fibrane run`
  const char* usage =
      "usage: bench_vtk_output CASE.yaml [--threads N] [--replace FROM TO]... [--samples S] [--rounds R] "
      "[--state DIR]\n  a step's VTK output of the case's shells, on one thread and on N\n";
  int samples = 0, rounds = 3, code = 0;  // samples 0: the case's
  std::string state;
  const auto path = case_arguments(argc, argv, usage, [&](const std::string& a, int& i) {
    if (i + 1 >= argc) return false;
    if (a == "--samples") samples = std::max(1, std::stoi(argv[++i]));
    else if (a == "--rounds") rounds = std::max(1, std::stoi(argv[++i]));
    else if (a == "--state") state = argv[++i];
    else return false;
    return true;
  }, code);
  if (!path) return code;
  auto c = fibrane::casefile::read_case(*path);
  auto& m = *c.model;
  if (samples == 0) samples = c.output.samples;
  evaluate_at_state(c, state, false);
  const int threads = omp_get_max_threads();
  fmt::print("case {}: {} samples per element edge, best of {} rounds, wall seconds\n", argv[1], samples, rounds);
  fmt::print("| shell | threads | sampled mesh | its document | Bezier mesh | its document | all | documents' bytes |\n");
  fmt::print("|---|---|---|---|---|---|---|---|\n");
  for (const auto& s : m.shells)
    for (const int n : {1, threads}) {
      omp_set_num_threads(n);
      const ShellOutputTimes t = time_shell(m, s, samples, rounds);
      fmt::print("| {} | {} | {:.3f} | {:.3f} | {:.3f} | {:.3f} | {:.3f} | {} |\n", s.name(), n, t.sampled,
                 t.sampled_document, t.bezier, t.bezier_document,
                 t.sampled + t.sampled_document + t.bezier + t.bezier_document, t.bytes);
      if (threads == 1) break;
    }
  omp_set_num_threads(threads);
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return guarded_main(argc, argv, run_bench); }
