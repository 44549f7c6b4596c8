// MUMPS (sequential build) as a LinearSolver, through its C interfaces dmumps_c (double) and smumps_c
// (single precision): multifrontal LDL^T with threshold pivoting (SYM = 2) of a symmetric matrix's lower
// triangle, or LU with threshold partial pivoting (SYM = 0) of the whole matrix; optionally block low-rank.
// Threads come from the BLAS only (Debian's sequential MUMPS is built without OpenMP): set_thread_count()
// bounds them.
#include <unistd.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <vector>

#include "common/system_memory.hpp"
#include "linalg/direct_solvers.hpp"

#ifdef FIBRANE_HAVE_MUMPS
#include <dmumps_c.h>
#include <smumps_c.h>
#endif

namespace fibrane::solve {

#ifdef FIBRANE_HAVE_MUMPS
namespace {

using SpMat = Eigen::SparseMatrix<double>;

// The two arithmetics: MUMPS's structure, its real type and its entry point.
struct DoubleArithmetic {
  using Struct = DMUMPS_STRUC_C;
  using Real = double;
  static void call(Struct* id) { dmumps_c(id); }
  static constexpr const char* suffix = "";
};
struct SingleArithmetic {
  using Struct = SMUMPS_STRUC_C;
  using Real = float;
  static void call(Struct* id) { smumps_c(id); }
  static constexpr const char* suffix = "-single";
};

constexpr int kUseCommWorld = -987654;  // MUMPS's communicator value for the sequential build

// Analysis once per pattern (JOB = 1), factorisation per matrix (JOB = 2), solve (JOB = 3).
// Settings (MUMPS 5.5 user guide):
// - ICNTL(13) = 1: the root front is factorised without ScaLAPACK. INFOG(12), the number of negative
//   pivots, leaves out pivots of a root factorised by ScaLAPACK; the sequential build never uses it, and
//   the setting keeps the count exact should the library be an MPI one.
// - ICNTL(24) = 0 (no null-pivot detection): a numerically singular matrix stops the factorisation
//   with INFOG(1) = -10, and factorize() returns false, as for the other solvers. (With detection on,
//   MUMPS would go on, count the null pivots in INFOG(28) and leave them out of INFOG(12), so INFOG(12)
//   would count the negative eigenvalues and INFOG(28) estimate the zero ones; a pivot is then never
//   both null and negative.)
// - ICNTL(14): MUMPS sizes its work space from the analysis plus this percentage (20 by default);
//   pivoting can delay more pivots than foreseen (INFOG(1) = -8 / -9), and the factorisation is then
//   repeated with the percentage doubled, up to three times.
// - ICNTL(23): the memory limit (MumpsOptions::memory_limit_megabytes). Where the analysis's estimate of
//   the factorisation's memory (for the relaxation of the attempt), with a tenth more, fits the limit,
//   ICNTL(23) stays 0 and MUMPS sizes its work space from the estimate. Otherwise ICNTL(23) is the limit:
//   MUMPS shares it between the factor, the stack and the arrays that extend them, and stops with
//   INFOG(1) = -19 (below the analysis's lower bound) or -9 (delayed pivots) where it needs more; a -9
//   under the limit is not repeated, since more relaxation only takes memory from the factor's share.
//   (Set when memory is plentiful, it costs: MUMPS then spreads over the larger work space instead of
//   compacting it; docs/performance.md, "A factorisation's memory limit".)
// - ICNTL(22): out of core (1) or in core (0). MUMPS reads it at each factorisation, and the solves
//   follow the factorisation's choice, so one analysis serves both (MumpsOptions::out_of_core_when_needed).
// - ICNTL(10) = 0: no iterative refinement inside MUMPS; a single-precision or low-rank factor is refined
//   in double precision by the caller (KrylovReuseSolver).
template <class Arithmetic>
class MumpsSolver final : public LinearSolver {
  using Real = typename Arithmetic::Real;

 public:
  explicit MumpsSolver(const MumpsOptions& options) : options_(options) { start(); }
  ~MumpsSolver() override {
    id_.job = -2;
    Arithmetic::call(&id_);
  }
  MumpsSolver(const MumpsSolver&) = delete;
  MumpsSolver& operator=(const MumpsSolver&) = delete;

  void analyze(const SpMat& a) override;
  bool factorize_numeric(const SpMat& a) override;
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const override { return solve_columns(b); }
  Eigen::MatrixXd solve_columns(const Eigen::MatrixXd& b) const override;
  std::string name() const override {
    return std::string(options_.unsymmetric ? "mumps-lu" : "mumps") + Arithmetic::suffix +
           (options_.low_rank ? "-blr" : "") + (out_of_core() ? "-ooc" : "");
  }
  long factor_nonzeros() const override;
  std::string analysis_summary() const override;
  // INFOG(12) counts negative pivots of an LDL^T; an LU gives no inertia.
  int negative_eigenvalues() const override { return factored_ && !options_.unsymmetric ? infog(12) : -1; }
  bool exact() const override { return !options_.low_rank && sizeof(Real) == sizeof(double); }
  std::string failure_detail() const override;

 private:
  // A new MUMPS instance (JOB = -1) with fibrane's settings.
  void start() {
    id_.job = -1;
    id_.par = 1;  // the host process works
    id_.sym = options_.unsymmetric ? 0 : 2;
    id_.comm_fortran = kUseCommWorld;
    Arithmetic::call(&id_);
    if (infog(1) < 0) throw std::runtime_error("MUMPS initialisation failed: INFOG(1) = " + std::to_string(infog(1)));
    icntl(1) = -1;  // no error, diagnostic, global or statistics output
    icntl(2) = -1;
    icntl(3) = -1;
    icntl(4) = 0;
    icntl(7) = options_.ordering;
    icntl(10) = 0;
    icntl(13) = 1;
    icntl(24) = 0;
    if (options_.low_rank) {
      icntl(35) = 2;
      id_.cntl[6] = static_cast<Real>(options_.low_rank_tolerance);  // CNTL(7)
    }
    if (!options_.out_of_core_directory.empty()) set_out_of_core_files();
    icntl(22) = options_.out_of_core_directory.empty() || options_.out_of_core_when_needed ? 0 : 1;
  }
  // OOC_TMPDIR and OOC_PREFIX (the process id, so that runs sharing the directory keep apart); MUMPS
  // deletes its files at JOB = -2 and at the next factorisation.
  void set_out_of_core_files() {
    const std::string& dir = options_.out_of_core_directory;
    const std::string prefix = "fibrane-" + std::to_string(::getpid()) + "-";
    if (dir.size() >= sizeof(id_.ooc_tmpdir))
      throw std::invalid_argument("MUMPS out-of-core directory name longer than " +
                                  std::to_string(sizeof(id_.ooc_tmpdir) - 1) + " characters: " + dir);
    std::snprintf(id_.ooc_tmpdir, sizeof(id_.ooc_tmpdir), "%s", dir.c_str());
    std::snprintf(id_.ooc_prefix, sizeof(id_.ooc_prefix), "%s", prefix.c_str());
  }
  // Whether the last (or next) factorisation keeps its factor in files: ICNTL(22), which MUMPS reads at
  // the factorisation and which then holds for its solves.
  bool out_of_core() const { return icntl(22) == 1; }
  // ICNTL(23) for the next attempt, in MB (0: MUMPS's own sizing), from the limit and the analysis's
  // estimate scaled to the attempt's relaxation ICNTL(14) (the analysis used `relaxation`).
  int memory_limit(int relaxation) const {
    const double limit = factorization_memory_limit(options_.memory_limit_megabytes) / (1 << 20);
    const double estimate = estimated_megabytes() * (100.0 + icntl(14)) / (100.0 + relaxation);
    if (limit <= 0 || 1.1 * estimate <= limit) return 0;
    return static_cast<int>(std::min(std::ceil(limit), double{INT_MAX}));
  }
  // The analysis's estimate of the factorisation's memory in MB: INFOG(17) in core, INFOG(27) out of core,
  // INFOG(36) and INFOG(38) for low-rank (sums over processes; one process here).
  int estimated_megabytes(bool ooc) const {
    return options_.low_rank ? (ooc ? infog(38) : infog(36)) : (ooc ? infog(27) : infog(17));
  }
  int estimated_megabytes() const { return estimated_megabytes(out_of_core()); }
  // 1-based accessors of MUMPS's control and information arrays, as the user guide numbers them.
  int& icntl(int i) { return id_.icntl[i - 1]; }
  int icntl(int i) const { return id_.icntl[i - 1]; }
  int infog(int i) const { return id_.infog[i - 1]; }
  // Whether the analysis's in-core estimate, with a tenth more, fits the memory limit (or there is none).
  bool fits_in_core() const {
    const double limit = factorization_memory_limit(options_.memory_limit_megabytes) / (1 << 20);
    return limit <= 0 || 1.1 * estimated_megabytes(false) <= limit;
  }
  // Whether the last factorisation stopped for want of memory: an allocation refused, or its limit.
  bool failed_for_memory() const {
    const int status = infog(1);
    return status == -13 || status == -19 || (status == -9 && icntl(23) > 0);
  }
  // JOB = 2 in the current mode (ICNTL(22)), repeated with more relaxation where delayed pivots outgrow
  // the work space (ICNTL(14), above).
  void run_factorization();
  void record_status() {
    last_status_ = infog(1);
    last_status2_ = infog(2);
    last_limit_ = icntl(23);
  }

  MumpsOptions options_;
  // Coordinates (1-based) of the entries MUMPS reads (the lower triangle for LDL^T, all for LU).
  std::vector<int> rows_, cols_;
  std::vector<Real> values_;  // the entries of irn/jcn, in a's order (the whole matrix, or its lower triangle)
  // Copies a's entries that MUMPS takes into values_, in the order analyze() listed them; false (values_
  // incomplete) when a has another number of them than the analysed pattern.
  bool gather_values(const SpMat& a);
  // Whether MUMPS takes entry (row, col): all of them for the LU, the lower triangle for LDL^T.
  bool takes(Eigen::Index row, Eigen::Index col) const { return options_.unsymmetric || row >= col; }
  std::vector<int> perm_in_;  // PERM_IN (1-based), the inverse of the pivot order
  Eigen::Index n_ = -1, matrix_nonzeros_ = -1;
  mutable typename Arithmetic::Struct id_{};
  bool analyzed_ = false, factored_ = false;
  int analyses_ = 0, last_status_ = 0, last_status2_ = 0, last_limit_ = 0;
};

template <class Arithmetic>
void MumpsSolver<Arithmetic>::analyze(const SpMat& a) {
  if (a.rows() != a.cols()) throw std::invalid_argument("MumpsSolver: the matrix is not square");
  if (analyses_ > 0) {  // a new instance: the last factor and analysis are freed and handed back
    id_.job = -2;
    Arithmetic::call(&id_);
    id_ = {};
    start();
    hand_back_freed_memory();
  }
  // The last pattern's arrays go before the new ones are sized to their entries.
  release_storage(rows_);
  release_storage(cols_);
  release_storage(values_);
  std::size_t entries = 0;
  for (Eigen::Index j = 0; j < a.outerSize(); ++j)
    for (SpMat::InnerIterator it(a, j); it; ++it) entries += takes(it.row(), j);
  rows_.reserve(entries);
  cols_.reserve(entries);
  for (Eigen::Index j = 0; j < a.outerSize(); ++j)
    for (SpMat::InnerIterator it(a, j); it; ++it)
      if (takes(it.row(), j)) {
        rows_.push_back(static_cast<int>(it.row()) + 1);
        cols_.push_back(static_cast<int>(j) + 1);
      }
  values_.assign(rows_.size(), Real(0));
  n_ = a.rows();
  matrix_nonzeros_ = a.nonZeros();
  id_.n = static_cast<int>(n_);
  id_.nnz = static_cast<int64_t>(rows_.size());
  id_.irn = rows_.data();
  id_.jcn = cols_.data();
  id_.a = values_.data();
  // PERM_IN(i) is the position of variable i in the pivot order (1-based): the inverse of the pivot order.
  std::vector<int> order = options_.pivot_order;
  if (options_.cholmod_ordering) order = cholmod_ordering(a);
  const int ordering = icntl(7);
  if (static_cast<Eigen::Index>(order.size()) == n_) {
    perm_in_.assign(order.size(), 0);
    for (size_t k = 0; k < order.size(); ++k) perm_in_[static_cast<size_t>(order[k])] = static_cast<int>(k) + 1;
    id_.perm_in = perm_in_.data();
    icntl(7) = 1;
  }
  id_.job = 1;
  Arithmetic::call(&id_);
  icntl(7) = ordering;
  record_status();
  analyzed_ = infog(1) >= 0;
  factored_ = false;
  ++analyses_;
}

template <class Arithmetic>
bool MumpsSolver<Arithmetic>::gather_values(const SpMat& a) {
  size_t k = 0;
  for (Eigen::Index j = 0; j < a.outerSize(); ++j)
    for (SpMat::InnerIterator it(a, j); it; ++it)
      if (takes(it.row(), j) && k++ < values_.size()) values_[k - 1] = static_cast<Real>(it.value());
  return k == values_.size();
}

template <class Arithmetic>
bool MumpsSolver<Arithmetic>::factorize_numeric(const SpMat& a) {
  if (!analyzed_ || a.rows() != n_ || a.nonZeros() != matrix_nonzeros_) analyze(a);
  factored_ = false;
  if (!analyzed_) return false;
  if (!gather_values(a)) {  // the same size and count of entries, but another pattern
    analyze(a);
    if (!analyzed_ || !gather_values(a)) return false;
  }
  const BlasThreadsForFactor threads(factor_nonzeros());
  id_.a = values_.data();
  const bool when_needed = options_.out_of_core_when_needed && !options_.out_of_core_directory.empty();
  if (when_needed) icntl(22) = fits_in_core() ? 0 : 1;
  run_factorization();
  if (when_needed && !out_of_core() && failed_for_memory()) {
    icntl(22) = 1;
    run_factorization();
  }
  record_status();
  factored_ = infog(1) >= 0;
  return factored_;
}

template <class Arithmetic>
void MumpsSolver<Arithmetic>::run_factorization() {
  const int relaxation = icntl(14);
  // Out of core, the factor is read back through the system's page cache at every solve; memory that the
  // process has freed but keeps (the last iteration's work arrays) would take that cache's place.
  if (out_of_core()) hand_back_all_freed_memory();
  for (int attempt = 0; attempt < 4; ++attempt) {
    icntl(23) = memory_limit(relaxation);
    id_.job = 2;
    Arithmetic::call(&id_);
    const int status = infog(1);
    if (status != -8 && (status != -9 || icntl(23) > 0)) break;
    icntl(14) *= 2;
  }
  icntl(14) = relaxation;
  if (out_of_core()) hand_back_all_freed_memory();  // the factorisation's own work space beyond the stack
}

template <class Arithmetic>
Eigen::MatrixXd MumpsSolver<Arithmetic>::solve_columns(const Eigen::MatrixXd& b) const {
  const auto failed = [&] { return Eigen::MatrixXd::Constant(b.rows(), b.cols(), std::numeric_limits<double>::quiet_NaN()); };
  if (!factored_ || b.rows() != n_) return failed();
  const BlasThreadsForFactor threads(factor_nonzeros());
  Eigen::Matrix<Real, Eigen::Dynamic, Eigen::Dynamic> x = b.cast<Real>();  // column-major: LRHS = n
  id_.rhs = x.data();
  id_.nrhs = static_cast<int>(b.cols());
  id_.lrhs = static_cast<int>(n_);
  id_.job = 3;
  Arithmetic::call(&id_);
  if (infog(1) < 0) return failed();
  return x.template cast<double>();
}

// The statuses a run meets (MUMPS 5.5 user guide, section 8); INFOG(2) < 0 counts millions.
template <class Arithmetic>
std::string MumpsSolver<Arithmetic>::failure_detail() const {
  if (last_status_ >= 0) return {};
  const std::string limit = std::to_string(last_limit_) + " MB";
  const std::string meaning =
      last_status_ == -10   ? ": numerically singular matrix"
      : last_status_ == -13 ? ": out of memory (an allocation of INFOG(2) entries failed)"
      : last_status_ == -19 ? ": it needs more memory than its limit of " + limit
      : last_status_ == -9 && last_limit_ > 0 ? ": delayed pivots need more memory than the limit of " + limit
      : last_status_ == -9 || last_status_ == -8 ? ": work space too small"
      : last_status_ == -90 ? ": out-of-core file error (is the directory's disk full?)"
                            : "";
  return "MUMPS INFOG(1) = " + std::to_string(last_status_) + ", INFOG(2) = " + std::to_string(last_status2_) + meaning;
}

// INFOG(29): entries in the factors after a factorisation (negative: millions); before, the analysis's
// estimate INFOG(20) (same convention).
template <class Arithmetic>
long MumpsSolver<Arithmetic>::factor_nonzeros() const {
  const int value = factored_ ? infog(29) : analyzed_ ? infog(20) : 0;
  return value >= 0 ? value : -1000000L * value;
}

// "<analyses> with <ordering INFOG(7)>, <MB> MB": the memory is what the last factorisation used
// (INFOG(22)), or the analysis's estimate before one.
template <class Arithmetic>
std::string MumpsSolver<Arithmetic>::analysis_summary() const {
  if (!analyzed_) return {};
  static const char* const names[] = {"AMD", "the given order", "AMF", "SCOTCH", "PORD", "METIS", "QAMD"};
  const int ordering = infog(7);
  const std::string method = ordering >= 0 && ordering <= 6 ? names[ordering] : "ordering " + std::to_string(ordering);
  const bool ooc = out_of_core();
  const int megabytes = factored_ ? infog(22) : estimated_megabytes();
  return std::to_string(analyses_) + " with " + method + ", " + std::to_string(megabytes) + " MB" +
         (options_.low_rank ? ", block low-rank" : "") + (ooc ? ", factor on disk" : "");
}

}  // namespace

bool mumps_available() { return true; }

std::unique_ptr<LinearSolver> make_mumps(const MumpsOptions& options) {
  if (options.single_precision) return std::make_unique<MumpsSolver<SingleArithmetic>>(options);
  return std::make_unique<MumpsSolver<DoubleArithmetic>>(options);
}

#else

bool mumps_available() { return false; }

std::unique_ptr<LinearSolver> make_mumps(const MumpsOptions&) {
  throw std::logic_error("fibrane was built without MUMPS (FIBRANE_MUMPS=OFF)");
}

#endif

}  // namespace fibrane::solve
