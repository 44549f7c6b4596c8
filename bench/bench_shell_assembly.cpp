// Cost of assembling the residual and tangent of a degree-4 Kirchhoff-Love shell through the real model
// (case file -> casefile::read_case -> Model::evaluate(q, t, true)), INCLUDING the scatter into the reduced
// sparse matrix, per quadrature point, on 1 and 2 OpenMP threads; and, for the ratio, the sparse
// factorisation of the same matrix. A serial breakdown of one assembly pass (basis evaluation, point kernel,
// the rest) shows what dominates.
// Usage: bench_shell_assembly [elements_per_direction = 32] [repetitions = 5]
// The example is looked up as examples/scordelis-lo.yaml in the working directory, then two levels above
// the executable (the repository root for build-*/bench/).
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "case/case_reader.hpp"
#include "case_edit.hpp"
#include "linalg/linear_solver.hpp"
#include "spline/quadrature.hpp"

namespace {

using Clock = std::chrono::steady_clock;

double process_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// Wall time and CPU time summed over the process's threads, in seconds. On a machine shared with other
// jobs the wall time of a serial pass includes time spent descheduled, the CPU time does not; on 2 threads
// the CPU time shows the work added by parallelisation (buffers, reduction, waiting at the barrier).
struct Timing {
  double wall = 1e300, cpu = 1e300;
};

// Best (minimum) of `reps` calls, separately for wall and CPU time: the minimum is the least disturbed.
Timing best_of(int reps, const std::function<void()>& f) {
  Timing best;
  for (int i = 0; i < reps; ++i) {
    const double c0 = process_cpu_seconds();
    const auto t0 = Clock::now();
    f();
    best.wall = std::min(best.wall, std::chrono::duration<double>(Clock::now() - t0).count());
    best.cpu = std::min(best.cpu, process_cpu_seconds() - c0);
  }
  return best;
}

// The Scordelis-Lo example at degree 4, C3, n x n elements, written to a temporary file.
std::string write_case(int n, const char* argv0) {
  auto source = std::filesystem::path("examples") / "scordelis-lo.yaml";
  if (!std::filesystem::exists(source))
    source = std::filesystem::absolute(argv0).parent_path().parent_path().parent_path() / source;
  std::ifstream in(source);
  if (!in) throw std::runtime_error("cannot find examples/scordelis-lo.yaml; run from the repository root");
  std::stringstream s;
  s << in.rdbuf();
  std::string text = s.str();
  const std::string from = "elements: [16, 16]";
  const auto at = text.find(from);
  if (at == std::string::npos) throw std::runtime_error("scordelis-lo.yaml: refine line not found");
  text.replace(at, from.size(), "elements: [" + std::to_string(n) + ", " + std::to_string(n) + "]");
  const auto path = std::filesystem::temp_directory_path() / "fibrane-bench-shell-assembly.yaml";
  std::ofstream(path) << text;
  return path.string();
}

// Serial passes over the shell's elements that split one assembly into its parts: basis evaluation
// (configuration-independent, recomputed every pass by ShellBody::assemble), and the point kernel with the
// per-element gather of control points and zeroing of the element arrays. The scatter and the reduction are
// what remains of Model::evaluate.
struct Breakdown {
  const fibrane::model::ShellBody& s;
  fibrane::spline::QuadratureRule gu, gv;
  std::vector<fibrane::spline::SurfaceBasis> bases;  // all quadrature points, element by element

  explicit Breakdown(const fibrane::model::ShellBody& body)
      : s(body), gu(fibrane::spline::gauss_legendre(body.gauss(0))), gv(fibrane::spline::gauss_legendre(body.gauss(1))) {
    bases.resize(s.elements.size() * gu.points.size() * gv.points.size());
    basis_pass();
  }
  double ju(std::size_t e) const { return 0.5 * (s.elements[e].u1 - s.elements[e].u0); }
  double jv(std::size_t e) const { return 0.5 * (s.elements[e].v1 - s.elements[e].v0); }

  void basis_pass() {
    std::size_t q = 0;
    for (std::size_t e = 0; e < s.elements.size(); ++e) {
      const auto& el = s.elements[e];
      for (double pv : gv.points)
        for (double pu : gu.points)
          bases[q++] = s.surface.basis_in(el.span_u, el.span_v, el.u0 + (pu + 1.0) * ju(e), el.v0 + (pv + 1.0) * jv(e));
    }
  }

  double kernel_pass(const Eigen::VectorXd& u, const fibrane::solve::DofMap& dofs) const {
    double energy = 0.0;
    Eigen::VectorXd r;
    Eigen::MatrixXd k;
    fibrane::shell::ElementTangent element_tangent;
    std::size_t q = 0;
    for (std::size_t e = 0; e < s.elements.size(); ++e) {
      const auto& cps = s.element_control_points[e];
      const Eigen::Matrix3Xd X = s.reference(cps), x = s.current(cps, u, dofs);
      const int n = 3 * static_cast<int>(cps.size());
      r.setZero(n);
      element_tangent.reset(static_cast<int>(cps.size()));
      const double w = ju(e) * jv(e);
      for (double wv : gv.weights)
        for (double wu : gu.weights)
          fibrane::shell::add_shell_point(s.section, bases[q++].R, X, x, wu * wv * w, &energy, &r, &element_tangent);
      k.setZero(n, n);
      element_tangent.add_to(k);
    }
    return energy;
  }
};

}  // namespace

int run_bench(int argc, char** argv) {
  if (help_requested(argc, argv,
                     "usage: bench_shell_assembly [ELEMENTS_PER_DIRECTION (32)] [REPETITIONS (5)]\n"
                     "  shell assembly of a Scordelis-Lo roof with 1, 2, ... threads\n"))
    return 0;
  const int n = argc > 1 ? std::atoi(argv[1]) : 32;
  const int reps = argc > 2 ? std::atoi(argv[2]) : 5;
  auto c = fibrane::casefile::read_case(write_case(n, argv[0]));
  auto& m = *c.model;
  const auto& shell = m.shells.at(0);
  const long qps = static_cast<long>(shell.elements.size()) * shell.gauss(0) * shell.gauss(1);

  // A small random state: the cost does not depend on the values, but a non-zero state exercises the
  // nonlinear terms exactly as a Newton iteration does.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> dist(-1e-3, 1e-3);
  Eigen::VectorXd q(m.size());
  for (auto& v : q) v = dist(rng);

  std::printf("Scordelis-Lo roof, degree %d, %d x %d elements, %ld quadrature points, %d free DOFs\n",
              shell.surface.degree(0), n, n, qps, m.size());
  const int max_threads = omp_get_max_threads();
  Timing serial;
  std::printf("\n| threads | residual + tangent: wall [ms] | CPU [ms] | per qp wall [us] | per qp CPU [us] | "
              "speed-up (wall) | residual only: wall [ms] | CPU [ms] |\n");
  std::printf("|---|---|---|---|---|---|---|---|\n");
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    m.evaluate(q, 1.0, true);  // warm-up: first touch of the thread buffers
    const Timing full = best_of(reps, [&] { m.evaluate(q, 1.0, true); });
    const Timing res = best_of(reps, [&] { m.evaluate(q, 1.0, false); });
    if (threads == 1) serial = full;
    std::printf("| %d | %.1f | %.1f | %.2f | %.2f | %.2f | %.1f | %.1f |\n", threads, 1e3 * full.wall,
                1e3 * full.cpu, 1e6 * full.wall / qps, 1e6 * full.cpu / qps, serial.wall / full.wall,
                1e3 * res.wall, 1e3 * res.cpu);
  }
  omp_set_num_threads(max_threads);

  m.evaluate(q, 1.0, true);
  const auto& k = m.tangent();
  auto solver = fibrane::solve::make_linear_solver("cholmod", true);
  const Timing analyze = best_of(1, [&] { solver->analyze(k); });
  bool ok = true;
  const Timing factor = best_of(reps, [&] { ok = solver->factorize(k) && ok; });
  std::printf("\nmatrix: %ld rows, %ld nonzeros (both triangles); %s factor: %ld nonzeros%s\n",
              static_cast<long>(k.rows()), static_cast<long>(k.nonZeros()), solver->name().c_str(),
              solver->factor_nonzeros(), ok ? "" : " (FACTORISATION FAILED)");
  std::printf("analysis %.1f ms; numeric factorisation wall %.1f ms, CPU %.1f ms\n", 1e3 * analyze.wall,
              1e3 * factor.wall, 1e3 * factor.cpu);
  std::printf("assembly (1 thread) / factorisation: %.2f by wall time, %.2f by CPU time\n",
              serial.wall / factor.wall, serial.cpu / factor.cpu);

  // The parts of one serial assembly, each the best of `reps` passes, interleaved with full evaluations so
  // that all three see the same machine load.
  omp_set_num_threads(1);
  Breakdown parts(shell);
  Timing eval, basis, kernel;
  double energy = 0.0;
  for (int i = 0; i < reps; ++i) {
    const Timing e = best_of(1, [&] { m.evaluate(q, 1.0, true); });
    const Timing b = best_of(1, [&] { parts.basis_pass(); });
    const Timing kk = best_of(1, [&] { energy += parts.kernel_pass(m.displacement(), m.dofs); });
    eval.cpu = std::min(eval.cpu, e.cpu);
    basis.cpu = std::min(basis.cpu, b.cpu);
    kernel.cpu = std::min(kernel.cpu, kk.cpu);
  }
  const double rest = eval.cpu - basis.cpu - kernel.cpu;
  std::printf("\nserial breakdown by CPU time (evaluate %.2f us per qp): basis_in %.2f us (%.0f%%); point kernel "
              "with gather and zeroing %.2f us (%.0f%%); scatter, reduction and the rest %.2f us (%.0f%%)%s\n",
              1e6 * eval.cpu / qps, 1e6 * basis.cpu / qps, 100 * basis.cpu / eval.cpu, 1e6 * kernel.cpu / qps,
              100 * kernel.cpu / eval.cpu, 1e6 * rest / qps, 100 * rest / eval.cpu,
              std::isfinite(energy) ? "" : " (non-finite energy)");
  return ok ? 0 : 1;
}

int main(int argc, char** argv) { return guarded_main(argc, argv, run_bench); }
