// Newton residual log of a nonlinear case: runs the quasi-time continuation of a YAML case (as `fibrane run`
// does, without writing output) and prints, for every converged step, the residual norm ||r|| of each Newton
// iteration together with the ratios log(r_{k+1}/r_k) / log(r_k/r_{k-1}), which tend to 2 when Newton
// converges quadratically (paper Sec. 2.3: Newton's method inside each continuation increment).
// Usage: shell_newton_log <case.yaml> [max_steps_to_print]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>

#include "case/case_reader.hpp"
#include "case_edit.hpp"
#include "path/load_stepping.hpp"
#include "linalg/linear_solver.hpp"

namespace {

// Observed order of convergence from three successive residual norms; NaN unless both decrease.
double observed_order(double r0, double r1, double r2) {
  const double a = std::log(r1 / r0), b = std::log(r2 / r1);
  return (a < 0.0 && b < 0.0) ? b / a : std::nan("");
}

}  // namespace

int main(int argc, char** argv) {
  if (help_requested(argc, argv,
                     "usage: shell_newton_log CASE.yaml [MAX_STEPS_TO_PRINT]\n"
                     "  |r| of every Newton iteration of the case's load stepping, with contraction and order\n"))
    return 0;
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s <case.yaml> [max_steps_to_print]\n", argv[0]);
    return 2;
  }
  const int max_print = argc > 2 ? std::atoi(argv[2]) : 1000000;
  try {
    auto c = fibrane::casefile::read_case(argv[1]);
    auto& m = *c.model;
    auto solver = fibrane::solve::make_linear_solver(c.run.linear_solver, m.symmetric());
    Eigen::VectorXd q = m.initial_unknowns();
    std::printf("step,t,iteration,residual,contraction,order\n");
    const auto result = fibrane::solve::LoadStepping(c.run.steps, c.run.newton).run(m, q, *solver, [&](const fibrane::solve::StepReport& r, const Eigen::VectorXd&) {
          if (r.step > max_print) return true;
          const auto& h = r.history;
          for (std::size_t k = 0; k < h.size(); ++k) {
            const double contraction = k >= 1 ? h[k] / (h[k - 1] * h[k - 1]) : std::nan("");
            const double order = k >= 2 ? observed_order(h[k - 2], h[k - 1], h[k]) : std::nan("");
            std::printf("%d,%.6g,%zu,%.6e,%.3e,%.3f\n", r.step, r.t, k, h[k], contraction, order);
          }
          return true;
        });
    std::fprintf(stderr, "%s: %s at t = %g after %d steps, %d Newton iterations\n", c.name.c_str(),
                 result.completed() ? "completed" : "stopped", result.t_reached, result.steps,
                 result.total_iterations);
    return result.completed() ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
}
