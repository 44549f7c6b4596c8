// A separator's dense front: assembly, partial LL^T (or LDL^T) and solves by LAPACK and BLAS (the algebra is in the
// header).
#include "linalg/dense_front.hpp"

#include <algorithm>

extern "C" {
void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info);
void dtrsm_(const char* side, const char* uplo, const char* transa, const char* diag, const int* m, const int* n,
            const double* alpha, const double* a, const int* lda, double* b, const int* ldb);
void dsyrk_(const char* uplo, const char* trans, const int* n, const int* k, const double* alpha, const double* a,
            const int* lda, const double* beta, double* c, const int* ldc);
void dsytrf_(const char* uplo, const int* n, double* a, const int* lda, int* ipiv, double* work, const int* lwork,
             int* info);
void dsytrs_(const char* uplo, const int* n, const int* nrhs, const double* a, const int* lda, const int* ipiv,
             double* b, const int* ldb, int* info);
void dgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k, const double* alpha,
            const double* a, const int* lda, const double* b, const int* ldb, const double* beta, double* c,
            const int* ldc);
}

namespace fibrane::solve {

void DenseFront::set(int separator, int boundary, std::vector<std::pair<int, long>> entries,
                     std::vector<std::vector<int>> child_maps) {
  s_ = separator;
  b_ = boundary;
  entries_ = std::move(entries);
  child_maps_ = std::move(child_maps);
  f_.resize(0, 0);
}

void DenseFront::assemble(const double* values) {
  f_.setZero(s_ + b_, s_ + b_);
  double* f = f_.data();
  for (const auto& [source, place] : entries_) f[place] += values[source];
}

void DenseFront::add(int child, Eigen::Ref<const Eigen::MatrixXd> u) {
  const std::vector<int>& map = child_maps_[static_cast<std::size_t>(child)];
  const auto n = static_cast<Eigen::Index>(map.size());
  for (Eigen::Index j = 0; j < n; ++j) {
    const int fj = map[static_cast<std::size_t>(j)];
    for (Eigen::Index i = j; i < n; ++i) {
      const int fi = map[static_cast<std::size_t>(i)];
      // the maps keep the order of rows, so (fi, fj) is in F's lower triangle
      f_(fi, fj) += u(i, j);
    }
  }
}

bool DenseFront::factorise() {
  const int n = s_ + b_;
  int info = 0;
  pivots_.clear();
  negative_ = 0;
  const Eigen::MatrixXd f_ss = f_.topLeftCorner(s_, s_);  // dpotrf overwrites what the LDL^T would need
  dpotrf_("L", &s_, f_.data(), &n, &info);
  if (info != 0) return factorise_ldlt(f_ss);
  if (b_ == 0) return true;
  const double one = 1, minus_one = -1;
  double* f_bs = f_.data() + s_;
  dtrsm_("R", "L", "T", "N", &b_, &s_, &one, f_.data(), &n, f_bs, &n);
  dsyrk_("L", "N", &b_, &s_, &minus_one, f_bs, &n, &one, f_bs + static_cast<long>(s_) * n, &n);
  return true;
}

bool DenseFront::factorise_ldlt(const Eigen::MatrixXd& f_ss) {
  const int n = s_ + b_;
  f_.topLeftCorner(s_, s_) = f_ss;
  pivots_.assign(static_cast<std::size_t>(std::max(s_, 1)), 0);
  int info = 0, query = -1;
  double size = 0;
  dsytrf_("L", &s_, f_.data(), &n, pivots_.data(), &size, &query, &info);
  std::vector<double> work(static_cast<std::size_t>(std::max(1.0, size)));
  const int lwork = static_cast<int>(work.size());
  dsytrf_("L", &s_, f_.data(), &n, pivots_.data(), work.data(), &lwork, &info);
  if (info != 0) {  // D singular (info > 0) or a bad argument
    pivots_.clear();
    return false;
  }
  for (int k = 0; k < s_;) {  // D's 1 x 1 blocks (IPIV > 0) and 2 x 2 blocks (two equal negative IPIVs)
    const double a = f_(k, k);
    if (pivots_[static_cast<std::size_t>(k)] > 0) {
      negative_ += a < 0;
      ++k;
      continue;
    }
    const double b = f_(k + 1, k), c = f_(k + 1, k + 1), det = a * c - b * b;
    negative_ += det < 0 ? 1 : (a + c < 0 ? 2 : 0);
    k += 2;
  }
  if (b_ == 0) return true;
  // W = F_SS^-1 F_BS^T, U = F_BB - F_BS W
  Eigen::MatrixXd w = f_.bottomLeftCorner(b_, s_).transpose();
  ldlt_solve(w.data(), b_, s_);
  const double one = 1, minus_one = -1;
  dgemm_("N", "N", &b_, &b_, &s_, &minus_one, f_.data() + s_, &n, w.data(), &s_, &one,
         f_.data() + s_ + static_cast<long>(s_) * n, &n);
  return true;
}

void DenseFront::ldlt_solve(double* x, int m, int ld) const {
  const int n = s_ + b_;
  int info = 0;
  dsytrs_("L", &s_, &m, f_.data(), &n, pivots_.data(), x, &ld, &info);
}

void DenseFront::drop_update() { f_.conservativeResize(Eigen::NoChange, s_); }

void DenseFront::forward(Eigen::MatrixXd& r) const {
  const int m = static_cast<int>(r.cols()), n = s_ + b_, ldr = static_cast<int>(r.rows());
  const double one = 1, minus_one = -1;
  if (ldlt())
    ldlt_solve(r.data(), m, ldr);
  else
    dtrsm_("L", "L", "N", "N", &s_, &m, &one, f_.data(), &n, r.data(), &ldr);
  if (b_ > 0) dgemm_("N", "N", &b_, &m, &s_, &minus_one, f_.data() + s_, &n, r.data(), &ldr, &one, r.data() + s_, &ldr);
}

void DenseFront::backward(Eigen::MatrixXd& y, const Eigen::MatrixXd& x_b) const {
  const int m = static_cast<int>(y.cols()), n = s_ + b_, ldy = static_cast<int>(y.rows());
  const double one = 1, minus_one = -1;
  if (ldlt()) {
    if (b_ == 0) return;
    Eigen::MatrixXd t = f_.bottomLeftCorner(b_, s_).transpose() * x_b;
    ldlt_solve(t.data(), m, s_);
    y.topRows(s_) -= t;
    return;
  }
  if (b_ > 0) {
    const int ldx = static_cast<int>(x_b.rows());
    dgemm_("T", "N", &s_, &m, &b_, &minus_one, f_.data() + s_, &n, x_b.data(), &ldx, &one, y.data(), &ldy);
  }
  dtrsm_("L", "L", "T", "N", &s_, &m, &one, f_.data(), &n, y.data(), &ldy);
}

long DenseFront::factor_entries() const {
  const long s = s_, b = b_;
  return s * (s + 1) / 2 + b * s;
}

double DenseFront::flops() const {
  const double s = s_, b = b_;
  return s * s * s / 3 + b * s * s + b * b * s;
}

}  // namespace fibrane::solve
