// MUMPS out of core (steps.out_of_core): the factor lives in files of the given directory while the solver
// holds it, the solutions are the in-core factorisation's, and the files are gone with the factor.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "grid_matrix.hpp"
#include "linalg/direct_solvers.hpp"
#include "linalg/linear_solver.hpp"

namespace fibrane::solve {
namespace {

namespace fs = std::filesystem;

// A fresh, empty directory for one test's factor files.
fs::path empty_directory(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("fibrane-ooc-test-" + std::to_string(::getpid()) + "-" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// Files in `dir` and their bytes together.
std::pair<int, std::uintmax_t> files_in(const fs::path& dir) {
  int n = 0;
  std::uintmax_t bytes = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    ++n;
    bytes += e.file_size();
  }
  return {n, bytes};
}

TEST(OutOfCore, LuSolvesAsInCoreWithTheFactorOnDisk) {
  if (!mumps_available()) GTEST_SKIP() << "built without MUMPS";
  const fs::path dir = empty_directory("lu");
  // An unsymmetric convection-diffusion matrix (90 000 unknowns, diagonally dominant: well conditioned), and
  // a nearby one of the same pattern.
  const Eigen::SparseMatrix<double> a = grid_matrix(300, 1.0, 0.5, 0.1, 1);
  const Eigen::SparseMatrix<double> a2 = grid_matrix(300, 1.0, 0.5, 0.1, 2);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(a.rows(), -1.0, 2.0);
  MumpsOptions in_core;
  in_core.unsymmetric = true;
  in_core.cholmod_ordering = true;
  MumpsOptions on_disk = in_core;
  on_disk.out_of_core_directory = dir.string();
  {
    auto reference = make_mumps(in_core);
    auto solver = make_mumps(on_disk);
    EXPECT_EQ(solver->name(), "mumps-lu-ooc");
    for (const auto* m : {&a, &a2}) {  // two factorisations with one analysis: the second replaces the first's files
      reference->analyze(*m);
      ASSERT_TRUE(reference->factorize(*m));
      if (m == &a) solver->analyze(*m);
      ASSERT_TRUE(solver->factorize(*m)) << solver->failure_detail();
      const auto [files, bytes] = files_in(dir);
      EXPECT_GE(files, 1);
      // The factor's entries in double precision are on disk (MUMPS writes L and U blocks as they are done).
      EXPECT_GE(static_cast<double>(bytes), 8.0 * 0.9 * static_cast<double>(solver->factor_nonzeros()));
      EXPECT_EQ(solver->factor_nonzeros(), reference->factor_nonzeros());
      const Eigen::VectorXd x = solver->solve(b), x_ref = reference->solve(b);
      // Both are backward-stable solves of the same pivot sequence: they agree to round-off times the
      // condition number (a few units for this matrix), far below 1e-10.
      EXPECT_LT((x - x_ref).norm() / x_ref.norm(), 1e-10);
      EXPECT_LT((*m * x - b).norm() / b.norm(), 1e-12);
    }
    EXPECT_NE(solver->analysis_summary().find("factor on disk"), std::string::npos) << solver->analysis_summary();
  }
  EXPECT_EQ(files_in(dir).first, 0) << "the factor files outlive the solver";
  fs::remove_all(dir);
}

TEST(OutOfCore, CaseSettingsTakeMumpsOnBothPaths) {
  if (!mumps_available()) GTEST_SKIP() << "built without MUMPS";
  const fs::path dir = empty_directory("settings");
  LinearSolverSettings settings;
  settings.out_of_core_directory = dir.string();
  // A symmetric positive definite matrix: the symmetric chain is MUMPS's LDL^T out of core, not CHOLMOD's
  // LL^T (which has no out-of-core mode).
  const Eigen::SparseMatrix<double> spd = grid_matrix(60, 0.1, 0.0);
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(spd.rows());
  {
    auto solver = make_linear_solver(settings, true);
    solver->analyze(spd);
    ASSERT_TRUE(solver->factorize(spd));
    EXPECT_EQ(solver->name(), "mumps-ooc");
    EXPECT_EQ(solver->negative_eigenvalues(), 0);
    EXPECT_LT((spd * solver->solve(b) - b).norm() / b.norm(), 1e-12);
    EXPECT_GE(files_in(dir).first, 1);
  }
  // A model that cannot promise symmetry: the symmetry probe picks the LU for an unsymmetric matrix.
  const Eigen::SparseMatrix<double> unsym = grid_matrix(60, 0.1, 0.5);
  {
    auto solver = make_linear_solver(settings, false);
    solver->analyze(unsym);
    ASSERT_TRUE(solver->factorize(unsym));
    EXPECT_EQ(solver->name(), "mumps-lu-ooc");
    EXPECT_LT((unsym * solver->solve(b) - b).norm() / b.norm(), 1e-12);
  }
  EXPECT_EQ(files_in(dir).first, 0);
  // Single precision out of core: refined in double precision; its fallback stays out of core.
  settings.precision = "single";
  {
    auto solver = make_linear_solver(settings, false);
    solver->analyze(unsym);
    ASSERT_TRUE(solver->factorize(unsym));
    EXPECT_NE(solver->name().find("mumps-lu-single-ooc"), std::string::npos) << solver->name();
    EXPECT_LT((unsym * solver->solve(b) - b).norm() / b.norm(), 1e-8);
  }
  EXPECT_EQ(files_in(dir).first, 0);
  fs::remove_all(dir);
}

// The megabytes in a MUMPS solver's analysis_summary() ("1 with the given order, 61 MB"): before a
// factorisation, the analysis's estimate of its memory, in core or out of core as the solver's mode is.
long summary_megabytes(const LinearSolver& solver) {
  const std::string summary = solver.analysis_summary();
  const auto end = summary.find(" MB");
  const auto start = summary.rfind(' ', end - 1);
  return std::stol(summary.substr(start + 1, end - start - 1));
}

// out_of_core_when_needed: without a memory limit the factor stays in memory (no files); with a limit
// between the out-of-core and the in-core estimates (each with MUMPS's margin of a tenth) it goes to the
// files. Either way the solution is the in-core factorisation's (the same pivots), for the LDL^T and the
// LU, over two matrices of one analysis.
TEST(OutOfCore, WhenNeededKeepsInMemoryWhatFits) {
  if (!mumps_available()) GTEST_SKIP() << "built without MUMPS";
  const fs::path dir = empty_directory("when-needed");
  const Eigen::SparseMatrix<double> a = grid_matrix(300, 0.5, 0.0, 0.1, 1), a2 = grid_matrix(300, 0.5, 0.0, 0.1, 2);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(a.rows(), -1.0, 2.0);
  for (const bool unsymmetric : {false, true}) {
    MumpsOptions in_core;
    in_core.unsymmetric = unsymmetric;
    in_core.cholmod_ordering = true;
    in_core.memory_limit_megabytes = 0;
    MumpsOptions on_disk = in_core;
    on_disk.out_of_core_directory = dir.string();
    auto probe_in = make_mumps(in_core), probe_disk = make_mumps(on_disk);
    probe_in->analyze(a);
    probe_disk->analyze(a);
    const long in_mb = summary_megabytes(*probe_in), disk_mb = summary_megabytes(*probe_disk);
    // 58 and 31 MB with Debian 12's MUMPS 5.5: the limit between them, 44 MB, is more than 1.1 x 31.
    ASSERT_GT(in_mb, 1.3 * disk_mb) << "the test needs an out-of-core estimate well below the in-core one";
    MumpsOptions when_needed = on_disk;
    when_needed.out_of_core_when_needed = true;
    for (const long limit : {0L, (in_mb + disk_mb) / 2}) {
      when_needed.memory_limit_megabytes = limit;
      auto solver = make_mumps(when_needed);
      solver->analyze(a);
      for (const auto* m : {&a, &a2}) {
        probe_in->factorize(*m);
        ASSERT_TRUE(solver->factorize(*m)) << solver->failure_detail();
        const Eigen::VectorXd x = solver->solve(b), x_ref = probe_in->solve(b);
        EXPECT_LE((x - x_ref).norm(), 1e-14 * x_ref.norm());
        const bool spilled = limit > 0;
        EXPECT_EQ(solver->name(), std::string(unsymmetric ? "mumps-lu" : "mumps") + (spilled ? "-ooc" : ""));
        EXPECT_EQ(files_in(dir).first > 0, spilled) << "limit " << limit << " MB";
        EXPECT_EQ(solver->analysis_summary().find("factor on disk") != std::string::npos, spilled);
      }
    }
    EXPECT_EQ(files_in(dir).first, 0) << "the factor files outlive the solver";
  }
  fs::remove_all(dir);
}

// The case settings' out_of_core_when_needed keeps auto's chain: CHOLMOD's LL^T in memory where it fits;
// refused for memory (a limit below its factor), the matrix goes to MUMPS's LDL^T, out of core. A limit
// below MUMPS's out-of-core need too fails, naming it.
TEST(OutOfCore, WhenNeededSendsAnLltThatDoesNotFitToMumpsOnDisk) {
  if (!mumps_available()) GTEST_SKIP() << "built without MUMPS";
  const fs::path dir = empty_directory("auto-when-needed");
  const Eigen::SparseMatrix<double> spd = grid_matrix(300, 0.5, 0.0);
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(spd.rows());
  LinearSolverSettings settings;
  settings.out_of_core_directory = dir.string();
  settings.out_of_core_when_needed = true;
  {
    auto solver = make_linear_solver(settings, true);
    solver->analyze(spd);
    ASSERT_TRUE(solver->factorize(spd));
    EXPECT_EQ(solver->name(), "auto(cholmod)");
    EXPECT_EQ(files_in(dir).first, 0);
  }
  MumpsOptions disk;
  disk.cholmod_ordering = true;
  disk.out_of_core_directory = dir.string();
  auto probe = make_mumps(disk);
  probe->analyze(spd);
  const long disk_mb = summary_megabytes(*probe);
  probe.reset();
  // A limit just below CHOLMOD's need (38 MB with Debian 12's SuiteSparse, named in its refusal) and above
  // MUMPS's out-of-core estimate with its margin (31 MB and a tenth).
  auto refused = make_cholmod_llt(1);
  refused->analyze(spd);
  ASSERT_FALSE(refused->factorize(spd));
  const std::string refusal = refused->failure_detail();
  const auto need_at = refusal.find("would need ");
  ASSERT_NE(need_at, std::string::npos) << refusal;
  const long cholmod_mb = std::stol(refusal.substr(need_at + 11));
  settings.memory_limit_megabytes = cholmod_mb - 1;
  ASSERT_GT(static_cast<double>(settings.memory_limit_megabytes), 1.1 * disk_mb);
  {
    auto solver = make_linear_solver(settings, true);
    solver->analyze(spd);
    ASSERT_TRUE(solver->factorize(spd)) << solver->failure_detail();
    EXPECT_EQ(solver->name(), "auto(mumps-ooc)");
    EXPECT_EQ(solver->negative_eigenvalues(), 0);
    EXPECT_LT((spd * solver->solve(b) - b).norm() / b.norm(), 1e-12);
    EXPECT_GE(files_in(dir).first, 1);
  }
  EXPECT_EQ(files_in(dir).first, 0);
  settings.memory_limit_megabytes = 1;
  {
    auto solver = make_linear_solver(settings, true);
    solver->analyze(spd);
    EXPECT_FALSE(solver->factorize(spd));
    EXPECT_NE(solver->failure_detail().find("limit of 1 MB"), std::string::npos) << solver->failure_detail();
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace fibrane::solve
