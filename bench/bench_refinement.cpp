// Cost of h-refinement of a shell patch: a rectangle raised to degree 4 and refined to N x 1 elements
// (C3, as the roll-up strip example; N up to the case-file maximum 65536 per direction). `one_pass` is
// NurbsSurface::refine (all knots of a direction at once, spline::insert_knots); `one_at_a_time` inserts
// the same knots with insert_knot, one Boehm insertion each, whose cost grows with N^2.
#include <benchmark/benchmark.h>

#include "spline/refinement.hpp"
#include "spline/shapes.hpp"
#include "spline/surface.hpp"

namespace {

using fibrane::spline::NurbsSurface;

NurbsSurface strip() {
  NurbsSurface s = fibrane::spline::make_rectangle({0, 0, 0}, {12, 0, 0}, {0, 1, 0});
  s.refine(1, 4, 3, 1);
  s.elevate_degree(0, 4 - s.degree(0));
  return s;
}

void one_pass(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const NurbsSurface coarse = strip();
  for (auto _ : state) {
    NurbsSurface s = coarse;
    s.refine(0, 4, 3, n);
    benchmark::DoNotOptimize(s.control_points().data());
  }
  state.SetComplexityN(n);
}
BENCHMARK(one_pass)->RangeMultiplier(4)->Range(1024, 65536)->Unit(benchmark::kMillisecond)->Complexity();

void one_at_a_time(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const NurbsSurface coarse = strip();
  for (auto _ : state) {
    NurbsSurface s = coarse;
    for (const auto& [u, times] : fibrane::spline::uniform_insertions(s.knots(0), 3, n)) s.insert_knot(0, u, times);
    benchmark::DoNotOptimize(s.control_points().data());
  }
  state.SetComplexityN(n);
}
BENCHMARK(one_at_a_time)->RangeMultiplier(2)->Range(512, 2048)->Unit(benchmark::kMillisecond)->Complexity();

}  // namespace

BENCHMARK_MAIN();
