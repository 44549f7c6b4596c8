// The memory limit of a factorisation (factorization_memory_limit): a factorisation that would need more
// than the limit fails, saying so, instead of growing until the system ends the process; within the limit
// it gives the unlimited factorisation's solution. The limits below are far below the factors (a few MB
// against tens of MB) or far above them, so the tests do not depend on this machine's free memory.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "common/system_memory.hpp"
#include "grid_matrix.hpp"
#include "linalg/direct_solvers.hpp"
#include "path/nonlinear.hpp"

namespace fibrane::solve {
namespace {

using SpMat = Eigen::SparseMatrix<double>;

// A 90 000-unknown grid matrix (grid_matrix.hpp): symmetric positive definite without convection, and
// the right-hand side of the checks.
const SpMat& spd_matrix() {
  static const SpMat a = grid_matrix(300, 0.5, 0.0);
  return a;
}
Eigen::VectorXd rhs(Eigen::Index n) { return Eigen::VectorXd::LinSpaced(n, -1.0, 2.0); }

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(MemoryLimit, TheProcessSeesItsMemory) {
  // /proc/meminfo is readable on Linux; what the process can take is at most the machine's memory plus
  // its allocator's free bytes (a few MB in a test).
  const double limit = static_cast<double>(memory_limit()), available = static_cast<double>(available_memory());
  EXPECT_GT(limit, 0);
  EXPECT_GT(available, 0);
  EXPECT_LT(available, limit + 1e9);
  EXPECT_GT(factorization_memory_limit(kAvailableMemory), 0);
  EXPECT_LT(factorization_memory_limit(kAvailableMemory), available);
  EXPECT_EQ(factorization_memory_limit(0), 0);
  EXPECT_EQ(factorization_memory_limit(3), 3.0 * (1 << 20));
}

// The megabytes in a MUMPS solver's analysis_summary() ("1 with METIS, 61 MB"): the analysis's estimate
// of the factorisation's memory before a factorisation.
long summary_megabytes(const LinearSolver& solver) {
  const std::string summary = solver.analysis_summary();
  const auto end = summary.find(" MB");
  const auto start = summary.rfind(' ', end - 1);
  return std::stol(summary.substr(start + 1, end - start - 1));
}

// MUMPS's factors of the matrix (LDL^T and LU) need ~30-60 MB: a 2 MB limit stops each before it
// allocates (INFOG(1) = -19). The automatic limit and a generous one leave MUMPS its own sizing; a limit
// at the analysis's estimate, below its margin of a tenth, makes MUMPS work within it (ICNTL(23)). Each
// gives the unlimited factorisation's solution to the last bits (the same pivots).
// Resident pages of this process (/proc/self/statm), in bytes.
double resident_bytes() {
  std::ifstream statm("/proc/self/statm");
  double size = 0, resident = 0;
  statm >> size >> resident;
  return resident * static_cast<double>(sysconf(_SC_PAGESIZE));
}

// hand_back_pages hands a buffer's whole pages back while the buffer stays allocated: the resident set
// shrinks by about its size (64 MB; at least 56 MB, since other allocations of the test process may
// fault in pages meanwhile), the pages read as zeros afterwards, and the first and last 4 KiB (the
// allocator's records next to them) keep their contents.
TEST(MemoryLimit, HandedBackPagesLeaveTheResidentSet) {
  const std::size_t bytes = std::size_t(64) << 20;
  std::vector<std::uint8_t> buffer(bytes, 7);
  const double before = resident_bytes();
  hand_back_pages(buffer.data(), bytes);
  const double after = resident_bytes();
  EXPECT_GT(before - after, 56.0 * (1 << 20));
  EXPECT_EQ(buffer.front(), 7);
  EXPECT_EQ(buffer[4095], 7);
  EXPECT_EQ(buffer.back(), 7);
  EXPECT_EQ(buffer[bytes / 2], 0);
  release_storage(buffer);
  EXPECT_EQ(buffer.capacity(), 0u);
}

// Freed memory goes back to the system only where the system has less available than the process would
// hold freed: a test process holds a few MB freed, far below any machine's available memory, and no machine
// has half the address space available. Where memory is plentiful release_pages keeps a 64 MB buffer's
// pages (resident, contents unchanged) for reuse.
TEST(MemoryLimit, FreedMemoryGoesBackOnlyWhereMemoryIsShort) {
  if (available_memory() < (std::uint64_t(1) << 30)) GTEST_SKIP() << "less than 1 GiB available";
  EXPECT_FALSE(hand_back_needed());
  EXPECT_FALSE(hand_back_needed(std::size_t(64) << 20));
  EXPECT_TRUE(hand_back_needed(std::numeric_limits<std::size_t>::max() / 2));
  const std::size_t bytes = std::size_t(64) << 20;
  std::vector<std::uint8_t> buffer(bytes, 7);
  const double before = resident_bytes();
  release_pages(buffer.data(), bytes);
  EXPECT_GT(resident_bytes() - before, -8.0 * (1 << 20));
  EXPECT_EQ(buffer[bytes / 2], 7);
}

TEST(MemoryLimit, MumpsStopsAtItsLimitAndSolvesWithinIt) {
  if (!mumps_available()) GTEST_SKIP() << "built without MUMPS";
  const SpMat& a = spd_matrix();
  const Eigen::VectorXd b = rhs(a.rows());
  for (const bool unsymmetric : {false, true}) {
    MumpsOptions options;
    options.cholmod_ordering = true;
    options.unsymmetric = unsymmetric;
    options.memory_limit_megabytes = 0;
    auto unlimited = make_mumps(options);
    unlimited->analyze(a);
    ASSERT_TRUE(unlimited->factorize(a)) << unlimited->failure_detail();
    const Eigen::VectorXd reference = unlimited->solve(b);
    auto probe = make_mumps(options);
    probe->analyze(a);
    const long estimate = summary_megabytes(*probe);
    EXPECT_GT(estimate, 10);
    for (const long megabytes : {kAvailableMemory, 4096L, estimate}) {
      options.memory_limit_megabytes = megabytes;
      auto solver = make_mumps(options);
      solver->analyze(a);
      ASSERT_TRUE(solver->factorize(a)) << solver->failure_detail();
      EXPECT_LE((solver->solve(b) - reference).norm(), 1e-14 * reference.norm());
      EXPECT_LE(summary_megabytes(*solver), megabytes == estimate ? estimate : 4096);  // INFOG(22): used
    }
    options.memory_limit_megabytes = 2;
    auto limited = make_mumps(options);
    limited->analyze(a);
    EXPECT_FALSE(limited->factorize(a));
    const std::string detail = limited->failure_detail();
    EXPECT_TRUE(contains(detail, "INFOG(1) = -19")) << detail;
    EXPECT_TRUE(contains(detail, "limit of 2 MB")) << detail;
    EXPECT_FALSE(limited->solve(b).allFinite());
  }
}

// CHOLMOD's LL^T factor of the matrix holds ~3.7 M entries (~30 MB): a 4 MB limit refuses the
// factorisation before it begins, a factor that already holds its values is refactorised in place, and
// the refusal names both sizes.
TEST(MemoryLimit, CholmodRefusesAFactorAboveItsLimit) {
  const SpMat& a = spd_matrix();
  auto limited = make_cholmod_llt(4);
  limited->analyze(a);
  EXPECT_FALSE(limited->factorize(a));
  const std::string detail = limited->failure_detail();
  EXPECT_TRUE(contains(detail, "limit of 4 MB")) << detail;
  EXPECT_EQ(limited->held_factor_entries(), 0);
  auto solver = make_cholmod_llt();
  solver->analyze(a);
  ASSERT_TRUE(solver->factorize(a));
  EXPECT_TRUE(solver->failure_detail().empty());
  const Eigen::VectorXd b = rhs(a.rows());
  EXPECT_LT((a * solver->solve(b) - b).norm(), 1e-12 * b.norm());
}

// A linear system r = A q - b with the grid matrix as its tangent.
class GridSystem final : public NonlinearSystem {
 public:
  int size() const override { return static_cast<int>(spd_matrix().rows()); }
  void evaluate(const Eigen::VectorXd& q, double, bool) override { r_ = spd_matrix() * q - rhs(q.size()); }
  const Eigen::VectorXd& residual() const override { return r_; }
  const SpMat& tangent() const override { return spd_matrix(); }
  int pattern_version() const override { return 1; }

 private:
  Eigen::VectorXd r_;
};

// Newton's report names the refusal, so the run's failure line says what stopped it.
TEST(MemoryLimit, NewtonReportsAFactorisationStoppedByTheLimit) {
  GridSystem system;
  Eigen::VectorXd q = Eigen::VectorXd::Zero(system.size());
  auto solver = make_cholmod_llt(4);
  const NewtonReport report = newton_solve(system, q, 1.0, NewtonOptions{}, *solver);
  EXPECT_FALSE(report.converged);
  EXPECT_TRUE(contains(report.failure, "factorization failed (cholmod: CHOLMOD's factor would need")) << report.failure;
  EXPECT_TRUE(contains(report.failure, "limit of 4 MB")) << report.failure;
}

}  // namespace
}  // namespace fibrane::solve
