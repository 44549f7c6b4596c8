// One domain of the split Cholesky: CHOLMOD's LL^T with the boundary last (the algebra is in the header).
#include "linalg/cholmod_domain.hpp"

#include <algorithm>
#include <limits>

#include "linalg/linear_solver.hpp"

extern "C" void dsyrk_(const char* uplo, const char* trans, const int* n, const int* k, const double* alpha,
                       const double* a, const int* lda, const double* beta, double* c, const int* ldc);

namespace fibrane::solve {

CholmodDomain::CholmodDomain() {
  cholmod_start(&common);
  common.print = 0;
  common.supernodal = CHOLMOD_SUPERNODAL;
}

CholmodDomain::~CholmodDomain() {
  cholmod_free_factor(&factor, &common);
  permuted.clear();
  cholmod_finish(&common);
}

bool CholmodDomain::analyse(const Eigen::SparseMatrix<double>& a) {
  PrincipalLower next = principal_lower(a, rows);
  kept_analysis = factor && next.column_start == lower.column_start && next.row == lower.row;
  lower = std::move(next);
  // What the last factorisation left that depends on where H's entries lie in a's values, or on its
  // outcome: the permuted triangle's map into a's values and MUMPS's analysis are made again at their
  // first use, and LL^T is tried first.
  permuted.clear();
  ldlt.reset();
  ldlt_first_ = false;
  indefinite = false;
  negative = 0;
  c.resize(0, 0);
  if (kept_analysis) return true;
  // CAMD's constrained minimum degree (the boundary a constraint set after the interior), which needed
  // fewer flops than METIS's order of the interior alone or of the whole domain with the boundary moved
  // last (docs/performance.md, "The factorisation's input").
  std::vector<int> order(static_cast<std::size_t>(size())), member(order.size(), 0);
  std::fill(member.begin() + interior, member.end(), 1);
  cholmod_sparse hv = cholmod_lower_view(size(), lower.column_start.data(), lower.row.data(), nullptr);
  if (!cholmod_camd(&hv, nullptr, 0, member.data(), order.data(), &common)) return false;
  // CHOLMOD's postorder of the elimination tree keeps the boundary, the top of its tree, last, unless the
  // interior has parts that the boundary does not join (a forest), whose trees the postorder may put after
  // it: then CAMD's order is taken as it is.
  for (const bool postorder : {true, false}) {
    cholmod_free_factor(&factor, &common);
    common.nmethods = 1;
    common.method[0].ordering = CHOLMOD_GIVEN;
    common.postorder = postorder;
    factor = cholmod_analyze_p(&hv, order.data(), nullptr, 0, &common);
    common.nmethods = 0;
    common.postorder = true;
    flops = common.fl;
    if (!factor || !factor->is_super) return false;
    if (boundary_last()) return true;
  }
  return false;
}

// Whether the factor's order keeps the boundary last; boundary_order[t]: the boundary row of the factor's
// column interior + t.
bool CholmodDomain::boundary_last() {
  const auto* perm = static_cast<const int*>(factor->Perm);
  boundary_order.assign(perm + interior, perm + size());
  std::vector<char> seen(static_cast<std::size_t>(boundary()), 0);
  for (int& r : boundary_order) {
    r -= interior;
    if (r < 0 || seen[static_cast<std::size_t>(r)]) return false;
    seen[static_cast<std::size_t>(r)] = 1;
  }
  return true;
}

bool CholmodDomain::factorise(const Eigen::SparseMatrix<double>& a) {
  indefinite = false;
  negative = 0;
  const bool llt_first = !ldlt_first_;
  // After an LL^T, MUMPS's factor (and its analysis) is freed: the next LDL^T analyses anew.
  if (llt_first && factorise_llt(a)) return ldlt.reset(), true;
  const bool ok = factorise_ldlt(a);
  ldlt_first_ = ok && negative > 0;
  if (ok) return true;
  if (llt_first || !factorise_llt(a)) return false;
  ldlt.reset();
  return true;
}

bool CholmodDomain::factorise_ldlt(const Eigen::SparseMatrix<double>& a) {
  if (!MumpsSchur::available()) return false;
  cholmod_change_factor(CHOLMOD_PATTERN, factor->is_ll, factor->is_super, true, true, factor, &common);
  c.resize(0, 0);
  if (!ldlt) {  // MUMPS analyses the pattern with CHOLMOD's pivot order, the boundary last
    std::vector<int> rows_of, columns_of;
    for (int j = 0; j < size(); ++j)
      for (int q = lower.column_start[static_cast<std::size_t>(j)]; q < lower.column_start[static_cast<std::size_t>(j) + 1]; ++q) {
        rows_of.push_back(lower.row[static_cast<std::size_t>(q)]);
        columns_of.push_back(j);
      }
    const auto* perm = static_cast<const int*>(factor->Perm);
    std::vector<int> order(perm, perm + interior);  // MUMPS wants the Schur rows last in their own order
    for (int r = interior; r < size(); ++r) order.push_back(r);
    ldlt = std::make_unique<MumpsSchur>();
    if (!ldlt->analyse(size(), boundary(), rows_of, columns_of, order)) {
      ldlt.reset();
      return false;
    }
  }
  std::vector<double> values(lower.source.size());
  for (std::size_t q = 0; q < values.size(); ++q) values[q] = a.valuePtr()[lower.source[q]];
  if (!ldlt->factorise(values.data())) return false;
  indefinite = true;
  negative = ldlt->negative_pivots();
  return true;
}

bool CholmodDomain::factorise_llt(const Eigen::SparseMatrix<double>& a) {
  if (!permuted.built()) {
    cholmod_sparse hv = cholmod_lower_view(size(), lower.column_start.data(), lower.row.data(), nullptr);
    if (!permuted.build(hv, *factor, common)) return false;
    permuted.map_through(lower.source);
  }
  double beta[2] = {0, 0};
  cholmod_sparse* values = permuted.fill(a.valuePtr());
  const SerialLibraryRegions serial;
  const int ok = cholmod_super_numeric(values, nullptr, beta, factor, &common);
  permuted.drop_values();
  if (!ok || common.status != CHOLMOD_OK || factor->minor < factor->n) return false;
  // C: the columns from the interior's end on, in their supernodes (column-major blocks of nsrow rows).
  const int b = boundary();
  c.setZero(b, b);
  const auto* super = static_cast<const int*>(factor->super);
  const auto* pi = static_cast<const int*>(factor->pi);
  const auto* px = static_cast<const int*>(factor->px);
  const auto* ls = static_cast<const int*>(factor->s);
  const auto* lx = static_cast<const double*>(factor->x);
  for (size_t sn = 0; sn < factor->nsuper; ++sn) {
    const int k1 = super[sn], k2 = super[sn + 1], nsrow = pi[sn + 1] - pi[sn];
    for (int j = std::max(k1, interior); j < k2; ++j)
      for (int r = j - k1; r < nsrow; ++r)
        c(boundary_order[static_cast<std::size_t>(ls[pi[sn] + r] - interior)], j - interior) =
            lx[px[sn] + (j - k1) * nsrow + r];
  }
  return true;
}

Eigen::MatrixXd CholmodDomain::update(const Eigen::SparseMatrix<double>& a) const {
  const int b = boundary();
  Eigen::MatrixXd u = indefinite ? ldlt->schur() : Eigen::MatrixXd::Zero(b, b);
  for (int col = 0; col < b; ++col)  // -K_BB's lower triangle, from the domain's lower triangle
    for (auto q = static_cast<std::size_t>(lower.column_start[static_cast<std::size_t>(interior + col)]);
         q < static_cast<std::size_t>(lower.column_start[static_cast<std::size_t>(interior + col) + 1]); ++q)
      u(lower.row[q] - interior, col) -= a.valuePtr()[lower.source[q]];
  const double one = 1;
  if (b > 0 && !indefinite) dsyrk_("L", "N", &b, &b, &one, c.data(), &b, &one, u.data(), &b);
  return u;
}

Eigen::MatrixXd CholmodDomain::forward(const Eigen::MatrixXd& local) {
  if (!indefinite) return solve(CHOLMOD_L, solve(CHOLMOD_P, local));
  Eigen::MatrixXd y(size() + boundary(), local.cols());
  Eigen::MatrixXd state = local;
  y.bottomRows(boundary()) = ldlt->reduce(state);
  y.topRows(size()) = state;
  return y;
}

Eigen::MatrixXd CholmodDomain::boundary_share(const Eigen::MatrixXd& y) const {
  if (indefinite) return y.bottomRows(boundary());
  return c * y.bottomRows(boundary());
}

Eigen::MatrixXd CholmodDomain::backward(Eigen::MatrixXd& y, const Eigen::MatrixXd& x_b) {
  if (indefinite) {
    Eigen::MatrixXd state = y.topRows(size());
    ldlt->expand(state, x_b);
    return state.topRows(interior);
  }
  y.bottomRows(boundary()).noalias() = c.transpose() * x_b;
  return solve(CHOLMOD_Pt, solve(CHOLMOD_Lt, y)).topRows(interior);
}

long CholmodDomain::factor_entries() const {
  const long llt = factor && factor->xtype != CHOLMOD_PATTERN ? static_cast<long>(factor->xsize) : 0;
  return llt + (ldlt ? ldlt->factor_entries() : 0);
}

Eigen::MatrixXd CholmodDomain::solve(int sys, const Eigen::MatrixXd& b) {
  cholmod_dense in{};
  in.nrow = static_cast<size_t>(b.rows());
  in.ncol = static_cast<size_t>(b.cols());
  in.nzmax = in.nrow * in.ncol;
  in.d = in.nrow;
  in.x = const_cast<double*>(b.data());
  in.xtype = CHOLMOD_REAL;
  in.dtype = CHOLMOD_DOUBLE;
  cholmod_dense* out = cholmod_solve(sys, factor, &in, &common);
  if (!out) return Eigen::MatrixXd::Constant(b.rows(), b.cols(), std::numeric_limits<double>::quiet_NaN());
  Eigen::MatrixXd x = Eigen::Map<const Eigen::MatrixXd>(static_cast<const double*>(out->x), b.rows(), b.cols());
  cholmod_free_dense(&out, &common);
  return x;
}

void CholmodDomain::release() {
  c.resize(0, 0);
  ldlt.reset();
  indefinite = false;
  if (!factor) return;
  cholmod_change_factor(CHOLMOD_PATTERN, factor->is_ll, factor->is_super, true, true, factor, &common);
  permuted.release_values();
}

}  // namespace fibrane::solve
