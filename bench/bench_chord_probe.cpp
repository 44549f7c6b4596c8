// How far a step's first factorisation is from the tangent of its next iterate, and where the difference
// lies:
//   bench_chord_probe CASE.yaml [--threads N] [--every K] [--t-end T] [--replace FROM TO]...
// runs the case's continuation and, at every K-th step, when Newton factorises the tangent K1 of the
// step's second iterate, solves K1 x = b (b = -r1, the update Newton takes) with three matrices: K1
// itself, the step's first tangent K0 (a chord update) and K0 + (K1 - K0)_SS, the first tangent with the
// difference replaced on the rows and columns S of the beams and of the shell unknowns coupled to them.
// It prints the relative linear residual |K1 x - b| / |b| of each (-1: the matrix did not factorise, it is
// not positive definite), and the difference's Frobenius norm on S x S and elsewhere. The step's first
// factorisation stands for what a chord iteration or a Krylov method preconditioned by it would use, the
// replaced block for a refactorisation of the interaction's rows alone (docs/performance.md, "Per-phase
// breakdown of the whole run").
#include <omp.h>

#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include <Eigen/SparseCore>
#include <fmt/format.h>

#include "case_edit.hpp"
#include "case/case_reader.hpp"
#include "linalg/linear_solver.hpp"
#include "run/process_environment.hpp"
#include "run/run.hpp"

namespace {

using SpMat = Eigen::SparseMatrix<double>;

class ProbeSolver : public fibrane::solve::LinearSolver {
 public:
  ProbeSolver(std::unique_ptr<fibrane::solve::LinearSolver> inner, std::vector<char> beam, int every)
      : inner_(std::move(inner)), beam_(std::move(beam)), every_(every) {}
  void begin_step() override {
    in_step_ = 0;
    ++step_;
    inner_->begin_step();
  }
  void analyze(const SpMat& a) override { inner_->analyze(a); }
  bool factorize_numeric(const SpMat& a) override {
    if (in_step_ == 0) k0_ = a;
    if (in_step_ == 1 && step_ % every_ == 0) {
      k1_ = a;
      pending_ = true;
    }
    ++in_step_;
    return inner_->factorize(a);
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const override { return solve_to(b, 0.0); }
  Eigen::VectorXd solve_to(const Eigen::VectorXd& b, double accuracy) const override {
    Eigen::VectorXd x = inner_->solve_to(b, accuracy);
    if (pending_) probe(b, x);
    pending_ = false;
    return x;
  }
  std::string name() const override { return inner_->name(); }
  long factor_nonzeros() const override { return inner_->factor_nonzeros(); }
  std::string analysis_summary() const override { return inner_->analysis_summary(); }
  int negative_eigenvalues() const override { return inner_->negative_eigenvalues(); }
  std::string failure_detail() const override { return inner_->failure_detail(); }
  double t = 0;

 private:
  // x solved with `m` (a fresh CHOLMOD LL^T), its linear residual against K1.
  double residual_with(const SpMat& m, const Eigen::VectorXd& b) const {
    auto s = fibrane::solve::make_linear_solver("cholmod", true);
    s->analyze(m);
    if (!s->factorize(m)) {
      fmt::print("  factorisation failed: {}\n", s->failure_detail());
      return -1;
    }
    const Eigen::VectorXd x = s->solve(b);
    return (k1_ * x - b).norm() / b.norm();
  }
  void probe(const Eigen::VectorXd& b, const Eigen::VectorXd& x1) const {
    const auto n = static_cast<int>(k1_.rows());
    std::vector<char> in_s(beam_);
    for (int j = 0; j < n; ++j)
      if (beam_[static_cast<std::size_t>(j)])
        for (SpMat::InnerIterator it(k1_, j); it; ++it) in_s[static_cast<std::size_t>(it.row())] = 1;
    int beams = 0, shells = 0;
    for (int i = 0; i < n; ++i)
      if (in_s[static_cast<std::size_t>(i)]) (beam_[static_cast<std::size_t>(i)] ? beams : shells) += 1;
    const SpMat diff = k1_ - k0_;
    SpMat diff_ss = diff;
    diff_ss.prune([&](Eigen::Index i, Eigen::Index j, double) {
      return in_s[static_cast<std::size_t>(i)] && in_s[static_cast<std::size_t>(j)];
    });
    const double all = diff.norm(), ss = diff_ss.norm();
    const double exact = (k1_ * x1 - b).norm() / b.norm();
    const double chord = residual_with(k0_, b);
    const SpMat hybrid = k0_ + diff_ss;
    const double mixed = residual_with(hybrid, b);
    fmt::print("probe step {} (the step after t = {:.6g}): S = {} beam + {} shell unknowns; |K1 - K0|_F = {:.4g} ({:.4g} on S x S, "
               "{:.4g} elsewhere), |K1|_F = {:.4g}; linear residual with K1 {:.2e}, with K0 {:.3e}, with K0 + "
               "(K1 - K0)_SS {:.3e}\n",
               step_, t, beams, shells, all, ss, std::sqrt(std::max(0.0, all * all - ss * ss)), k1_.norm(), exact,
               chord, mixed);
    std::fflush(stdout);
  }
  std::unique_ptr<fibrane::solve::LinearSolver> inner_;
  std::vector<char> beam_;
  int every_;
  int step_ = 0, in_step_ = 0;
  SpMat k0_, k1_;
  mutable bool pending_ = false;
};

}  // namespace

int run_bench(int argc, char** argv) {
  fibrane::run::configure_process_environment(argc, argv);  // the environment of `fibrane run`
  const char* usage = "usage: bench_chord_probe CASE.yaml [--threads N] [--every K] [--t-end T] [--replace FROM TO]...\n";
  int every = 6, code = 0;
  double t_end = -1;
  const auto path = case_arguments(argc, argv, usage, [&](const std::string& a, int& i) {
    if (i + 1 >= argc) return false;
    if (a == "--every") every = std::max(1, std::stoi(argv[++i]));
    else if (a == "--t-end") t_end = std::stod(argv[++i]);
    else return false;
    return true;
  }, code);
  if (!path) return code;
  auto c = fibrane::casefile::read_case(*path);
  auto& m = *c.model;
  if (t_end > 0) c.run.steps.t_end = t_end;
  std::vector<char> beam(static_cast<std::size_t>(m.size()), 0);
  for (int j = 0; j < m.size(); ++j) {
    const int d = m.constraints.free_dof(j);
    for (int blk = 0; blk < m.dofs.num_blocks(); ++blk)
      if (m.dofs.dofs_per_node(blk) == 4 && d >= m.dofs.block_offset(blk) &&
          d < m.dofs.block_offset(blk) + m.dofs.block_size(blk))
        beam[static_cast<std::size_t>(j)] = 1;
  }
  ProbeSolver solver(fibrane::solve::make_linear_solver(c.run.linear_solver, m.symmetric()), beam, every);
  Eigen::VectorXd q = m.initial_unknowns();
  const auto method = fibrane::run::make_method(c.run, false);
  const auto result = method->run(m, q, solver, [&](const fibrane::solve::StepReport& r, const Eigen::VectorXd&) {
    solver.t = r.t;
    return true;
  });
  fmt::print("{}\n", result.completed() ? "completed" : result.message);
  return 0;
}

int main(int argc, char** argv) { return guarded_main(argc, argv, run_bench); }
