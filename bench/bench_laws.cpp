// Cost of one Lennard-Jones disk-plate evaluation with all derivatives (target: < 200 ns), at
// typical beam-shell distances: near the equilibrium (difference form of Eq. 56) and far away (the
// stable thickness-quadrature form).
#include <benchmark/benchmark.h>

#include "laws/disk_plate.hpp"
#include "laws/lennard_jones.hpp"

namespace {

using fibrane::laws::LennardJonesDiskPlate;

void lj_evaluate(benchmark::State& state, double gap_over_sigma) {
  const LennardJonesDiskPlate lj{1.0, 0.01, 1.0, 0.1};
  double d = 1.0 + 0.05 + gap_over_sigma * 0.01, c = 0.95;
  for (auto _ : state) {
    benchmark::DoNotOptimize(lj.evaluate(d, c));
    d += 1e-12;  // vary the input so nothing is hoisted
  }
}
BENCHMARK_CAPTURE(lj_evaluate, near_equilibrium, 1.0);
BENCHMARK_CAPTURE(lj_evaluate, moderate_gap, 10.0);
BENCHMARK_CAPTURE(lj_evaluate, far_gap, 1000.0);               // (d - cR) / (h/2) = 200: difference form
BENCHMARK_CAPTURE(lj_evaluate, far_stable_form, 20000.0);      // (d - cR) / (h/2) = 4000: thickness quadrature

void geometric_plate_m6(benchmark::State& state) {
  const fibrane::laws::DiskPlate plate(6, 1.0, 0.1);
  double d = 1.06;
  for (auto _ : state) {
    benchmark::DoNotOptimize(plate.evaluate(d, 0.95));
    d += 1e-12;
  }
}
BENCHMARK(geometric_plate_m6);

}  // namespace

BENCHMARK_MAIN();
