// The memory estimate follows the solver path a case takes: an LU holds 2.2 times a Cholesky factor,
// single precision halves it, Krylov solves add GMRES's basis; the checks while bodies are read take the
// lightest path (0.5).
#include <gtest/gtest.h>

#include "case/case_limits.hpp"

namespace fibrane::casefile {
namespace {

TEST(SolverPathSize, EstimateFollowsThePath) {
  ModelSize base = shell_size(300.0 * 300.0, 100.0 * 100.0, 4, 4, 5);
  EXPECT_DOUBLE_EQ(base.factor_scale, 0.5);
  const auto factor_bytes = [&](const solve::LinearSolverSettings& s, bool symmetric) {
    ModelSize m = base;
    set_solver_path(m, s, symmetric);
    return m;
  };
  solve::LinearSolverSettings settings;
  const ModelSize cholesky = factor_bytes(settings, true), lu = factor_bytes(settings, false);
  EXPECT_DOUBLE_EQ(cholesky.factor_scale, 1.0);
  EXPECT_DOUBLE_EQ(lu.factor_scale, 2.2);
  EXPECT_GT(lu.bytes(), cholesky.bytes());
  EXPECT_NE(lu.path.find("LU"), std::string::npos);
  settings.precision = "single";
  const ModelSize single_lu = factor_bytes(settings, false);
  EXPECT_DOUBLE_EQ(single_lu.factor_scale, 1.1);
  EXPECT_GT(single_lu.vectors, 0.0);  // refined by Krylov solves
  EXPECT_NE(single_lu.path.find("single precision"), std::string::npos);
  // The difference in bytes is the factor's share: 12 bytes per Cholesky entry times the scale difference,
  // plus the Krylov vectors.
  EXPECT_NEAR(lu.bytes() - cholesky.bytes(), 12.0 * 1.2 * base.factor_nonzeros, 1e-6 * lu.bytes());
}

}  // namespace
}  // namespace fibrane::casefile
