#include "linalg/rank_one_terms.hpp"

#include <algorithm>
#include <limits>

#include "linalg/linear_solver.hpp"

namespace fibrane::solve {

void RankOneTerms::on_rows(const std::vector<int>& rows, Eigen::MatrixXd& u, Eigen::VectorXd& c) const {
  std::vector<int> kept;
  for (int k = 0; k < size(); ++k) {
    if (coefficient[static_cast<std::size_t>(k)] == 0.0) continue;
    for (Eigen::SparseVector<double>::InnerIterator it(vector[static_cast<std::size_t>(k)]); it; ++it)
      if (it.value() != 0.0 && std::binary_search(rows.begin(), rows.end(), static_cast<int>(it.index()))) {
        kept.push_back(k);
        break;
      }
  }
  const auto m = static_cast<Eigen::Index>(kept.size());
  u.setZero(static_cast<Eigen::Index>(rows.size()), m);
  c.resize(m);
  for (Eigen::Index j = 0; j < m; ++j) {
    const auto k = static_cast<std::size_t>(kept[static_cast<std::size_t>(j)]);
    c[j] = coefficient[k];
    for (Eigen::SparseVector<double>::InnerIterator it(vector[k]); it; ++it) {
      const auto at = std::lower_bound(rows.begin(), rows.end(), static_cast<int>(it.index()));
      if (at != rows.end() && *at == it.index()) u(at - rows.begin(), j) = it.value();
    }
  }
}

Eigen::SparseMatrix<double> RankOneTerms::assembled(Eigen::Index n) const {
  std::vector<Eigen::Triplet<double>> t;
  for (int k = 0; k < size(); ++k) {
    const Eigen::SparseVector<double>& v = vector[static_cast<std::size_t>(k)];
    for (Eigen::SparseVector<double>::InnerIterator i(v); i; ++i)
      for (Eigen::SparseVector<double>::InnerIterator j(v); j; ++j)
        t.emplace_back(static_cast<int>(i.index()), static_cast<int>(j.index()),
                       coefficient[static_cast<std::size_t>(k)] * i.value() * j.value());
  }
  Eigen::SparseMatrix<double> sum(n, n);
  sum.setFromTriplets(t.begin(), t.end());
  return sum;
}

Eigen::VectorXd solve_with_rank_one_terms(const LinearSolver& a_solver, const Eigen::MatrixXd& u,
                                          const Eigen::VectorXd& c, const Eigen::VectorXd& b) {
  Eigen::VectorXd x = a_solver.solve(b);
  if (u.cols() == 0) return x;
  const Eigen::MatrixXd y = a_solver.solve_columns(u);
  // (A + U C U^T) x = b  <=>  x = A^-1 b - A^-1 U z,  (I + C U^T A^-1 U) z = C U^T A^-1 b
  const Eigen::MatrixXd g =
      Eigen::MatrixXd::Identity(u.cols(), u.cols()) + c.asDiagonal() * (u.transpose() * y);
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(g);
  if (!lu.isInvertible()) {
    x.setConstant(std::numeric_limits<double>::quiet_NaN());
    return x;
  }
  x.noalias() -= y * lu.solve((c.asDiagonal() * (u.transpose() * x)).eval());
  return x;
}

}  // namespace fibrane::solve
