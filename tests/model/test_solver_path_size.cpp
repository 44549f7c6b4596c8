// The memory estimate follows the solver path a case takes: an LU holds 2.2 times a Cholesky factor,
// single precision halves it, out of core keeps kOutOfCoreShare of it in memory, Krylov solves add GMRES's
// basis; the checks while bodies are read take the lightest path (0.5). The path is chosen before the
// model is finalised, so the model's symmetry must be known then.
#include <gtest/gtest.h>

#include "case/case_limits.hpp"
#include "model/beam_body.hpp"
#include "model/loads.hpp"
#include "model/model.hpp"
#include "spline/curve.hpp"
#include "spline/knot_vector.hpp"

namespace fibrane::casefile {
namespace {

TEST(SolverPathSize, EstimateFollowsThePath) {
  ModelSize base = shell_size(300.0 * 300.0, 100.0 * 100.0, 4, 4, 5);
  EXPECT_DOUBLE_EQ(base.factor_scale, 0.5);
  // skew_rows: 0 symmetric, -1 any number (an LU).
  const auto factor_bytes = [&](const solve::LinearSolverSettings& s, int skew_rows) {
    ModelSize m = base;
    set_solver_path(m, s, skew_rows);
    return m;
  };
  solve::LinearSolverSettings settings;
  const ModelSize cholesky = factor_bytes(settings, 0), lu = factor_bytes(settings, -1);
  // A skew part on few rows (point moments): "auto" factorises the symmetric part.
  const ModelSize corrected = factor_bytes(settings, 20);
  EXPECT_DOUBLE_EQ(corrected.factor_scale, 1.0);
  EXPECT_NE(corrected.path.find("low-rank correction"), std::string::npos);
  EXPECT_DOUBLE_EQ(factor_bytes(settings, solve::kMaxSkewRows + 1).factor_scale, 2.2);
  EXPECT_DOUBLE_EQ(cholesky.factor_scale, 1.0);
  EXPECT_DOUBLE_EQ(lu.factor_scale, 2.2);
  EXPECT_GT(lu.bytes(), cholesky.bytes());
  EXPECT_NE(lu.path.find("LU"), std::string::npos);
  settings.precision = "single";
  const ModelSize single_lu = factor_bytes(settings, -1);
  EXPECT_DOUBLE_EQ(single_lu.factor_scale, 1.1);
  EXPECT_GT(single_lu.vectors, 0.0);  // refined by Krylov solves
  EXPECT_NE(single_lu.path.find("single precision"), std::string::npos);
  // The difference in bytes is the factor's share: 12 bytes per Cholesky entry times the scale difference,
  // plus the Krylov vectors.
  EXPECT_NEAR(lu.bytes() - cholesky.bytes(), 12.0 * 1.2 * base.factor_nonzeros, 1e-6 * lu.bytes());
  // Out of core: MUMPS on both paths (LDL^T 1.1, LU 2.2), of which kOutOfCoreShare stays in memory.
  settings.precision = "double";
  settings.out_of_core_directory = "/tmp";
  const ModelSize disk_lu = factor_bytes(settings, -1), disk_ldlt = factor_bytes(settings, 0);
  EXPECT_DOUBLE_EQ(disk_lu.factor_scale, 2.2 * kOutOfCoreShare);
  EXPECT_DOUBLE_EQ(disk_ldlt.factor_scale, 1.1 * kOutOfCoreShare);
  EXPECT_DOUBLE_EQ(disk_lu.vectors, 0.0);
  EXPECT_NE(disk_lu.path.find("out of core"), std::string::npos);
  EXPECT_LT(disk_lu.bytes(), cholesky.bytes());
}

TEST(SolverPathSize, ModelKnowsItsSymmetryBeforeItIsFinalised) {
  model::Model m;
  const std::vector<Eigen::Vector3d> points = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
  spline::NurbsCurve curve(spline::KnotVector(3, {0, 0, 0, 0, 1, 1, 1, 1}), points);
  m.beams.emplace_back("fiber", curve, beam::BeamSection::circular(1000, 0.3, 0.1), Eigen::Vector3d::Zero());
  EXPECT_TRUE(m.symmetric());
  EXPECT_EQ(m.skew_rows(), 0);
  // An end moment's load stiffness is unsymmetric on the DOFs of the element it acts on (4 control points
  // of the cubic beam, 4 DOFs each).
  m.moments.emplace_back(m.beams.back(), 1.0, Eigen::Vector3d(0, 0, 1), 0);
  EXPECT_FALSE(m.symmetric());
  EXPECT_EQ(m.skew_rows(), 16);
}

}  // namespace
}  // namespace fibrane::casefile
