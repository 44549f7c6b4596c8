// Cost of one Kirchhoff-Love shell quadrature point (src/shell/kl_shell.hpp): energy + residual + tangent
// for elements of degree 2, 3, 4 (nen = 9, 16, 25), with the St. Venant-Kirchhoff section and (the
// *Material benchmarks) with the neo-Hookean materials of src/shell/material.hpp. The kernel's cost does not depend on the values, so
// the inputs are a jittered flat grid and random basis derivatives; the element vector and matrix are
// zeroed once per element in real assembly and are not re-zeroed here.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include "shell/kl_shell.hpp"
#include "shell/material.hpp"

namespace {

struct PointData {
  fibrane::shell::BasisDerivs R;
  Eigen::Matrix3Xd X, x;
};

PointData make_point(int nen) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  PointData d{fibrane::shell::BasisDerivs(6, nen), Eigen::Matrix3Xd(3, nen), Eigen::Matrix3Xd(3, nen)};
  const int side = static_cast<int>(std::lround(std::sqrt(nen)));
  for (int A = 0; A < nen; ++A) {
    for (int r = 0; r < 6; ++r) d.R(r, A) = u(rng);
    d.X.col(A) << A % side + 0.1 * u(rng), A / side + 0.1 * u(rng), 0.1 * u(rng);
    d.x.col(A) = d.X.col(A) + 0.05 * Eigen::Vector3d(u(rng), u(rng), u(rng));
  }
  return d;
}

void BM_ShellPointResidualTangent(benchmark::State& state) {
  const int nen = static_cast<int>(state.range(0));
  const PointData d = make_point(nen);
  const fibrane::shell::ShellSection section = fibrane::shell::ShellSection::svk(1.0e5, 0.3, 0.01);
  Eigen::VectorXd r = Eigen::VectorXd::Zero(3 * nen);
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(3 * nen, 3 * nen);
  double energy = 0.0;
  for (auto _ : state) {
    fibrane::shell::add_shell_point(section, d.R, d.X, d.x, 1e-3, &energy, &r, &k);
    benchmark::DoNotOptimize(k.data());
    benchmark::ClobberMemory();
  }
  state.counters["dofs"] = 3.0 * nen;
}
BENCHMARK(BM_ShellPointResidualTangent)->Arg(9)->Arg(16)->Arg(25)->Unit(benchmark::kMicrosecond);

void BM_ShellPointResidualOnly(benchmark::State& state) {
  const int nen = static_cast<int>(state.range(0));
  const PointData d = make_point(nen);
  const fibrane::shell::ShellSection section = fibrane::shell::ShellSection::svk(1.0e5, 0.3, 0.01);
  Eigen::VectorXd r = Eigen::VectorXd::Zero(3 * nen);
  double energy = 0.0;
  for (auto _ : state) {
    fibrane::shell::add_shell_point(section, d.R, d.X, d.x, 1e-3, &energy, &r);
    benchmark::DoNotOptimize(r.data());
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_ShellPointResidualOnly)->Arg(9)->Arg(16)->Arg(25)->Unit(benchmark::kMicrosecond);

// Residual + tangent with a neo-Hookean section: range(1) = 0 compressible, 1 incompressible (4 thickness
// points each).
void BM_ShellPointResidualTangentMaterial(benchmark::State& state) {
  const int nen = static_cast<int>(state.range(0));
  const PointData d = make_point(nen);
  fibrane::shell::ShellSection section{0.01, nullptr};
  if (state.range(1) == 0)
    section.material = std::make_shared<const fibrane::shell::NeoHookeanMaterial>(1.0e5, 0.3, 4);
  else
    section.material = std::make_shared<const fibrane::shell::IncompressibleNeoHookeanMaterial>(3.0e4, 4);
  Eigen::VectorXd r = Eigen::VectorXd::Zero(3 * nen);
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(3 * nen, 3 * nen);
  double energy = 0.0;
  for (auto _ : state) {
    fibrane::shell::add_shell_point(section, d.R, d.X, d.x, 1e-3, &energy, &r, &k);
    benchmark::DoNotOptimize(k.data());
    benchmark::ClobberMemory();
  }
  if (!std::isfinite(energy)) state.SkipWithError("non-finite energy: the point's state is not admissible");
}
BENCHMARK(BM_ShellPointResidualTangentMaterial)->Args({9, 0})->Args({9, 1})->Args({25, 0})->Args({25, 1})
    ->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
