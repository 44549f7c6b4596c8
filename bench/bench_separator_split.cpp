// What parallelism across the elimination tree would give the symmetric factorisation: a case's first
// tangent K, split by METIS's node bisector (cholmod_bisect) into two interiors I0, I1 and a separator S, and
//   - K factorised whole by fibrane's CHOLMOD LL^T with the BLAS threads of the run (--threads N),
//   - the two halves K[I0+S, I0+S] and K[I1+S, I1+S] factorised side by side, one thread and one BLAS
//     thread each,
// each factorised twice after its analysis (the second is what a Newton iteration of the pattern costs).
// The halves' factors hold what a split solver needs but the separator's dense Schur complement
// (S x S: T0 + T1 - K_SS, Tk the trailing block's L L^T of half k), whose LL^T is timed on its own (Eigen).
//   bench_separator_split CASE.yaml [--threads N] [--replace FROM TO]...
#include <omp.h>

#include <Eigen/Cholesky>
#include <Eigen/CholmodSupport>
#include <chrono>
#include <fmt/format.h>
#include <vector>

#include "case_edit.hpp"
#include "case/case_reader.hpp"
#include "linalg/direct_solvers.hpp"
#include "linalg/linear_solver.hpp"
#include "run/process_environment.hpp"

namespace {

using SpMat = Eigen::SparseMatrix<double>;
using fibrane::solve::LinearSolver;

double seconds_of(const auto& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// K's rows and columns `keep` (in that order), both triangles as K has them.
SpMat submatrix(const SpMat& k, const std::vector<int>& keep) {
  std::vector<int> local(static_cast<std::size_t>(k.rows()), -1);
  for (std::size_t i = 0; i < keep.size(); ++i) local[static_cast<std::size_t>(keep[i])] = static_cast<int>(i);
  std::vector<Eigen::Triplet<double>> t;
  for (std::size_t c = 0; c < keep.size(); ++c)
    for (SpMat::InnerIterator it(k, keep[c]); it; ++it)
      if (const int r = local[static_cast<std::size_t>(it.row())]; r >= 0) t.emplace_back(r, static_cast<int>(c), it.value());
  SpMat s(static_cast<Eigen::Index>(keep.size()), static_cast<Eigen::Index>(keep.size()));
  s.setFromTriplets(t.begin(), t.end());
  return s;
}

// Seconds of the analysis, the first and the second factorisation of `a`.
struct Timed {
  double analysis = 0, first = 0, second = 0;
  bool ok = true;
};

Timed factorise_twice(LinearSolver& solver, const SpMat& a) {
  Timed t;
  t.analysis = seconds_of([&] { solver.analyze(a); });
  t.first = seconds_of([&] { t.ok = solver.factorize(a); });
  t.second = seconds_of([&] { t.ok = solver.factorize(a) && t.ok; });
  return t;
}

}  // namespace

int run_bench(int argc, char** argv) {
  fibrane::run::configure_process_environment(argc, argv);  // the environment of `fibrane run`
  const char* usage = "usage: bench_separator_split CASE.yaml [--threads N] [--replace FROM TO]...\n";
  int code = 0;
  const auto path = case_arguments(argc, argv, usage, [](const std::string&, int&) { return false; }, code);
  if (!path) return code;
  auto c = fibrane::casefile::read_case(*path);
  auto& m = *c.model;
  m.evaluate(m.initial_unknowns(), 0.0, true);
  const SpMat k = m.tangent();

  // METIS's node bisector of K's graph (the lower triangle, as CHOLMOD reads a symmetric matrix).
  std::vector<int> partition(static_cast<std::size_t>(k.rows()));
  cholmod_common common;
  cholmod_start(&common);
  cholmod_sparse view = Eigen::viewAsCholmod(k.selfadjointView<Eigen::Lower>());
  const long separator = cholmod_bisect(&view, nullptr, 0, 1, partition.data(), &common);
  cholmod_finish(&common);
  std::vector<int> half[2], sep;
  for (int i = 0; i < k.rows(); ++i) (partition[static_cast<std::size_t>(i)] == 2 ? sep : half[partition[static_cast<std::size_t>(i)]]).push_back(i);
  for (auto& h : half) h.insert(h.end(), sep.begin(), sep.end());
  fmt::print("{}: {} unknowns, {} matrix non-zeros; halves {} and {} unknowns with the separator of {} ({})\n",
             *path, k.rows(), k.nonZeros(), half[0].size(), half[1].size(), sep.size(), separator);

  auto whole = fibrane::solve::make_cholmod_llt();
  const Timed w = factorise_twice(*whole, k);
  fmt::print("whole, {} threads: analysis {:.3f} s, factorisation {:.3f} s, again {:.3f} s, {} factor entries{}\n",
             omp_get_max_threads(), w.analysis, w.first, w.second, whole->factor_nonzeros(), w.ok ? "" : " (failed)");
  whole.reset();

  const SpMat parts[2] = {submatrix(k, half[0]), submatrix(k, half[1])};
  std::unique_ptr<LinearSolver> solvers[2] = {fibrane::solve::make_cholmod_llt(), fibrane::solve::make_cholmod_llt()};
  Timed h[2];
  double side_by_side = 0;
  {
    const fibrane::solve::BlasThreadsForFactor one_blas_thread(0);  // a factor of no entries: one BLAS thread
    side_by_side = seconds_of([&] {
#pragma omp parallel for num_threads(2) schedule(static, 1)
      for (int i = 0; i < 2; ++i) h[i] = factorise_twice(*solvers[i], parts[i]);
    });
  }
  for (int i = 0; i < 2; ++i)
    fmt::print("half {}: analysis {:.3f} s, factorisation {:.3f} s, again {:.3f} s, {} factor entries{}\n", i,
               h[i].analysis, h[i].first, h[i].second, solvers[i]->factor_nonzeros(), h[i].ok ? "" : " (failed)");
  fmt::print("side by side: {:.3f} s in all; the second factorisations {:.3f} s at the longer\n", side_by_side,
             std::max(h[0].second, h[1].second));

  // The separator's dense LL^T, on a matrix of its size that is positive definite.
  const auto s = static_cast<Eigen::Index>(sep.size());
  Eigen::MatrixXd dense = Eigen::MatrixXd::Random(s, s);
  dense = dense * dense.transpose() + static_cast<double>(s) * Eigen::MatrixXd::Identity(s, s);
  Eigen::LLT<Eigen::MatrixXd> llt;
  fmt::print("separator's dense LL^T ({} x {}): {:.3f} s\n", s, s, seconds_of([&] { llt.compute(dense); }));
  return 0;
}

int main(int argc, char** argv) { return guarded_main(argc, argv, run_bench); }
