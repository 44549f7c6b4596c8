#include "linalg/skew_correction.hpp"

#include <algorithm>
#include <cmath>

namespace fibrane::solve {

void SkewCorrection::dominate_support(Eigen::SparseMatrix<double>& s, const std::vector<int>& support) {
  for (int i : support) {  // column i holds row i's entries (s is symmetric)
    double off = 0;
    double* diagonal = nullptr;  // only an entry of the pattern: the analysis was made for it
    for (Eigen::SparseMatrix<double>::InnerIterator it(s, i); it; ++it)
      if (it.row() != i) off += std::abs(it.value());
      else diagonal = &it.valueRef();
    if (diagonal) *diagonal = std::max(*diagonal, off);
  }
}

bool SkewCorrection::prepare(const LinearSolver& symmetric, const Eigen::SparseMatrix<double>& k,
                             const Eigen::SparseMatrix<double>& s, std::vector<int> support) {
  support_ = std::move(support);
  const auto m = static_cast<Eigen::Index>(support_.size());
  Eigen::MatrixXd p = Eigen::MatrixXd::Zero(k.rows(), m);
  c_.resize(m, m);
  for (Eigen::Index a = 0; a < m; ++a) {
    p(support_[static_cast<size_t>(a)], a) = 1.0;
    for (Eigen::Index b = 0; b < m; ++b)
      c_(a, b) = k.coeff(support_[static_cast<size_t>(a)], support_[static_cast<size_t>(b)]) -
                 s.coeff(support_[static_cast<size_t>(a)], support_[static_cast<size_t>(b)]);
  }
  z_ = symmetric.solve_columns(p);
  Eigen::MatrixXd pz(m, m);
  for (Eigen::Index a = 0; a < m; ++a) pz.row(a) = z_.row(support_[static_cast<size_t>(a)]);
  const Eigen::MatrixXd mm = Eigen::MatrixXd::Identity(m, m) + c_ * pz;
  if (!mm.allFinite()) return false;
  m_.compute(mm);
  // PartialPivLU does not report singularity; its reciprocal condition estimate does.
  return m == 0 || m_.rcond() > 1e-14;
}

Eigen::VectorXd SkewCorrection::apply(const Eigen::VectorXd& y) const {
  if (support_.empty()) return y;
  Eigen::VectorXd py(static_cast<Eigen::Index>(support_.size()));
  for (size_t a = 0; a < support_.size(); ++a) py[static_cast<Eigen::Index>(a)] = y[support_[a]];
  return y - z_ * m_.solve(c_ * py);
}

void SkewCorrection::clear() {
  support_.clear();
  z_.resize(0, 0);
  c_.resize(0, 0);
}

}  // namespace fibrane::solve
