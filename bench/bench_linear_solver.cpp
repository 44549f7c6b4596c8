// The sparse solver on a case's tangent at t = 0 (undeformed, after one evaluation):
//   bench_linear_solver CASE.yaml [--threads N] [--replace FROM TO]...
// prints the time of a first symbolic analysis (fill-reducing ordering: CHOLMOD's choice), of a second one
// (only the method that won the first), of the numeric factorisation and of a solve, for the solver the
// case asks for as fibrane builds it (for a model with point moments: with the symmetry probe) and for the
// symmetric chain alone (the difference is the probe's cost).
#include <omp.h>

#include <chrono>
#include <fmt/format.h>
#include <iostream>
#include <string>
#include <vector>

#include "case_edit.hpp"
#include "case/case_reader.hpp"
#include "solve/linear_solver.hpp"

namespace {

double seconds(const auto& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: bench_linear_solver CASE.yaml [--threads N] [--replace FROM TO]...\n";
    return 2;
  }
  std::vector<std::pair<std::string, std::string>> edits;
  for (int i = 2; i < argc; ++i)
    if (!common_option(argc, argv, i, edits)) {
      std::cerr << "unknown argument " << argv[i] << "\n";
      return 2;
    }
  std::string path;
  try {
    path = edited_case(argv[1], edits);
  } catch (const std::exception& e) {
    std::cerr << e.what() << "\n";
    return 2;
  }
  auto c = fibrane::casefile::read_case(path);
  auto& m = *c.model;
  m.evaluate(m.initial_unknowns(), 0.0, true);
  const Eigen::SparseMatrix<double>& k = m.tangent();
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(k.rows());
  fmt::print("case {}: {} unknowns, {} matrix non-zeros, {} threads\n", argv[1], k.rows(), k.nonZeros(),
             omp_get_max_threads());
  fmt::print("| solver | first analysis | second analysis | factorisation | solve | factor non-zeros | analyses |\n");
  fmt::print("|---|---|---|---|---|---|---|\n");
  for (const bool symmetric : {m.symmetric(), true}) {
    auto solver = fibrane::solve::make_linear_solver(c.run.linear_solver, symmetric);
    bool ok = false;
    const double first = seconds([&] { solver->analyze(k); });
    const double second = seconds([&] { solver->analyze(k); });
    const double factor = seconds([&] { ok = solver->factorize(k); });
    Eigen::VectorXd x;
    const double solve = seconds([&] { x = solver->solve(b); });
    fmt::print("| {}{} | {:.3f} s | {:.3f} s | {:.3f} s | {:.3f} s | {} | {} |\n", solver->name(), ok ? "" : " (failed)",
               first, second, factor, solve, solver->factor_nonzeros(), solver->analysis_summary());
  }
  return 0;
}
