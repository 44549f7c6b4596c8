// Cost of the beam-shell interaction building blocks (src/interaction): one SBS pair point (energy +
// residual + tangent) for RF2 / RF1 / FF-with-RF1-tangent / FF-exact at nB = 5 (quartic beam element) and
// nS = 25 (quartic shell element), and one closest-point projection on a 20 x 20 quartic patch, cold
// (global search + Newton) and warm-started from a nearby previous foot point; one soft-minimum point
// (energy + residual + tangent, and the window's construction) at the bending example's paper mesh.
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>

#include "laws/lennard_jones.hpp"
#include "interaction/closest_point.hpp"
#include "interaction/sbs_point.hpp"
#include "interaction/soft_distance.hpp"
#include "spline/shapes.hpp"
#include "spline/surface_third.hpp"

namespace {

using namespace fibrane;

// 20 x 20 quartic C1 patch over [0,10]^2 with a smooth bump (so that the projection is not trivial).
spline::NurbsSurface bumpy_patch() {
  spline::NurbsSurface s = spline::make_rectangle({0, 0, 0}, {10, 0, 0}, {0, 10, 0});
  s.refine(0, 4, 1, 20);
  s.refine(1, 4, 1, 20);
  std::vector<Eigen::Vector3d> x = s.control_points();
  for (Eigen::Vector3d& p : x) p.z() = 0.5 * std::sin(0.7 * p.x()) * std::cos(0.5 * p.y());
  return spline::NurbsSurface(s.knots(0), s.knots(1), x, s.weights());
}

Eigen::Matrix<double, 2, Eigen::Dynamic> bernstein4(double xi) {
  Eigen::Matrix<double, 2, Eigen::Dynamic> b(2, 5);
  const double binom[5] = {1, 4, 6, 4, 1};
  for (int i = 0; i < 5; ++i) {
    b(0, i) = binom[i] * std::pow(xi, i) * std::pow(1 - xi, 4 - i);
    b(1, i) = binom[i] * ((i > 0 ? i * std::pow(xi, i - 1) * std::pow(1 - xi, 4 - i) : 0.0) -
                          (i < 4 ? (4 - i) * std::pow(xi, i) * std::pow(1 - xi, 3 - i) : 0.0));
  }
  return b;
}

interaction::PairPoint make_pair(const spline::NurbsSurface& s) {
  const interaction::ShellProximity prox(s);
  interaction::PairPoint p;
  p.beam_basis = bernstein4(0.3);
  p.beam_x.resize(3, 5);
  for (int i = 0; i < 5; ++i) p.beam_x.col(i) = Eigen::Vector3d(4.0 + 0.25 * i, 5.0 + 0.05 * i, 1.0 + 0.02 * i);
  const auto proj = prox.project(p.beam_x * p.beam_basis.row(0).transpose());
  const auto& e = prox.elements()[proj.element];
  const spline::SurfaceBasis b = s.basis_in(e.span_u, e.span_v, proj.u, proj.v);
  p.shell_basis = b.R;
  p.shell_basis3 = spline::basis3_in(s, e.span_u, e.span_v, proj.u, proj.v).R;
  p.shell_x.resize(3, static_cast<int>(b.indices.size()));
  for (std::size_t a = 0; a < b.indices.size(); ++a) p.shell_x.col(a) = s.control_points()[b.indices[a]];
  p.weight = 0.1;
  return p;
}

void BM_SbsPoint(benchmark::State& state) {
  const auto f = static_cast<interaction::Formulation>(state.range(0));
  const auto ft = static_cast<interaction::FfTangent>(state.range(1));
  const interaction::PairPoint p = make_pair(bumpy_patch());
  laws::LennardJonesDiskPlate law{};
  law.epsilon = 1, law.sigma = 0.05, law.disk_radius = 0.5, law.plate_thickness = 0.5;
  Eigen::VectorXd r = Eigen::VectorXd::Zero(4 * 5 + 3 * 25);
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(r.size(), r.size());
  double energy = 0;
  for (auto _ : state) {
    interaction::add_sbs_point(law, f, ft, p, &energy, &r, &k);
    benchmark::DoNotOptimize(k.data());
    benchmark::ClobberMemory();
  }
}
// Formulation: 0 FF, 1 RF1, 2 RF2; FfTangent: 0 rf1, 1 exact.
BENCHMARK(BM_SbsPoint)->ArgNames({"formulation", "ff_exact"})->Args({2, 0})->Args({1, 0})->Args({0, 0})
    ->Args({0, 1})->Unit(benchmark::kMicrosecond);

void BM_Projection(benchmark::State& state) {
  const spline::NurbsSurface s = bumpy_patch();
  const interaction::ShellProximity prox(s);
  const Eigen::Vector3d p(4.3, 6.1, 0.9);
  const auto previous = prox.project(p + Eigen::Vector3d(1e-3, -1e-3, 0));
  const bool warm = state.range(0) != 0;
  for (auto _ : state) {
    auto r = warm ? prox.project(p, Eigen::Vector2d(previous.u, previous.v)) : prox.project(p);
    benchmark::DoNotOptimize(r.distance);
  }
}
BENCHMARK(BM_Projection)->ArgName("warm")->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

void BM_ProximityUpdate(benchmark::State& state) {
  const spline::NurbsSurface s = bumpy_patch();
  interaction::ShellProximity prox(s);
  for (auto _ : state) prox.update(s.control_points());
}
BENCHMARK(BM_ProximityUpdate)->Unit(benchmark::kMicrosecond);

// One soft-minimum point as in the bending example at the paper's mesh: the quarter plate [0, 5]^2 with
// 100 x 100 quartic C1 elements and its mirror plane x = 0, the point in the mirror plane at the RF2
// equilibrium distance of the example's law (d_eq = 0.782), window and cells as src/model/coupling.cpp
// makes them (interaction::soft_window_half_width, soft_window_cell); argument: width x 1e4.
struct SoftSetup {
  laws::LennardJonesDiskPlate law{6400, 0.05, 0.5, 0.5, 1, 1, 400};
  spline::NurbsSurface plate = spline::make_rectangle({0, 0, 0}, {5, 0, 0}, {0, 5, 0});
  Eigen::RowVectorXd basis = bernstein4(0.3).row(0);
  Eigen::Matrix3Xd beam_x = Eigen::Matrix3Xd(3, 5);
  double d_eq = 0, width = 0;
  explicit SoftSetup(double w) : width(w) {
    plate.refine(0, 4, 1, 100);
    plate.refine(1, 4, 1, 100);
    d_eq = law.equilibrium_distance(1.0);
    for (int i = 0; i < 5; ++i) beam_x.col(i) = Eigen::Vector3d(0, 2.6 + 0.1 * i, d_eq);
  }
  interaction::SoftWindow window() const {
    return interaction::make_soft_window(plate, {0.0, 0.6}, interaction::soft_window_half_width(width, d_eq),
                                         interaction::soft_window_cell(width, d_eq),
                                         {interaction::MirrorPlane{0, 0.0}});
  }
};

void BM_SoftPoint(benchmark::State& state) {
  const SoftSetup setup(state.range(0) * 1e-4);
  const interaction::SoftWindow w = setup.window();
  Eigen::Matrix3Xd x(3, w.control_points.size());
  for (std::size_t a = 0; a < w.control_points.size(); ++a)
    x.col(a) = setup.plate.control_points()[w.control_points[a]];
  const double beta = 1.0 / (setup.width * setup.d_eq);
  Eigen::VectorXd r;
  Eigen::MatrixXd k;
  std::vector<int> support;  // as the coupling calls it: residual and tangent on the support only
  for (auto _ : state) {
    double e = 0;
    interaction::add_soft_rf2_point(setup.law, beta, setup.basis, setup.beam_x, w, x, 0.0, 0.01, &e, &r, &k,
                                    nullptr, &support);
    benchmark::DoNotOptimize(k.data());
  }
  state.counters["samples"] = w.num_samples();
  state.counters["window_points"] = static_cast<double>(w.control_points.size());
  state.counters["support_dofs"] = static_cast<double>(support.size());
}
BENCHMARK(BM_SoftPoint)->ArgName("width_1e4")->Arg(5)->Arg(20)->Unit(benchmark::kMillisecond);

// The same point where the shell wraps around it, as at the fiber's end when points switch: a cylindrical
// shell of radius R = d_eq / 0.95 about an axis through the point (relative curvature 1 - d / R = 0.05,
// the example's `below`), elements of the paper mesh's size (0.05). Every sample across the arc is at the
// same distance, so the support is as wide as the window across it.
void BM_SoftPointWrapped(benchmark::State& state) {
  const SoftSetup setup(5e-4);
  const double R = setup.d_eq / 0.95;
  spline::NurbsSurface shell = spline::make_cylinder_patch(R, 2.0, 0.0, std::numbers::pi);
  shell.refine(0, 4, 1, static_cast<int>(std::ceil(std::numbers::pi * R / 0.05)));  // u: the arc
  shell.refine(1, 4, 1, 40);                                                          // v: x in [0, 2]
  const interaction::SoftWindow w = interaction::make_soft_window(
      shell, {0.5, 0.5}, interaction::soft_window_half_width(setup.width, setup.d_eq),
      interaction::soft_window_cell(setup.width, setup.d_eq), {});
  Eigen::Matrix3Xd x(3, w.control_points.size());
  for (std::size_t a = 0; a < w.control_points.size(); ++a) x.col(a) = shell.control_points()[w.control_points[a]];
  const Eigen::Vector3d axis_point(1.0, 0.0, 0.0);  // the cylinder's axis is x
  Eigen::Matrix3Xd beam_x(3, 5);
  for (int i = 0; i < 5; ++i) beam_x.col(i) = axis_point;
  const double beta = 1.0 / (setup.width * setup.d_eq);
  Eigen::VectorXd r;
  Eigen::MatrixXd k;
  std::vector<int> support;
  for (auto _ : state) {
    double e = 0;
    interaction::add_soft_rf2_point(setup.law, beta, setup.basis, beam_x, w, x, 0.0, 0.01, &e, &r, &k, nullptr,
                                    &support);
    benchmark::DoNotOptimize(k.data());
  }
  state.counters["samples"] = w.num_samples();
  state.counters["window_points"] = static_cast<double>(w.control_points.size());
  state.counters["support_dofs"] = static_cast<double>(support.size());
}
BENCHMARK(BM_SoftPointWrapped)->Unit(benchmark::kMillisecond);

void BM_SoftWindow(benchmark::State& state) {
  const SoftSetup setup(state.range(0) * 1e-4);
  for (auto _ : state) benchmark::DoNotOptimize(setup.window().weight.data());
}
BENCHMARK(BM_SoftWindow)->ArgName("width_1e4")->Arg(5)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
