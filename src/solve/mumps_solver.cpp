// MUMPS (sequential build) as a LinearSolver: multifrontal symmetric indefinite LDL^T with threshold
// pivoting (SYM = 2), through the C interface dmumps_c. Threads come from the BLAS only (Debian's
// sequential MUMPS is built without OpenMP): set_thread_count() bounds them.
#include <limits>
#include <stdexcept>
#include <vector>

#include "solve/direct_solvers.hpp"

#ifdef FIBRANE_HAVE_MUMPS
#include <dmumps_c.h>
#endif

namespace fibrane::solve {

#ifdef FIBRANE_HAVE_MUMPS
namespace {

using SpMat = Eigen::SparseMatrix<double>;

// 1-based accessors of MUMPS's control and information arrays, as the user guide numbers them.
int& icntl(DMUMPS_STRUC_C& id, int i) { return id.icntl[i - 1]; }
double& cntl(DMUMPS_STRUC_C& id, int i) { return id.cntl[i - 1]; }
int infog(const DMUMPS_STRUC_C& id, int i) { return id.infog[i - 1]; }

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
class MumpsSolver final : public LinearSolver {
 public:
  explicit MumpsSolver(const MumpsOptions& options) {
    id_.job = -1;
    id_.par = 1;  // the host process works
    id_.sym = 2;  // general symmetric: LDL^T with pivoting
    id_.comm_fortran = kUseCommWorld;
    dmumps_c(&id_);
    if (infog(id_, 1) < 0) throw std::runtime_error("MUMPS initialisation failed: INFOG(1) = " + std::to_string(infog(id_, 1)));
    icntl(id_, 1) = -1;  // no error, diagnostic, global or statistics output
    icntl(id_, 2) = -1;
    icntl(id_, 3) = -1;
    icntl(id_, 4) = 0;
    icntl(id_, 7) = options.ordering;
    icntl(id_, 13) = 1;
    icntl(id_, 24) = 0;
    if (options.low_rank) {
      icntl(id_, 35) = 2;
      cntl(id_, 7) = options.low_rank_tolerance;
    }
    pivot_order_ = options.pivot_order;
  }
  ~MumpsSolver() override {
    id_.job = -2;
    dmumps_c(&id_);
  }
  MumpsSolver(const MumpsSolver&) = delete;
  MumpsSolver& operator=(const MumpsSolver&) = delete;

  void analyze(const SpMat& a) override;
  bool factorize(const SpMat& a) override;
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const override;
  std::string name() const override { return "mumps"; }
  long factor_nonzeros() const override;
  std::string analysis_summary() const override;
  int negative_eigenvalues() const override { return factored_ ? infog(id_, 12) : -1; }

 private:
  // Coordinates (1-based) of the lower triangle, and where each entry sits in the matrix's values.
  std::vector<int> rows_, cols_;
  std::vector<Eigen::Index> positions_;
  std::vector<double> values_;
  std::vector<int> pivot_order_, perm_in_;  // MumpsOptions::pivot_order; PERM_IN, its inverse (1-based)
  Eigen::Index n_ = -1, matrix_nonzeros_ = -1;
  mutable DMUMPS_STRUC_C id_{};
  mutable std::vector<double> rhs_;
  bool analyzed_ = false, factored_ = false;
  int analyses_ = 0;
};

void MumpsSolver::analyze(const SpMat& a) {
  if (a.rows() != a.cols()) throw std::invalid_argument("MumpsSolver: the matrix is not square");
  rows_.clear();
  cols_.clear();
  positions_.clear();
  for (Eigen::Index j = 0; j < a.outerSize(); ++j)
    for (SpMat::InnerIterator it(a, j); it; ++it)
      if (it.row() >= j) {
        rows_.push_back(static_cast<int>(it.row()) + 1);
        cols_.push_back(static_cast<int>(j) + 1);
        positions_.push_back(&it.value() - a.valuePtr());
      }
  values_.assign(positions_.size(), 0.0);
  n_ = a.rows();
  matrix_nonzeros_ = a.nonZeros();
  id_.n = static_cast<int>(n_);
  id_.nnz = static_cast<int64_t>(rows_.size());
  id_.irn = rows_.data();
  id_.jcn = cols_.data();
  id_.a = values_.data();
  // PERM_IN(i) is the position of variable i in the pivot order (1-based): the inverse of pivot_order_.
  const int ordering = icntl(id_, 7);
  if (static_cast<Eigen::Index>(pivot_order_.size()) == n_) {
    perm_in_.assign(pivot_order_.size(), 0);
    for (size_t k = 0; k < pivot_order_.size(); ++k) perm_in_[static_cast<size_t>(pivot_order_[k])] = static_cast<int>(k) + 1;
    id_.perm_in = perm_in_.data();
    icntl(id_, 7) = 1;
  }
  id_.job = 1;
  dmumps_c(&id_);
  icntl(id_, 7) = ordering;
  analyzed_ = infog(id_, 1) >= 0;
  factored_ = false;
  ++analyses_;
}

bool MumpsSolver::factorize(const SpMat& a) {
  if (!analyzed_ || a.rows() != n_ || a.nonZeros() != matrix_nonzeros_) analyze(a);
  factored_ = false;
  if (!analyzed_) return false;
  const BlasThreadsForFactor threads(factor_nonzeros());
  const double* v = a.valuePtr();
  for (size_t k = 0; k < positions_.size(); ++k) values_[k] = v[positions_[k]];
  id_.a = values_.data();
  const int relaxation = icntl(id_, 14);
  for (int attempt = 0; attempt < 4; ++attempt) {
    id_.job = 2;
    dmumps_c(&id_);
    const int status = infog(id_, 1);
    if (status != -8 && status != -9) break;
    icntl(id_, 14) *= 2;
  }
  icntl(id_, 14) = relaxation;
  factored_ = infog(id_, 1) >= 0;
  return factored_;
}

Eigen::VectorXd MumpsSolver::solve(const Eigen::VectorXd& b) const {
  if (!factored_ || b.size() != n_) return Eigen::VectorXd::Constant(b.size(), std::numeric_limits<double>::quiet_NaN());
  const BlasThreadsForFactor threads(factor_nonzeros());
  rhs_.assign(b.data(), b.data() + b.size());
  id_.rhs = rhs_.data();
  id_.nrhs = 1;
  id_.lrhs = static_cast<int>(n_);
  id_.job = 3;
  dmumps_c(&id_);
  if (infog(id_, 1) < 0) return Eigen::VectorXd::Constant(b.size(), std::numeric_limits<double>::quiet_NaN());
  return Eigen::Map<const Eigen::VectorXd>(rhs_.data(), n_);
}

// INFOG(29): entries in the factors after a factorisation (negative: millions); before, the analysis's
// estimate INFOG(20) (same convention).
long MumpsSolver::factor_nonzeros() const {
  const int value = factored_ ? infog(id_, 29) : analyzed_ ? infog(id_, 20) : 0;
  return value >= 0 ? value : -1000000L * value;
}

// "<analyses> with <ordering INFOG(7)>, <MB> MB": the memory is what the last factorisation used
// (INFOG(22)), or the analysis's estimate (INFOG(17)) before one.
std::string MumpsSolver::analysis_summary() const {
  if (!analyzed_) return {};
  static const char* const names[] = {"AMD", "the given order", "AMF", "SCOTCH", "PORD", "METIS", "QAMD"};
  const int ordering = infog(id_, 7);
  const std::string method = ordering >= 0 && ordering <= 6 ? names[ordering] : "ordering " + std::to_string(ordering);
  const int megabytes = factored_ ? infog(id_, 22) : infog(id_, 17);
  return std::to_string(analyses_) + " with " + method + ", " + std::to_string(megabytes) + " MB" +
         (icntl(id_, 35) > 0 ? ", block low-rank" : "");
}

}  // namespace

bool mumps_available() { return true; }

std::unique_ptr<LinearSolver> make_mumps(const MumpsOptions& options) { return std::make_unique<MumpsSolver>(options); }

#else

bool mumps_available() { return false; }

std::unique_ptr<LinearSolver> make_mumps(const MumpsOptions&) {
  throw std::logic_error("fibrane was built without MUMPS (FIBRANE_MUMPS=OFF)");
}

#endif

}  // namespace fibrane::solve
