// The sparse solvers on a case's tangent at t = 0 (undeformed, after one evaluation), or at the state of a
// run's checkpoint (--state DIR: the output directory of a run of the same case, unfinished):
//   bench_linear_solver CASE.yaml [--threads N] [--replace FROM TO]... [--solver KIND]... [--shift S]
//                       [--rounds R] [--state DIR] [--without-window-fill]
// KIND: a kind of make_linear_solver (auto, cholmod, ldlt, mumps, mumps-lu, umfpack, umfpack64; "auto" as fibrane builds it for
// the case, i.e. with the symmetry probe for a model with point moments), cholmod-split (CHOLMOD's LL^T in domains
// below METIS's separators where the matrix is large enough, as steps.split makes it: as many domains as threads),
// cholmod-split-L (the same with L levels of separators, 2^L domains), cholmod-split-refine-F (a domain bisected
// again above F times an even share of the work: CholmodSplitOptions::refine_above), cholmod-split-shared (the last
// domain gets the finished ones' BLAS threads: CholmodSplitOptions::share_idle_cores), cholmod-whole (= cholmod),
// "symmetric-auto" (the symmetric
// chain alone), or MUMPS with another ordering or block low-rank: mumps-amd, mumps-amf, mumps-scotch,
// mumps-pord, mumps-qamd, mumps-blr (tolerance 1e-10), mumps-cholmod (CHOLMOD's pivot order, as "auto"
// gives it to MUMPS), mumps-c[-lu][-single][-blr][-ooc] (CHOLMOD's ordering; LU; single precision; block
// low-rank with dropping 1e-4; factor on disk in $TMPDIR or /tmp). Default: auto and symmetric-auto.
// --shift S factorises K - S d I instead of K, d the mean of K's diagonal (S > 0 makes it indefinite).
// --rounds R: the solvers take turns R times (each round builds every solver afresh), so that a machine
// shared with other jobs slows all of them alike; the table has each one's best and median.
// Printed per solver: the first symbolic analysis, a second one (CHOLMOD: only the ordering method that
// won the first), the numeric factorisation (wall, and the process's user and system CPU time), a second
// one of the same matrix (wall: what each later Newton iteration of the pattern costs), a solve,
// the factor's non-zeros, the negative eigenvalues reported, the solve's backward error |K x - b| / (|K| |x| + |b|) (infinity norms),
// with several rounds the largest relative change of the solution from the first round's (0: repeatable to
// the last bit), and the peak resident memory the solver added to the process (VmHWM, reset before each solver, less the resident
// size then; the largest over the rounds).
// --without-window-fill: the tangent without the soft windows' fill (drop_window_fill), with --state DIR.
#include <omp.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fmt/format.h>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "bench_state.hpp"
#include "case_edit.hpp"
#include "case/case_reader.hpp"
#include "linalg/cholmod_split.hpp"
#include "linalg/direct_solvers.hpp"
#include "linalg/linear_solver.hpp"
#include "linalg/skew_correction.hpp"
#include "linalg/symmetry_probe.hpp"
#include "run/process_environment.hpp"

namespace {

using fibrane::solve::LinearSolver;

// Wall, user and system seconds of a call.
struct Times {
  double wall = 0, user = 0, system = 0;
};

double seconds(const timeval& t) { return t.tv_sec + 1e-6 * t.tv_usec; }

Times measure(const auto& f) {
  rusage r0{}, r1{};
  getrusage(RUSAGE_SELF, &r0);
  const auto t0 = std::chrono::steady_clock::now();
  f();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  getrusage(RUSAGE_SELF, &r1);
  return {wall, seconds(r1.ru_utime) - seconds(r0.ru_utime), seconds(r1.ru_stime) - seconds(r0.ru_stime)};
}

// A field of /proc/self/status in MiB (VmRSS: resident now, VmHWM: its peak).
double status_mib(const std::string& field) {
  std::ifstream in("/proc/self/status");
  std::string key;
  double kib = 0;
  while (in >> key)
    if (key == field + ":") {
      in >> kib;
      break;
    }
  return kib / 1024;
}

// Resets VmHWM to the current resident size (Linux: writing 5 to /proc/self/clear_refs).
void reset_peak() { std::ofstream("/proc/self/clear_refs") << "5"; }

// The solver of a --solver KIND. "mumps-cholmod" (MUMPS with CHOLMOD's pivot order, as "auto" makes it)
// analyses `k` with CHOLMOD here, outside the times.
std::unique_ptr<LinearSolver> make_solver(const std::string& kind, const fibrane::solve::LinearSolverSettings& case_settings,
                                          bool symmetric, const Eigen::SparseMatrix<double>& k) {
  static const std::map<std::string, int> orderings = {
      {"mumps-amd", 0}, {"mumps-amf", 2}, {"mumps-scotch", 3}, {"mumps-pord", 4}, {"mumps-qamd", 6}};
  fibrane::solve::MumpsOptions options;
  if (const auto it = orderings.find(kind); it != orderings.end()) {
    options.ordering = it->second;
    return fibrane::solve::make_mumps(options);
  }
  if (kind == "mumps-blr") {
    options.low_rank = true;
    return fibrane::solve::make_mumps(options);
  }
  // "mumps-c[-lu][-single][-blr][-ooc]": MUMPS with CHOLMOD's ordering per analysis, LU or LDL^T, single
  // or double precision, block low-rank (dropping 1e-4) or full rank, out of core (in $TMPDIR, else /tmp).
  if (kind.rfind("mumps-c", 0) == 0 && kind != "mumps-cholmod") {
    options.cholmod_ordering = true;
    options.unsymmetric = kind.find("-lu") != std::string::npos;
    options.single_precision = kind.find("-single") != std::string::npos;
    options.low_rank = kind.find("-blr") != std::string::npos;
    options.low_rank_tolerance = 1e-4;
    if (kind.find("-ooc") != std::string::npos) {
      const char* tmp = std::getenv("TMPDIR");
      options.out_of_core_directory = tmp && *tmp ? tmp : "/tmp";
    }
    return fibrane::solve::make_mumps(options);
  }
  if (kind == "mumps-cholmod") {
    auto llt = fibrane::solve::make_cholmod_llt();
    llt->analyze(k);
    options.pivot_order = fibrane::solve::cholmod_pivot_order(*llt);
    return fibrane::solve::make_mumps(options);
  }
  if (kind == "cholmod-split") return fibrane::solve::make_cholmod_split_llt();
  if (kind == "cholmod-split-shared") return fibrane::solve::make_cholmod_split_llt({.share_idle_cores = true});
  if (kind.rfind("cholmod-split-refine-", 0) == 0)  // cholmod-split-refine-F: CholmodSplitOptions::refine_above F
    return fibrane::solve::make_cholmod_split_llt({.refine_above = std::stod(kind.substr(21))});
  if (kind.rfind("cholmod-split-", 0) == 0)  // cholmod-split-L: L levels of nested dissection
    return fibrane::solve::make_cholmod_split_llt({.levels = std::stoi(kind.substr(14))});
  if (kind == "cholmod-whole") return fibrane::solve::make_cholmod_llt();
  if (kind == "symmetric-auto") return fibrane::solve::make_linear_solver(case_settings.kind, true);
  if (kind == "auto") return fibrane::solve::make_linear_solver(case_settings.kind, symmetric);
  return fibrane::solve::make_linear_solver(kind, true);
}

struct Row {
  std::string name, summary;
  std::vector<double> first, second, factor_wall, factor_user, factor_system, refactor, solve, memory;
  long factor_nonzeros = 0;
  int negative = -1;
  double residual = 0;
  bool ok = true;
  Eigen::VectorXd first_solution;  // the first round's
  double change = 0;               // the later rounds' largest |x - x_first|_inf / |x_first|_inf
};

// One round for one solver: analyse twice, factorise, solve, appended to `row`.
void run(Row& row, LinearSolver& solver, const Eigen::SparseMatrix<double>& k, const Eigen::VectorXd& b) {
  bool ok = false;
  Eigen::VectorXd x;
  row.first.push_back(measure([&] { solver.analyze(k); }).wall);
  row.second.push_back(measure([&] { solver.analyze(k); }).wall);
  const Times f = measure([&] { ok = solver.factorize(k); });
  row.factor_wall.push_back(f.wall);
  row.factor_user.push_back(f.user);
  row.factor_system.push_back(f.system);
  row.refactor.push_back(measure([&] { ok = solver.factorize(k) && ok; }).wall);
  row.solve.push_back(measure([&] { x = solver.solve(b); }).wall);
  row.name = solver.name();
  row.summary = solver.analysis_summary();
  row.factor_nonzeros = solver.factor_nonzeros();
  row.negative = solver.negative_eigenvalues();
  row.ok = row.ok && ok;
  // Normwise backward error |K x - b| / (|K| |x| + |b|) in the infinity norm (K holds both triangles).
  const Eigen::VectorXd r = k * x - b;
  const double k_norm = (k.cwiseAbs() * Eigen::VectorXd::Ones(k.cols())).maxCoeff();
  row.residual = ok ? r.lpNorm<Eigen::Infinity>() / (k_norm * x.lpNorm<Eigen::Infinity>() + b.lpNorm<Eigen::Infinity>()) : 0.0;
  if (row.first_solution.size() == 0) row.first_solution = x;
  else if (ok)
    row.change = std::max(row.change, (x - row.first_solution).lpNorm<Eigen::Infinity>() /
                                          row.first_solution.lpNorm<Eigen::Infinity>());
}

// "best / median" of the rounds.
std::string best_median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  if (v.size() == 1) return fmt::format("{:.3f}", v[0]);
  return fmt::format("{:.3f} / {:.3f}", v.front(), v[v.size() / 2]);
}

}  // namespace

// --without-window-fill: removes from k (the tangent of c's model at a state) the entries that join two shell
// unknowns and that the tangent at t = 0 lacks. A shell element's own entries, and every entry of a beam
// row, are in both; what is left out is the fill of the soft points' dense rank-one terms s m m^T over
// their windows (interaction/soft_distance.cpp), which join window control points of different elements.
// The matrix so made is not the tangent (the terms' entries within an element stay): it measures what a
// factorisation without the windows' fill would cost.
void drop_window_fill(const std::string& path, const fibrane::model::Model& m, Eigen::SparseMatrix<double>& k) {
  auto start = fibrane::casefile::read_case(path);
  evaluate_at_state(start, "", true);
  const Eigen::SparseMatrix<double>& k0 = start.model->tangent();
  std::vector<char> beam(static_cast<size_t>(k.rows()), 0);  // rows of blocks of 4 DOFs per node: beams
  for (int i = 0; i < k.rows(); ++i) {
    const int dof = m.constraints.free_dof(i);
    for (int b = 0; b < m.dofs.num_blocks(); ++b)
      if (dof >= m.dofs.block_offset(b) && dof < m.dofs.block_offset(b) + m.dofs.block_size(b))
        beam[static_cast<size_t>(i)] = m.dofs.dofs_per_node(b) == 4;
  }
  auto in_start = [&](int i, int j) {
    const int* first = k0.innerIndexPtr() + k0.outerIndexPtr()[j];
    return std::binary_search(first, k0.innerIndexPtr() + k0.outerIndexPtr()[j + 1], i);
  };
  std::vector<Eigen::Triplet<double>> kept;
  kept.reserve(static_cast<size_t>(k0.nonZeros()));
  for (int j = 0; j < k.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(k, j); it; ++it) {
      const int i = static_cast<int>(it.row());
      if (beam[static_cast<size_t>(i)] || beam[static_cast<size_t>(j)] || in_start(i, j))
        kept.emplace_back(i, j, it.value());
    }
  fmt::print("without the windows' fill: {} of {} entries dropped (t = 0: {} entries)\n",
             k.nonZeros() - static_cast<long>(kept.size()), k.nonZeros(), k0.nonZeros());
  k.setFromTriplets(kept.begin(), kept.end());
}

int run_bench(int argc, char** argv) {
  fibrane::run::configure_process_environment(argc, argv);  // the environment of `fibrane run`
  const char* usage =
      "usage: bench_linear_solver CASE.yaml [--threads N] [--replace FROM TO]... [--solver KIND]... [--shift S] "
      "[--rounds R] [--state DIR] [--without-window-fill]\n  analysis, factorisation and solve of the case's first tangent, or its tangent at the "
      "checkpoint in DIR (shifted by -S mean(diag) I)\n";
  std::vector<std::string> kinds;
  double shift = 0;
  int rounds = 1, code = 0;
  std::string state;
  bool without_window_fill = false;
  const auto path = case_arguments(argc, argv, usage, [&](const std::string& a, int& i) {
    if (a == "--without-window-fill") return without_window_fill = true;
    if (i + 1 >= argc) return false;
    if (a == "--solver") kinds.emplace_back(argv[++i]);
    else if (a == "--shift") shift = std::stod(argv[++i]);
    else if (a == "--rounds") rounds = std::max(1, std::stoi(argv[++i]));
    else if (a == "--state") state = argv[++i];
    else return false;
    return true;
  }, code);
  if (!path) return code;
  if (kinds.empty()) kinds = {"auto", "symmetric-auto"};
  auto c = fibrane::casefile::read_case(*path);
  auto& m = *c.model;
  evaluate_at_state(c, state, true);
  Eigen::SparseMatrix<double> k = m.tangent();
  if (without_window_fill) drop_window_fill(*path, m, k);
  const double mean_diagonal = k.diagonal().mean();
  if (shift != 0) k.diagonal().array() -= shift * mean_diagonal;
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(k.rows());
  fmt::print("case {}: {} unknowns, {} matrix non-zeros, {} threads (BLAS {}), shift {} x mean diagonal {:.6g}, "
             "resident {:.0f} MiB (peak {:.0f}) before the solvers\n",
             argv[1], k.rows(), k.nonZeros(), omp_get_max_threads(), fibrane::solve::blas_thread_count(), shift,
             mean_diagonal, status_mib("VmRSS"), status_mib("VmHWM"));
  {  // the passes of "auto" over an unsymmetric-capable model's matrix before each factorisation
    fibrane::solve::SymmetryProbe probe;
    std::vector<int> support;
    const double build = measure([&] { probe.build(k); }).wall;
    bool symmetric = false;
    const double check = measure([&] { symmetric = probe.symmetric(k); }).wall;
    const double classify = measure([&] { support = probe.skew_support(k); }).wall;
    // The skew path's S, written into k's block and put back, against a copy of the matrix for it.
    fibrane::solve::SkewCorrection correction;
    const double in_place = measure([&] { correction.symmetrize(k, support), correction.restore(k); }).wall;
    Eigen::SparseMatrix<double> copy;
    const double copied = measure([&] { copy = k; }).wall;
    copy.resize(0, 0);
    copy.data().squeeze();
    fmt::print("symmetry probe: map {:.3f} s, symmetric {:.3f} s ({}), skew support {:.3f} s ({} rows); S in place and "
               "back {:.6f} s (a copy of the matrix {:.3f} s)\n",
               build, check, symmetric, classify, support.size(), in_place, copied);
    if (const auto candidates = m.skew_candidates()) {  // what fibrane's analyses give the probe
      fibrane::solve::SymmetryProbe rows;
      const double rows_build = measure([&] { rows.build(k, *candidates); }).wall;
      const double rows_classify = measure([&] { support = rows.skew_support(k); }).wall;
      fmt::print("symmetry probe of the model's {} skew candidate rows: map {:.6f} s, skew support {:.6f} s ({} rows)\n",
                 candidates->size(), rows_build, rows_classify, support.size());
    }
  }
  std::vector<Row> rows(kinds.size());
  for (int round = 0; round < rounds; ++round)
    for (size_t s = 0; s < kinds.size(); ++s) {
      reset_peak();
      const double resident = status_mib("VmRSS");
      auto solver = make_solver(kinds[s], c.run.linear_solver, m.symmetric(), k);
      run(rows[s], *solver, k, b);
      rows[s].memory.push_back(status_mib("VmHWM") - resident);
    }
  fmt::print("times in s{}\n", rounds > 1 ? fmt::format(", best / median of {} rounds", rounds) : "");
  fmt::print("| solver | first analysis | second analysis | factorisation wall | user | system | refactorisation | "
             "solve | factor non-zeros | negative eigenvalues | backward error | change from round 1 | peak memory [MiB] | "
             "analyses |\n");
  fmt::print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Row& r : rows)
    fmt::print("| {}{} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.1e} | {} | {:.0f} | {} |\n", r.name,
               r.ok ? "" : " (failed)", best_median(r.first), best_median(r.second), best_median(r.factor_wall),
               best_median(r.factor_user), best_median(r.factor_system), best_median(r.refactor), best_median(r.solve),
               r.factor_nonzeros,
               r.negative, r.residual, rounds > 1 ? fmt::format("{:.1e}", r.change) : "-", *std::max_element(r.memory.begin(), r.memory.end()), r.summary);
  return 0;
}

int main(int argc, char** argv) { return guarded_main(argc, argv, run_bench); }
