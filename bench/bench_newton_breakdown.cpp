// Where a Newton iteration spends its time, for any case and mesh:
//   bench_newton_breakdown CASE.yaml [--t-end T] [--threads N] [--reuse R] [--assembly A] [--replace FROM TO]...
// runs the case's continuation (no output files) and prints one table: DOFs, matrix and factor non-zeros,
// and per Newton iteration the time of shell assembly, beam assembly, interaction (projection/search and
// assembly), pattern work, the rest of the evaluation, symbolic analysis, numeric factorisation and solve,
// plus the Newton iterations per step, the assembly's per-thread buffers and the peak memory.
#include <omp.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "case_edit.hpp"
#include "case/case_reader.hpp"
#include "model/coupling.hpp"
#include "run/run.hpp"
#include "linalg/linear_solver.hpp"
#include "run/process_environment.hpp"

namespace {

using clock_type = std::chrono::steady_clock;

double seconds_since(clock_type::time_point t0) {
  return std::chrono::duration<double>(clock_type::now() - t0).count();
}

// Forwards to a real solver and times each phase. Around a KrylovReuseSolver (steps.krylov), `factorize`
// counts and times the calls (a reused factorisation costs nothing), `solve` the Krylov solves and any
// factorisation made within them; the solver's analysis summary gives its real counts.
class TimedSolver : public fibrane::solve::LinearSolver {
 public:
  explicit TimedSolver(std::unique_ptr<fibrane::solve::LinearSolver> inner) : inner_(std::move(inner)) {}
  void analyze(const Eigen::SparseMatrix<double>& a) override {
    const auto t0 = clock_type::now();
    inner_->analyze(a);
    analyze_ += seconds_since(t0);
    ++analyses;
  }
  bool factorize_numeric(const Eigen::SparseMatrix<double>& a) override {
    const auto t0 = clock_type::now();
    const bool ok = inner_->factorize(a);
    factorize_ += seconds_since(t0);
    ++factorizations;
    nnz = a.nonZeros();
    if (first_nnz == 0) {
      first_nnz = nnz;
      first_factor_nnz = inner_->factor_nonzeros();
    }
    return ok;
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const override {
    const auto t0 = clock_type::now();
    Eigen::VectorXd x = inner_->solve(b);
    solve_ += seconds_since(t0);
    return x;
  }
  Eigen::VectorXd solve_to(const Eigen::VectorXd& b, double relative_accuracy) const override {
    const auto t0 = clock_type::now();
    Eigen::VectorXd x = inner_->solve_to(b, relative_accuracy);
    solve_ += seconds_since(t0);
    return x;
  }
  bool factorize_exactly(const Eigen::SparseMatrix<double>& a) override {
    const auto t0 = clock_type::now();
    const bool ok = inner_->factorize_exactly(a);
    factorize_ += seconds_since(t0);
    ++factorizations;
    return ok;
  }
  std::string name() const override { return inner_->name(); }
  long factor_nonzeros() const override { return inner_->factor_nonzeros(); }
  std::string analysis_summary() const override { return inner_->analysis_summary(); }
  int negative_eigenvalues() const override { return inner_->negative_eigenvalues(); }
  bool exact() const override { return inner_->exact(); }
  std::string failure_detail() const override { return inner_->failure_detail(); }

  double analyze_ = 0, factorize_ = 0;
  mutable double solve_ = 0;
  int analyses = 0, factorizations = 0;
  long nnz = 0, first_nnz = 0, first_factor_nnz = 0;  // last and first factorisation

 private:
  std::unique_ptr<fibrane::solve::LinearSolver> inner_;
};

long peak_memory_kib() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("VmHWM:", 0) == 0) return std::stol(line.substr(6));
  return -1;
}

}  // namespace

int run_bench(int argc, char** argv) {
  fibrane::run::configure_process_environment(argc, argv);  // the environment of `fibrane run`
  const char* usage =
      "usage: bench_newton_breakdown CASE.yaml [--t-end T] [--threads N] [--reuse R] [--assembly A]\n"
      "                              [--replace FROM TO]...\n"
      "  runs the case's continuation method (steps.method) without output files and prints where the time goes\n"
      "  --t-end T: end the run at t = T (load stepping, arc-length)\n"
      "  --reuse R: steps.reuse_factorization for this run (default: the case's; 0 times plain Newton)\n"
      "  --assembly A: how threads share the assembly: colours (the default) or buffers (per-thread copies)\n";
  double t_end = -1, reuse = -1;
  std::string assembly = "colours";
  int code = 0;
  const auto path = case_arguments(argc, argv, usage, [&](const std::string& a, int& i) {
    if (i + 1 >= argc) return false;
    if (a == "--t-end") t_end = std::stod(argv[++i]);
    else if (a == "--reuse") reuse = std::stod(argv[++i]);
    else if (a == "--assembly") assembly = argv[++i];
    else return false;
    return true;
  }, code);
  if (!path) return code;
  if (assembly != "colours" && assembly != "buffers") {
    std::cerr << "--assembly: colours or buffers, not '" << assembly << "'\n";
    return 2;
  }
  auto c = fibrane::casefile::read_case(*path);
  auto& m = *c.model;
  if (t_end > 0) c.run.steps.t_end = c.run.arc_length.t_end = t_end;
  if (reuse >= 0) c.run.newton.reuse_below = reuse;
  if (assembly == "buffers") m.set_assembly(fibrane::solve::SparseAssembler::Strategy::ThreadBuffers);
  TimedSolver solver(fibrane::solve::make_linear_solver(c.run.linear_solver, m.symmetric()));
  Eigen::VectorXd q = m.initial_unknowns();
  m.reset_times();
  std::vector<int> iterations;
  int updates = 0;
  const auto t0 = clock_type::now();
  const auto method = fibrane::run::make_method(c.run, false);
  const auto result = method->run(m, q, solver, [&](const fibrane::solve::StepReport& r, const Eigen::VectorXd&) {
        iterations.push_back(r.iterations);
        updates += r.iterations;
        return true;
      });
  const double wall = seconds_since(t0);
  const auto& pt = m.times();
  const int n = std::max(1, pt.tangents);
  const double per = 1e3 / n;  // milliseconds per Newton iteration with a tangent (= per factorisation
                               // without reuse; residual-only evaluations are counted in the one before)
  double mean_iterations = 0;
  for (int k : iterations) mean_iterations += k;
  if (!iterations.empty()) mean_iterations /= iterations.size();
  const double not_factorisation = pt.shell + pt.beam + pt.projection + pt.interaction + pt.pattern + pt.other +
                                   solver.analyze_ + solver.solve_;
  fmt::print("case {}: {} ({}, {}, {} threads, assembly {})\n", c.path,
             result.completed() ? "completed" : result.message, method->name(), solver.name(), omp_get_max_threads(),
             assembly);
  fmt::print("| quantity | value |\n|---|---|\n");
  fmt::print("| DOFs (all / free) | {} / {} |\n", m.dofs.size(), m.size());
  fmt::print("| matrix non-zeros (first / last factorisation) | {} / {} |\n", solver.first_nnz, solver.nnz);
  fmt::print("| factor non-zeros (first / last factorisation) | {} / {} |\n", solver.first_factor_nnz,
             solver.factor_nonzeros());
  std::string soft;
  for (const auto* cp : m.interactions_of<fibrane::model::Coupling>())
    soft += fmt::format("{}{}: {}", soft.empty() ? "" : ", ", cp->name(), cp->soft_points());
  fmt::print("| soft-minimum points at the end | {} |\n", soft.empty() ? "-" : soft);
  fmt::print("| steps / evaluations with tangent / updates per step | {} / {} / {:.2f} |\n", iterations.size(), pt.tangents,
             mean_iterations);
  fmt::print("| shell assembly per iteration | {:.2f} ms |\n", pt.shell * per);
  fmt::print("| beam assembly per iteration | {:.2f} ms |\n", pt.beam * per);
  fmt::print("| interaction search + projection | {:.2f} ms |\n", pt.projection * per);
  fmt::print("| interaction assembly | {:.2f} ms |\n", pt.interaction * per);
  fmt::print("| pattern rebuilds (count) / time per iteration | {} / {:.2f} ms |\n", pt.pattern_rebuilds,
             pt.pattern * per);
  fmt::print("| loads, moments, reduction | {:.2f} ms |\n", pt.other * per);
  const std::string how = solver.analysis_summary();
  fmt::print("| symbolic analyses (count{}) / time per iteration | {} / {:.2f} ms |\n", how.empty() ? "" : ": " + how,
             solver.analyses, solver.analyze_ * per);
  fmt::print("| numeric factorisation per iteration | {:.2f} ms |\n", solver.factorize_ * per);
  fmt::print("| solve per iteration | {:.2f} ms |\n", solver.solve_ * per);
  fmt::print("| everything but factorisation / factorisation | {:.3f} |\n",
             solver.factorize_ > 0 ? not_factorisation / solver.factorize_ : 0.0);
  fmt::print("| residual-only evaluations | {} |\n", pt.evaluations - pt.tangents - pt.partial_tangents);
  fmt::print("| evaluations with part of the tangent (local first updates; their times in the rows above) | {} |\n",
             pt.partial_tangents);
  fmt::print("| updates of converged steps / factorisations (reuse {}) | {} / {} |\n", c.run.newton.reuse_below,
             updates, solver.factorizations);
  fmt::print("| assembly buffers at the end | {:.1f} MiB |\n", m.assembly_buffer_bytes() / 1048576.0);
  fmt::print("| wall time | {:.2f} s |\n| peak memory | {:.1f} MiB |\n", wall, peak_memory_kib() / 1024.0);
  return result.completed() ? 0 : 1;
}

int main(int argc, char** argv) { return guarded_main(argc, argv, run_bench); }
