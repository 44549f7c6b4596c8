// MUMPS's LDL^T with a Schur complement on the last rows (the algebra is in the header).
#include "linalg/mumps_schur.hpp"

#include <limits>
#include <mutex>

#ifdef FIBRANE_HAVE_MUMPS
#include <dmumps_c.h>
#endif

namespace fibrane::solve {

#ifdef FIBRANE_HAVE_MUMPS

namespace {

std::mutex& mumps_lock() {
  static std::mutex m;
  return m;
}

constexpr int kUseCommWorld = -987654;  // MUMPS's communicator value for the sequential build

}  // namespace

// The MUMPS instance and the arrays it points into. Settings (MUMPS 5.5 user guide) as make_mumps's
// (direct_solvers.hpp), and:
// - ICNTL(19) = 2: the Schur complement centralised on the host, its lower triangle by columns in SCHUR
//   (leading dimension SCHUR_LLD = b); the upper triangle is filled here.
// - ICNTL(7) = 1 with PERM_IN: the caller's pivot order (CHOLMOD's analysis of the same domain); MUMPS
//   keeps the Schur rows LISTVAR_SCHUR last whatever the order says.
// - ICNTL(26) = 1 / 2 at JOB = 3: the reduction and the expansion of a solve; between the two, RHS holds
//   MUMPS's intermediate solution and must not change.
struct MumpsSchur::Instance {
  DMUMPS_STRUC_C id{};
  std::vector<int> rows, columns, perm_in, schur_rows;
  std::vector<double> values, schur;
  bool started = false;
  int& icntl(int i) { return id.icntl[i - 1]; }
  int infog(int i) const { return id.infog[i - 1]; }
  void call(int job) {
    const std::lock_guard<std::mutex> hold(mumps_lock());
    id.job = job;
    dmumps_c(&id);
  }
  ~Instance() {
    if (started) call(-2);
  }
};

MumpsSchur::MumpsSchur() = default;
MumpsSchur::~MumpsSchur() = default;
bool MumpsSchur::available() { return true; }

bool MumpsSchur::analyse(int n, int boundary, const std::vector<int>& rows, const std::vector<int>& columns,
                         const std::vector<int>& pivot_order) {
  id_ = std::make_unique<Instance>();
  factored_ = false;
  boundary_ = boundary;
  Instance& m = *id_;
  m.id.par = 1;
  m.id.sym = 2;
  m.id.comm_fortran = kUseCommWorld;
  m.call(-1);
  m.started = true;
  if (m.infog(1) < 0) return false;
  for (const int i : {1, 2, 3}) m.icntl(i) = -1;  // no output
  m.icntl(4) = 0;
  m.icntl(10) = 0;
  m.icntl(13) = 1;
  m.icntl(24) = 0;
  m.rows.resize(rows.size());
  m.columns.resize(columns.size());
  for (std::size_t k = 0; k < rows.size(); ++k) {
    m.rows[k] = rows[k] + 1;
    m.columns[k] = columns[k] + 1;
  }
  m.values.assign(rows.size(), 0.0);
  m.perm_in.assign(static_cast<std::size_t>(n), 0);
  for (std::size_t k = 0; k < pivot_order.size(); ++k)
    m.perm_in[static_cast<std::size_t>(pivot_order[k])] = static_cast<int>(k) + 1;
  m.schur_rows.resize(static_cast<std::size_t>(boundary));
  for (int k = 0; k < boundary; ++k) m.schur_rows[static_cast<std::size_t>(k)] = n - boundary + k + 1;
  m.schur.assign(static_cast<std::size_t>(boundary) * static_cast<std::size_t>(boundary), 0.0);
  m.id.n = n;
  m.id.nnz = static_cast<int64_t>(m.rows.size());
  m.id.irn = m.rows.data();
  m.id.jcn = m.columns.data();
  m.id.a = m.values.data();
  m.id.perm_in = m.perm_in.data();
  m.icntl(7) = 1;
  m.icntl(19) = 2;
  m.id.size_schur = boundary;
  m.id.listvar_schur = m.schur_rows.data();
  m.id.schur = m.schur.data();
  m.id.schur_lld = boundary;
  m.call(1);
  return m.infog(1) >= 0;
}

bool MumpsSchur::factorise(const double* values) {
  factored_ = false;
  if (!id_) return false;
  Instance& m = *id_;
  std::copy(values, values + m.values.size(), m.values.begin());
  m.call(2);
  if (m.infog(1) < 0) return false;
  schur_ = Eigen::Map<const Eigen::MatrixXd>(m.schur.data(), boundary_, boundary_);
  for (Eigen::Index j = 1; j < boundary_; ++j)
    for (Eigen::Index i = 0; i < j; ++i) schur_(i, j) = schur_(j, i);
  factored_ = true;
  return true;
}

int MumpsSchur::negative_pivots() const { return factored_ ? id_->infog(12) : -1; }

long MumpsSchur::factor_entries() const {
  if (!factored_) return 0;
  const int value = id_->infog(29);
  return value >= 0 ? value : -1000000L * value;
}

// One half of a solve (JOB = 3 with ICNTL(26) = phase) on rhs and the reduced right-hand side; false where
// MUMPS fails.
bool MumpsSchur::solve_phase(int phase, Eigen::MatrixXd& rhs, Eigen::MatrixXd& reduced) const {
  Instance& m = *id_;
  m.id.rhs = rhs.data();
  m.id.nrhs = static_cast<int>(rhs.cols());
  m.id.lrhs = static_cast<int>(rhs.rows());
  m.id.redrhs = reduced.data();
  m.id.lredrhs = boundary_;
  m.icntl(26) = phase;
  m.call(3);
  m.icntl(26) = 0;
  return m.infog(1) >= 0;
}

Eigen::MatrixXd MumpsSchur::reduce(Eigen::MatrixXd& rhs) const {
  Eigen::MatrixXd reduced(boundary_, rhs.cols());
  if (!solve_phase(1, rhs, reduced)) reduced.setConstant(std::numeric_limits<double>::quiet_NaN());
  return reduced;
}

void MumpsSchur::expand(Eigen::MatrixXd& rhs, const Eigen::MatrixXd& x_b) const {
  Eigen::MatrixXd reduced = x_b;
  if (!solve_phase(2, rhs, reduced)) rhs.setConstant(std::numeric_limits<double>::quiet_NaN());
}

#else

struct MumpsSchur::Instance {};
MumpsSchur::MumpsSchur() = default;
MumpsSchur::~MumpsSchur() = default;
bool MumpsSchur::available() { return false; }
bool MumpsSchur::analyse(int, int, const std::vector<int>&, const std::vector<int>&, const std::vector<int>&) {
  return false;
}
bool MumpsSchur::factorise(const double*) { return false; }
int MumpsSchur::negative_pivots() const { return -1; }
long MumpsSchur::factor_entries() const { return 0; }
Eigen::MatrixXd MumpsSchur::reduce(Eigen::MatrixXd& rhs) const {
  return Eigen::MatrixXd::Constant(boundary_, rhs.cols(), std::numeric_limits<double>::quiet_NaN());
}
void MumpsSchur::expand(Eigen::MatrixXd& rhs, const Eigen::MatrixXd&) const {
  rhs.setConstant(std::numeric_limits<double>::quiet_NaN());
}

#endif

}  // namespace fibrane::solve
