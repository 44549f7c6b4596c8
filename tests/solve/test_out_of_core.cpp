// MUMPS out of core (steps.out_of_core): the factor lives in files of the given directory while the solver
// holds it, the solutions are the in-core factorisation's, and the files are gone with the factor.
#include <gtest/gtest.h>
#include <unistd.h>

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

}  // namespace
}  // namespace fibrane::solve
