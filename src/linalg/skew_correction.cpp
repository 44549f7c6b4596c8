#include "linalg/skew_correction.hpp"

#include <algorithm>
#include <cmath>

namespace fibrane::solve {

bool SkewCorrection::symmetrize(Eigen::SparseMatrix<double>& k, std::vector<int> support) {
  clear();
  const int* outer = k.outerIndexPtr();
  const int* inner = k.innerIndexPtr();
  double* v = k.valuePtr();
  const auto m = static_cast<Eigen::Index>(support.size());
  std::vector<int> mirror, diagonal(support.size(), -1);
  std::vector<std::pair<Eigen::Index, Eigen::Index>> place;  // (row, column) in the block
  for (Eigen::Index b = 0; b < m; ++b) {
    const int col = support[static_cast<size_t>(b)];
    for (int q = outer[col]; q < outer[col + 1]; ++q) {
      const int row = inner[q];
      const auto in_support = std::lower_bound(support.begin(), support.end(), row);
      if (in_support == support.end() || *in_support != row) continue;
      const int* found = std::lower_bound(inner + outer[row], inner + outer[row + 1], col);
      if (found == inner + outer[row + 1] || *found != col) {
        clear();
        return false;
      }
      changed_.push_back(q);
      mirror.push_back(static_cast<int>(found - inner));
      place.emplace_back(in_support - support.begin(), b);
      if (row == col) diagonal[static_cast<size_t>(b)] = q;
    }
  }
  for (const int q : changed_) original_.push_back(v[q]);
  std::vector<double> part(changed_.size());
  for (std::size_t t = 0; t < changed_.size(); ++t) part[t] = 0.5 * (v[changed_[t]] + v[mirror[t]]);
  for (std::size_t t = 0; t < changed_.size(); ++t) v[changed_[t]] = part[t];
  for (Eigen::Index b = 0; b < m; ++b) {  // column b holds row b's entries (S is symmetric)
    const int col = support[static_cast<size_t>(b)];
    const int d = diagonal[static_cast<size_t>(b)];
    if (d < 0) continue;  // only an entry of the pattern: the analysis was made for it
    double off = 0;
    for (int q = outer[col]; q < outer[col + 1]; ++q)
      if (q != d) off += std::abs(v[q]);
    v[d] = std::max(v[d], off);
  }
  c_ = Eigen::MatrixXd::Zero(m, m);
  for (std::size_t t = 0; t < changed_.size(); ++t) c_(place[t].first, place[t].second) = original_[t] - v[changed_[t]];
  support_ = std::move(support);
  rows_ = k.rows();
  return true;
}

void SkewCorrection::restore(Eigen::SparseMatrix<double>& k) const {
  double* v = k.valuePtr();
  for (std::size_t t = 0; t < changed_.size(); ++t) v[changed_[t]] = original_[t];
}

bool SkewCorrection::prepare(const LinearSolver& symmetric) {
  const auto m = static_cast<Eigen::Index>(support_.size());
  Eigen::MatrixXd p = Eigen::MatrixXd::Zero(rows_, m);
  for (Eigen::Index a = 0; a < m; ++a) p(support_[static_cast<size_t>(a)], a) = 1.0;
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
  changed_.clear();
  original_.clear();
  z_.resize(0, 0);
  c_.resize(0, 0);
}

}  // namespace fibrane::solve
