// Cost of assembling the residual and tangent of a degree-4 Kirchhoff-Love shell through the real model
// (case file -> model::read_case -> Model::evaluate(q, t, true)), INCLUDING the scatter into the reduced
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
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "model/case_reader.hpp"
#include "solve/linear_solver.hpp"
#include "spline/quadrature.hpp"

namespace {

using Clock = std::chrono::steady_clock;

// Best (minimum) wall time in seconds of `reps` calls: the minimum is the least disturbed by the other jobs
// sharing the machine.
double best_seconds(int reps, const std::function<void()>& f) {
  double best = 1e300;
  for (int i = 0; i < reps; ++i) {
    const auto t0 = Clock::now();
    f();
    best = std::min(best, std::chrono::duration<double>(Clock::now() - t0).count());
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

// Serial pass over the shell's elements, timing basis evaluation and the point kernel separately (the
// same loop as model::ShellBody::assemble without the scatter). Returns {basis, kernel} seconds.
std::pair<double, double> serial_breakdown(const fibrane::model::ShellBody& s, const Eigen::VectorXd& u,
                                           const fibrane::solve::DofMap& dofs) {
  const auto gu = fibrane::spline::gauss_legendre(s.gauss(0));
  const auto gv = fibrane::spline::gauss_legendre(s.gauss(1));
  double t_basis = 0.0, t_kernel = 0.0, energy = 0.0;
  Eigen::VectorXd r;
  Eigen::MatrixXd k;
  std::vector<fibrane::spline::SurfaceBasis> bases(gu.points.size() * gv.points.size());
  for (std::size_t e = 0; e < s.elements.size(); ++e) {
    const auto& el = s.elements[e];
    const auto& cps = s.element_control_points[e];
    const Eigen::Matrix3Xd X = s.reference(cps), x = s.current(cps, u, dofs);
    const int n = 3 * static_cast<int>(cps.size());
    r.setZero(n);
    k.setZero(n, n);
    const double ju = 0.5 * (el.u1 - el.u0), jv = 0.5 * (el.v1 - el.v0);
    auto t0 = Clock::now();
    for (std::size_t j = 0; j < gv.points.size(); ++j)
      for (std::size_t i = 0; i < gu.points.size(); ++i)
        bases[i + gu.points.size() * j] = s.surface.basis_in(el.span_u, el.span_v, el.u0 + (gu.points[i] + 1.0) * ju,
                                                             el.v0 + (gv.points[j] + 1.0) * jv);
    auto t1 = Clock::now();
    for (std::size_t j = 0; j < gv.points.size(); ++j)
      for (std::size_t i = 0; i < gu.points.size(); ++i)
        fibrane::shell::add_shell_point(s.section, bases[i + gu.points.size() * j].R, X, x,
                                        gu.weights[i] * gv.weights[j] * ju * jv, &energy, &r, &k);
    auto t2 = Clock::now();
    t_basis += std::chrono::duration<double>(t1 - t0).count();
    t_kernel += std::chrono::duration<double>(t2 - t1).count();
  }
  if (!std::isfinite(energy)) std::printf("(non-finite energy)\n");
  return {t_basis, t_kernel};
}

}  // namespace

int main(int argc, char** argv) {
  const int n = argc > 1 ? std::atoi(argv[1]) : 32;
  const int reps = argc > 2 ? std::atoi(argv[2]) : 5;
  auto c = fibrane::model::read_case(write_case(n, argv[0]));
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
  double t_serial = 0.0;
  std::printf("\n| threads | residual + tangent [ms] | per qp [us] | speed-up | residual only [ms] |\n");
  std::printf("|---|---|---|---|---|\n");
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    m.evaluate(q, 1.0, true);  // warm-up: first-touch of the thread buffers
    const double t_full = best_seconds(reps, [&] { m.evaluate(q, 1.0, true); });
    const double t_res = best_seconds(reps, [&] { m.evaluate(q, 1.0, false); });
    if (threads == 1) t_serial = t_full;
    std::printf("| %d | %.2f | %.2f | %.2f | %.2f |\n", threads, 1e3 * t_full, 1e6 * t_full / qps,
                t_serial / t_full, 1e3 * t_res);
  }
  omp_set_num_threads(max_threads);

  m.evaluate(q, 1.0, true);
  const auto& k = m.tangent();
  auto solver = fibrane::solve::make_linear_solver("cholmod", true);
  const double t_analyze = best_seconds(1, [&] { solver->analyze(k); });
  bool ok = true;
  const double t_factor = best_seconds(reps, [&] { ok = solver->factorize(k) && ok; });
  std::printf("\nmatrix: %ld rows, %ld nonzeros (both triangles); %s factor: %ld nonzeros%s\n",
              static_cast<long>(k.rows()), static_cast<long>(k.nonZeros()), solver->name().c_str(),
              solver->factor_nonzeros(), ok ? "" : " (FACTORISATION FAILED)");
  std::printf("analysis %.2f ms, numeric factorisation %.2f ms; assembly (1 thread) / factorisation = %.2f\n",
              1e3 * t_analyze, 1e3 * t_factor, t_serial / t_factor);

  double t_basis = 1e300, t_kernel = 1e300;
  for (int i = 0; i < reps; ++i) {
    const auto [b, kk] = serial_breakdown(shell, m.displacement(), m.dofs);
    t_basis = std::min(t_basis, b);
    t_kernel = std::min(t_kernel, kk);
  }
  std::printf("\nserial breakdown per qp: basis_in %.2f us (%.0f%%), shell point kernel %.2f us (%.0f%%), "
              "rest of evaluate (gather, zeroing, scatter, reduction) %.2f us (%.0f%%)\n",
              1e6 * t_basis / qps, 100 * t_basis / t_serial, 1e6 * t_kernel / qps, 100 * t_kernel / t_serial,
              1e6 * (t_serial - t_basis - t_kernel) / qps, 100 * (t_serial - t_basis - t_kernel) / t_serial);
  return ok ? 0 : 1;
}
