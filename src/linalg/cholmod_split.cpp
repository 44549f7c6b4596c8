// CHOLMOD's supernodal LL^T in two halves side by side, joined by the separator's dense Schur complement
// (the algebra is in cholmod_split.hpp).
#include "linalg/cholmod_split.hpp"

#include <cholmod.h>
#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <string>

#include "linalg/cholmod_permuted_lower.hpp"
#include "linalg/direct_solvers.hpp"

extern "C" {
void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info);
void dpotrs_(const char* uplo, const int* n, const int* nrhs, const double* a, const int* lda, double* b,
             const int* ldb, int* info);
void dsyrk_(const char* uplo, const char* trans, const int* n, const int* k, const double* alpha, const double* a,
            const int* lda, const double* beta, double* c, const int* ldc);
}

namespace fibrane::solve {
namespace {

using SpMat = Eigen::SparseMatrix<double>;

// One half: its interior and the separator, with its own CHOLMOD workspace (the halves run on two threads).
struct Half {
  std::vector<int> rows;  // the whole matrix's rows of the half's rows: the interior, then the separator
  int interior = 0;
  std::vector<int> lower_start, lower_rows;  // the pattern of the half's lower triangle, compressed columns
  std::vector<int> source;  // source[q]: the index in the whole matrix's values of the lower triangle's entry q
  CholmodPermutedLower permuted;  // the permuted lower triangle, its source mapped into the whole
  cholmod_common common{};
  cholmod_factor* factor = nullptr;
  double flops = 0;  // of a factorisation, as CHOLMOD's analysis counts them
  std::vector<int> separator_order;  // the separator rows (0 ... s-1) in the factor's order
  Eigen::MatrixXd c;  // P^T C: the factor's trailing separator block, its rows in the separator's order

  Half() {
    cholmod_start(&common);
    common.print = 0;
    common.supernodal = CHOLMOD_SUPERNODAL;
  }
  ~Half() {
    cholmod_free_factor(&factor, &common);
    permuted.clear();
    cholmod_finish(&common);
  }
  Half(const Half&) = delete;
  Half& operator=(const Half&) = delete;
  int size() const { return static_cast<int>(rows.size()); }
  cholmod_sparse lower() { return cholmod_lower_view(size(), lower_start.data(), lower_rows.data(), nullptr); }
};

// The pattern of the lower triangle of a's rows and columns h.rows (in that order) in h.lower_start and
// h.lower_rows, and in h.source the index in a's values of each of its entries. Two counting sorts (the
// entries by row, then by column in the order of their rows) leave every column's rows sorted.
void sub_lower(const SpMat& a, Half& h) {
  const std::vector<int>& rows = h.rows;
  const int n = static_cast<int>(rows.size());
  std::vector<int> local(static_cast<std::size_t>(a.rows()), -1);
  for (int i = 0; i < n; ++i) local[static_cast<std::size_t>(rows[static_cast<std::size_t>(i)])] = i;
  const int* outer = a.outerIndexPtr();
  const int* inner = a.innerIndexPtr();
  auto for_each_entry = [&](auto&& visit) {  // visit(local row, local column, index in a), row >= column
    for (int j = 0; j < a.cols(); ++j) {
      const int lj = local[static_cast<std::size_t>(j)];
      if (lj < 0) continue;
      for (int p = outer[j]; p < outer[j + 1]; ++p) {
        const int i = inner[p], li = local[static_cast<std::size_t>(i)];
        if (i >= j && li >= 0) visit(std::max(li, lj), std::min(li, lj), p);  // a's lower triangle
      }
    }
  };
  std::vector<int> row_start(static_cast<std::size_t>(n) + 1, 0);
  for_each_entry([&](int r, int, int) { ++row_start[static_cast<std::size_t>(r) + 1]; });
  std::partial_sum(row_start.begin(), row_start.end(), row_start.begin());
  const auto entries = static_cast<std::size_t>(row_start.back());
  std::vector<int> next(row_start.begin(), row_start.end() - 1), row_column(entries), row_source(entries);
  for_each_entry([&](int r, int c, int p) {
    const auto k = static_cast<std::size_t>(next[static_cast<std::size_t>(r)]++);
    row_column[k] = c;
    row_source[k] = p;
  });
  std::vector<int>& column_start = h.lower_start;
  column_start.assign(static_cast<std::size_t>(n) + 1, 0);
  for (const int c : row_column) ++column_start[static_cast<std::size_t>(c) + 1];
  std::partial_sum(column_start.begin(), column_start.end(), column_start.begin());
  next.assign(column_start.begin(), column_start.end() - 1);
  h.lower_rows.resize(entries);
  h.source.resize(entries);
  for (int r = 0; r < n; ++r)
    for (auto k = static_cast<std::size_t>(row_start[static_cast<std::size_t>(r)]);
         k < static_cast<std::size_t>(row_start[static_cast<std::size_t>(r) + 1]); ++k) {
      const auto q = static_cast<std::size_t>(next[static_cast<std::size_t>(row_column[k])]++);
      h.lower_rows[q] = r;
      h.source[q] = row_source[k];
    }
}

// Analyses a half with its interior in CHOLMOD's fill-reducing order and the separator after it, as given;
// false where CHOLMOD fails or its factor does not keep the separator last.
bool analyse(Half& h, const SpMat& a) {
  sub_lower(a, h);
  // CAMD's constrained minimum degree (the separator a constraint set after the interior), which needed
  // fewer flops than METIS's order of the interior alone or of the whole half with the separator moved
  // last (docs/performance.md, "The factorisation's input").
  std::vector<int> order(static_cast<std::size_t>(h.size())), member(order.size(), 0);
  std::fill(member.begin() + h.interior, member.end(), 1);
  cholmod_sparse hv = h.lower();
  if (!cholmod_camd(&hv, nullptr, 0, member.data(), order.data(), &h.common)) return false;
  h.common.nmethods = 1;
  h.common.method[0].ordering = CHOLMOD_GIVEN;
  h.factor = cholmod_analyze_p(&hv, order.data(), nullptr, 0, &h.common);
  h.common.nmethods = 0;
  h.flops = h.common.fl;
  if (!h.factor || !h.factor->is_super) return false;
  // CHOLMOD's postorder of the elimination tree keeps the separator, the tree's top, last: only its own
  // order may change. separator_order[t]: the separator row of the factor's column interior + t.
  const auto* perm = static_cast<const int*>(h.factor->Perm);
  const int s = h.size() - h.interior;
  h.separator_order.assign(perm + h.interior, perm + h.size());
  std::vector<char> seen(static_cast<std::size_t>(s), 0);
  for (int& r : h.separator_order) {
    r -= h.interior;
    if (r < 0 || seen[static_cast<std::size_t>(r)]) return false;
    seen[static_cast<std::size_t>(r)] = 1;
  }
  return true;
}

// Factorises a half from the whole matrix's values and copies out its separator block C, its rows in the
// separator's order (P^T C; its columns stay in the factor's); false where the half is not positive
// definite or CHOLMOD fails.
bool factorise(Half& h, const SpMat& a) {
  if (!h.permuted.built()) {
    if (!h.permuted.build(h.lower(), *h.factor, h.common)) return false;
    h.permuted.map_through(h.source);
  }
  double beta[2] = {0, 0};
  const int ok = cholmod_super_numeric(h.permuted.fill(a.valuePtr()), nullptr, beta, h.factor, &h.common);
  h.permuted.drop_values();
  if (!ok || h.common.status != CHOLMOD_OK || h.factor->minor < h.factor->n) return false;
  // C: the columns from the interior's end on, in their supernodes (column-major blocks of nsrow rows).
  const int s = h.size() - h.interior;
  h.c.setZero(s, s);
  const auto* super = static_cast<const int*>(h.factor->super);
  const auto* pi = static_cast<const int*>(h.factor->pi);
  const auto* px = static_cast<const int*>(h.factor->px);
  const auto* ls = static_cast<const int*>(h.factor->s);
  const auto* lx = static_cast<const double*>(h.factor->x);
  for (size_t sn = 0; sn < h.factor->nsuper; ++sn) {
    const int k1 = super[sn], k2 = super[sn + 1], nsrow = pi[sn + 1] - pi[sn];
    for (int j = std::max(k1, h.interior); j < k2; ++j)
      for (int r = j - k1; r < nsrow; ++r)
        h.c(h.separator_order[static_cast<std::size_t>(ls[pi[sn] + r] - h.interior)], j - h.interior) =
            lx[px[sn] + (j - k1) * nsrow + r];
  }
  return true;
}

// One of CHOLMOD's solves (sys: CHOLMOD_P, CHOLMOD_L, CHOLMOD_Lt, CHOLMOD_Pt) with a half's factor.
Eigen::MatrixXd half_solve(int sys, Half& h, const Eigen::MatrixXd& b) {
  cholmod_dense in{};
  in.nrow = static_cast<size_t>(b.rows());
  in.ncol = static_cast<size_t>(b.cols());
  in.nzmax = in.nrow * in.ncol;
  in.d = in.nrow;
  in.x = const_cast<double*>(b.data());
  in.xtype = CHOLMOD_REAL;
  in.dtype = CHOLMOD_DOUBLE;
  cholmod_dense* out = cholmod_solve(sys, h.factor, &in, &h.common);
  if (!out) return Eigen::MatrixXd::Constant(b.rows(), b.cols(), std::numeric_limits<double>::quiet_NaN());
  Eigen::MatrixXd x = Eigen::Map<const Eigen::MatrixXd>(static_cast<const double*>(out->x), b.rows(), b.cols());
  cholmod_free_dense(&out, &h.common);
  return x;
}

// The solver: two halves and the separator's Schur complement where the matrix is split, make_cholmod_llt's
// solver where it is not.
class CholmodSplitSolver final : public LinearSolver {
 public:
  explicit CholmodSplitSolver(const CholmodSplitOptions& o) : options_(o) {}

  void analyze(const SpMat& a) override {
    halves_[0].reset();
    halves_[1].reset();
    t_.resize(0, 0);
    factored_ = false;
    hand_back_freed_memory();
    split_ = a.rows() >= options_.min_unknowns && omp_get_max_threads() >= 2 && a.isCompressed() && split(a);
    if (split_) return;
    partition_.clear();  // a bisection that did not serve is not kept: the next pattern is bisected anew
    halves_[0].reset();
    halves_[1].reset();
    if (!whole_) whole_ = make_cholmod_llt(options_.memory_limit_megabytes);
    whole_->analyze(a);
  }
  bool factorize(const SpMat& a) override {
    factored_ = false;
    if (!split_) return whole_->factorize(a);
    if (const std::string refusal = memory_refusal(); !refusal.empty()) {
      refusal_ = refusal;
      return false;
    }
    refusal_.clear();
    bool ok[2] = {false, false};
    {
      const BlasThreadsForFactor one_blas_thread(0);  // one BLAS thread per half
#pragma omp parallel for num_threads(2) schedule(static, 1)
      for (int k = 0; k < 2; ++k) ok[k] = factorise(*halves_[k], a);
    }
    if (!ok[0] || !ok[1]) return false;
    factored_ = schur(a);
    return factored_;
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const override {
    if (!split_) return whole_->solve(b);
    return solve_columns(b);
  }
  // All columns together: one pass through each half's factor (the rank-m correction of "auto" solves m).
  Eigen::MatrixXd solve_columns(const Eigen::MatrixXd& b) const override {
    if (!split_) return whole_->solve_columns(b);
    const auto s = t_.rows(), m = b.cols();
    Eigen::MatrixXd y[2], x_s = b(separator_, Eigen::all);
    {
      const BlasThreadsForFactor one_blas_thread(0);
#pragma omp parallel for num_threads(2) schedule(static, 1)
      for (int k = 0; k < 2; ++k) {
        Half& h = *halves_[k];
        Eigen::MatrixXd local = Eigen::MatrixXd::Zero(h.size(), m);
        for (int i = 0; i < h.interior; ++i) local.row(i) = b.row(h.rows[static_cast<std::size_t>(i)]);
        y[k] = half_solve(CHOLMOD_L, h, half_solve(CHOLMOD_P, h, local));
      }
    }
    for (int k = 0; k < 2; ++k)  // b_S + C_k v_k
      x_s.noalias() += halves_[k]->c * y[k].bottomRows(s);
    const int n = static_cast<int>(s), columns = static_cast<int>(m);
    int info = 0;
    dpotrs_("L", &n, &columns, t_.data(), &n, x_s.data(), &n, &info);
    Eigen::MatrixXd x(b.rows(), m);
    {
      const BlasThreadsForFactor one_blas_thread(0);
#pragma omp parallel for num_threads(2) schedule(static, 1)
      for (int k = 0; k < 2; ++k) {
        Half& h = *halves_[k];
        y[k].bottomRows(s).noalias() = h.c.transpose() * x_s;
        const Eigen::MatrixXd local = half_solve(CHOLMOD_Pt, h, half_solve(CHOLMOD_Lt, h, y[k]));
        for (int i = 0; i < h.interior; ++i) x.row(h.rows[static_cast<std::size_t>(i)]) = local.row(i);
      }
    }
    x(separator_, Eigen::all) = x_s;
    return x;
  }
  std::string name() const override { return "cholmod"; }
  long factor_nonzeros() const override {
    if (!split_) return whole_ ? whole_->factor_nonzeros() : 0;
    const long s = t_.rows();
    return static_cast<long>(halves_[0]->factor->xsize + halves_[1]->factor->xsize) + s * (s + 1) / 2;
  }
  std::string analysis_summary() const override {
    if (!split_) return whole_ ? whole_->analysis_summary() : std::string();
    char flops[64];
    std::snprintf(flops, sizeof flops, " (%.3g and %.3g GFlop)", halves_[0]->flops / 1e9, halves_[1]->flops / 1e9);
    return "in two halves at a separator of " + std::to_string(separator_.size()) + flops;
  }
  int negative_eigenvalues() const override {
    if (!split_) return whole_ ? whole_->negative_eigenvalues() : -1;
    return factored_ ? 0 : -1;
  }
  std::string failure_detail() const override { return split_ ? refusal_ : whole_ ? whole_->failure_detail() : ""; }
  void release_factor() override {
    factored_ = false;
    if (!split_) {
      if (whole_) whole_->release_factor();
      return;
    }
    for (auto& h : halves_) {
      cholmod_change_factor(CHOLMOD_PATTERN, h->factor->is_ll, h->factor->is_super, true, true, h->factor,
                            &h->common);
      h->permuted.release_values();
    }
  }
  long held_factor_entries() const override {
    if (!split_) return whole_ ? whole_->held_factor_entries() : 0;
    long held = 0;
    for (const auto& h : halves_)
      if (h->factor->xtype != CHOLMOD_PATTERN) held += static_cast<long>(h->factor->xsize);
    return held;
  }
  long separator() const { return split_ ? static_cast<long>(separator_.size()) : 0; }
  // The pivot order of the whole: the two interiors in their factors' orders, then the separator.
  std::vector<int> pivot_order() const {
    if (!split_) return whole_ ? cholmod_pivot_order(*whole_) : std::vector<int>();
    std::vector<int> order;
    for (const auto& h : halves_) {
      const auto* perm = static_cast<const int*>(h->factor->Perm);
      for (int k = 0; k < h->interior; ++k) order.push_back(h->rows[static_cast<std::size_t>(perm[k])]);
    }
    order.insert(order.end(), separator_.begin(), separator_.end());
    return order;
  }

 private:
  // METIS's node bisector of a's graph and the analyses of both halves; false where the split does not serve.
  bool split(const SpMat& a) {
    if (!separates(a)) {
      partition_.assign(static_cast<std::size_t>(a.rows()), 0);
      cholmod_common common;
      cholmod_start(&common);
      common.print = 0;
      cholmod_sparse v = cholmod_lower_view(a, nullptr);
      const long s = cholmod_bisect(&v, nullptr, 0, 1, partition_.data(), &common);
      cholmod_finish(&common);
      if (s <= 0 || s > options_.max_separator) {
        partition_.clear();
        return false;
      }
    }
    separator_.clear();
    for (int k = 0; k < 2; ++k) halves_[k] = std::make_unique<Half>();
    for (int i = 0; i < a.rows(); ++i) {
      const int part = partition_[static_cast<std::size_t>(i)];
      (part == 2 ? separator_ : halves_[part]->rows).push_back(i);
    }
    for (auto& h : halves_) {
      h->interior = static_cast<int>(h->rows.size());
      if (5L * h->interior < a.rows()) return false;
      h->rows.insert(h->rows.end(), separator_.begin(), separator_.end());
    }
    bool ok[2] = {false, false};
#pragma omp parallel for num_threads(2) schedule(static, 1)
    for (int k = 0; k < 2; ++k) ok[k] = analyse(*halves_[k], a);
    if (!ok[0] || !ok[1]) return false;
    // Side by side, the half with more work sets the time, on one core, where the whole factorisation runs
    // on two at little more than one core's speed: the split pays until one half holds nearly all the work
    // (docs/performance.md, "The factorisation's input").
    const double larger = std::max(halves_[0]->flops, halves_[1]->flops);
    return larger <= options_.max_work_share * (halves_[0]->flops + halves_[1]->flops);
  }
  // Whether the last bisection still separates a's graph (no entry joins the two interiors): a new pattern
  // of the same model differs from the last one by the coupling's entries, which mostly stay within a half.
  // METIS's bisection is then kept, and the halves are only analysed anew.
  bool separates(const SpMat& a) const {
    if (partition_.size() != static_cast<std::size_t>(a.rows())) return false;
    for (int j = 0; j < a.cols(); ++j) {
      const int pj = partition_[static_cast<std::size_t>(j)];
      if (pj == 2) continue;
      for (int p = a.outerIndexPtr()[j]; p < a.outerIndexPtr()[j + 1]; ++p)
        if (partition_[static_cast<std::size_t>(a.innerIndexPtr()[p])] == 1 - pj) return false;
    }
    return true;
  }
  // T = C_0 C_0^T + C_1 C_1^T - K_SS and its LL^T (LAPACK, the configured BLAS threads); false where T is
  // not positive definite.
  bool schur(const SpMat& a) {
    const int s = static_cast<int>(separator_.size());
    t_.setZero(s, s);
    const Half& h = *halves_[0];  // -K_SS's lower triangle, from the first half's lower triangle
    const std::vector<int>& outer = h.lower_start;
    for (int c = 0; c < s; ++c)
      for (auto q = static_cast<std::size_t>(outer[static_cast<std::size_t>(h.interior + c)]);
           q < static_cast<std::size_t>(outer[static_cast<std::size_t>(h.interior + c) + 1]); ++q)
        t_(h.lower_rows[q] - h.interior, c) = -a.valuePtr()[h.source[q]];
    const double one = 1;
    for (const auto& h : halves_) dsyrk_("L", "N", &s, &s, &one, h->c.data(), &s, &one, t_.data(), &s);
    int info = 0;
    dpotrf_("L", &s, t_.data(), &s, &info);
    return info == 0;
  }
  std::string memory_refusal() const {
    const double limit = factorization_memory_limit(options_.memory_limit_megabytes);
    if (limit <= 0) return {};
    double needed = 3.0 * static_cast<double>(separator_.size() * separator_.size());
    for (const auto& h : halves_)
      if (h->factor->xtype == CHOLMOD_PATTERN) needed += static_cast<double>(h->factor->xsize + h->factor->maxcsize);
    needed *= sizeof(double);
    if (needed <= limit) return {};
    return "CHOLMOD's two factors would need " + std::to_string(std::lround(needed / (1 << 20))) +
           " MB, more than the limit of " + std::to_string(std::lround(limit / (1 << 20))) + " MB";
  }

  CholmodSplitOptions options_;
  bool split_ = false, factored_ = false;
  std::array<std::unique_ptr<Half>, 2> halves_;
  std::vector<int> partition_;  // of the last bisection: 0 or 1, the half of each row; 2 the separator
  std::vector<int> separator_;
  Eigen::MatrixXd t_;  // the separator's Schur complement's LL^T factor (lower)
  std::unique_ptr<LinearSolver> whole_;
  std::string refusal_;
};

}  // namespace

std::unique_ptr<LinearSolver> make_cholmod_split_llt(const CholmodSplitOptions& options) {
  return std::make_unique<CholmodSplitSolver>(options);
}

long cholmod_split_separator(const LinearSolver& solver) {
  const auto* split = dynamic_cast<const CholmodSplitSolver*>(&solver);
  return split ? split->separator() : 0;
}

std::vector<int> cholmod_split_pivot_order(const LinearSolver& solver) {
  const auto* split = dynamic_cast<const CholmodSplitSolver*>(&solver);
  return split ? split->pivot_order() : std::vector<int>();
}

}  // namespace fibrane::solve
