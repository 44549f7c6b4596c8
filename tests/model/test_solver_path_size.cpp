// The memory estimate follows the solver path a case takes: an LU holds 2.2 times a Cholesky factor,
// single precision halves it, out of core keeps kOutOfCoreShare of it in memory, Krylov solves add GMRES's
// basis; the checks while bodies are read take the lightest path (single precision out of core). The path
// is chosen before the model is finalised, so the model's symmetry must be known then. The estimate's
// matrix pattern is counted from the knot vectors, and its peaks follow measured runs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "case/case_limits.hpp"
#include "model/beam_body.hpp"
#include "model/loads.hpp"
#include "model/model.hpp"
#include "spline/curve.hpp"
#include "spline/knot_vector.hpp"

namespace fibrane::casefile {
namespace {

// Two basis functions share an element when their supports [t_i, t_{i+p+1}] overlap in an interval of
// positive length: the definition direction_pattern's single pass over the element spans must reproduce.
double pairs_by_supports(const spline::KnotVector& k) {
  const auto& t = k.knots();
  const int n = k.num_basis(), p = k.degree();
  double pairs = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (std::min(t[i + p + 1], t[j + p + 1]) - std::max(t[i], t[j]) > k.tolerance()) ++pairs;
  return pairs;
}

TEST(SolverPathSize, PatternCountsTheFunctionsThatShareAnElement) {
  // Uniform knot vectors of every continuity, and one with a repeated interior knot and unequal spans.
  for (int p = 1; p <= 5; ++p)
    for (int c = 0; c < p; ++c)
      for (int n : {1, 2, 7}) {
        const auto k = spline::KnotVector::open_uniform(p, n, c);
        const DirectionPattern d = direction_pattern(k);
        EXPECT_EQ(d.functions, k.num_basis());
        EXPECT_EQ(d.pairs, pairs_by_supports(k)) << "p " << p << " c " << c << " n " << n;
      }
  const spline::KnotVector graded(3, {0, 0, 0, 0, 0.1, 0.3, 0.3, 0.6, 0.6, 0.6, 1, 1, 1, 1});
  EXPECT_EQ(direction_pattern(graded).pairs, pairs_by_supports(graded));
  // The C1 quartic direction of the bending meshes: 7 neighbours per function away from the ends (5 for
  // the function inside an element, 8 for the two at a knot of multiplicity 3), against 2p + 1 = 9 at
  // maximal continuity; the ends' functions have fewer (6.983 on average over 602 functions).
  const auto c1 = direction_pattern(spline::KnotVector::open_uniform(4, 200, 1));
  EXPECT_NEAR(c1.pairs / c1.functions, 7.0, 0.02);
}

TEST(SolverPathSize, EstimateFollowsThePath) {
  const DirectionPattern u = direction_pattern(spline::KnotVector::open_uniform(4, 100, 3));
  ModelSize base = shell_size(u, u, 100.0 * 100.0, 25);
  EXPECT_DOUBLE_EQ(base.factor_scale, kLightestFactorScale);
  EXPECT_EQ(base.dofs, 3.0 * 104 * 104);  // 100 + 4 quartic C3 functions per direction
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
  // The difference in bytes is the factor phase's share: kFactorPhase times 12 bytes per Cholesky entry
  // times the scale difference.
  EXPECT_NEAR(lu.bytes() - cholesky.bytes(), kFactorPhase * 12.0 * 1.2 * base.factor_nonzeros, 1e-6 * lu.bytes());
  // Out of core: MUMPS on both paths (LDL^T 1.1, LU 2.2), of which kOutOfCoreShare stays in memory.
  settings.precision = "double";
  settings.out_of_core_directory = "/tmp";
  const ModelSize disk_lu = factor_bytes(settings, -1), disk_ldlt = factor_bytes(settings, 0);
  EXPECT_DOUBLE_EQ(disk_lu.factor_scale, 2.2 * kOutOfCoreShare);
  EXPECT_DOUBLE_EQ(disk_ldlt.factor_scale, 1.1 * kOutOfCoreShare);
  EXPECT_DOUBLE_EQ(disk_lu.vectors, 0.0);
  EXPECT_NE(disk_lu.path.find("out of core"), std::string::npos);
  EXPECT_LT(disk_lu.bytes(), cholesky.bytes());
  // Out of core where needed: the in-memory path's scale (CHOLMOD's LL^T), and MUMPS's out-of-core one
  // for what does not fit. The case needs the latter's memory; its peak lies between the two, bounded
  // by the machine's.
  settings.out_of_core_when_needed = true;
  const ModelSize spill = factor_bytes(settings, 0);
  EXPECT_DOUBLE_EQ(spill.factor_scale, 1.0);
  EXPECT_DOUBLE_EQ(spill.spill_scale, 1.1 * kOutOfCoreShare);
  EXPECT_DOUBLE_EQ(spill.bytes(), cholesky.bytes());
  EXPECT_DOUBLE_EQ(spill.least_bytes(), disk_ldlt.bytes());
  EXPECT_DOUBLE_EQ(spill.peak_bytes(1e30), spill.bytes());
  EXPECT_DOUBLE_EQ(spill.peak_bytes(0), spill.least_bytes());
  const double between = 0.5 * (spill.bytes() + spill.least_bytes());
  EXPECT_DOUBLE_EQ(spill.peak_bytes(between), between);
  EXPECT_DOUBLE_EQ(disk_ldlt.peak_bytes(0), disk_ldlt.bytes());
  EXPECT_DOUBLE_EQ(factor_bytes(settings, -1).spill_scale, 2.2 * kOutOfCoreShare);
}

// The estimate against the whole runs' peak memory (maximum resident set) of the full bending membrane
// (examples/bending-full.yaml and bench/cases/bending-full-{278k,1m}.yaml: quartic C1 shell of N x N
// elements, fiber of 4N; "auto" with a low-rank skew correction), measured with 2 threads
// (docs/performance.md, "The memory estimate"): within -25 % and +40 % at 47 k and 278 k unknowns. At
// 1.1 M the run in memory was ended by the system's out-of-memory killer at 22.7 GiB on the 23.5 GiB
// development machine: the estimate must refuse it there, and let it through out of core (11.5 GiB), also
// out of core where needed (least_bytes()).
TEST(SolverPathSize, EstimateTracksTheMeasuredPeaks) {
  const auto estimate = [](int n, const solve::LinearSolverSettings& settings) {
    const DirectionPattern u = direction_pattern(spline::KnotVector::open_uniform(4, n, 1));
    const DirectionPattern fiber = direction_pattern(spline::KnotVector::open_uniform(4, 4 * n, 1));
    ModelSize size = shell_size(u, u, n * n, 25);
    size += beam_size(fiber, 4 * n, 5);
    set_solver_path(size, settings, 13);
    const double gib = size.least_bytes() / (1ull << 30);
    std::printf("    %d x %d, %s: %.3g unknowns, %.3g non-zeros, %.3g factor entries, %.2f GiB estimated\n", n,
                n, size.path.c_str(), size.dofs, size.nonzeros, size.factor_nonzeros, gib);
    return gib;
  };
  const solve::LinearSolverSettings in_memory;
  solve::LinearSolverSettings on_disk;
  on_disk.out_of_core_directory = "/tmp";
  struct Run {
    int n;
    const solve::LinearSolverSettings& settings;
    double peak_gib;
  };
  for (const Run& run : {Run{40, in_memory, 1.10}, Run{100, in_memory, 5.88}, Run{200, on_disk, 11.50}}) {
    const double gib = estimate(run.n, run.settings);
    EXPECT_GT(gib, 0.75 * run.peak_gib);
    EXPECT_LT(gib, 1.4 * run.peak_gib);
  }
  EXPECT_GT(estimate(200, in_memory), 23.5);
  // Out of core where needed, the 1.1 M membrane is let through: it needs what the run out of core needs.
  solve::LinearSolverSettings when_needed = on_disk;
  when_needed.out_of_core_when_needed = true;
  EXPECT_LT(estimate(200, when_needed), 23.5);
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
