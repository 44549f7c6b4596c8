#include "path/local_correction.hpp"

#include <algorithm>
#include <cmath>
#include <span>

#include "linalg/linear_solver.hpp"

namespace fibrane::solve {

std::vector<int> local_rows(const Eigen::VectorXd& r, const Eigen::SparseMatrix<double>& k,
                            const LocalRowsOptions& options, const RowUnion& unite) {
  const int n = static_cast<int>(r.size());
  std::vector<char> in(static_cast<std::size_t>(n), 0);
  std::vector<int> frontier;
  const double level = options.seed_level * r.cwiseAbs().maxCoeff();
  for (int i = 0; i < n; ++i)
    if (std::abs(r[i]) >= level && level > 0) {
      in[static_cast<std::size_t>(i)] = 1;
      frontier.push_back(i);
    }
  std::size_t count = frontier.size();
  const double wanted = options.share * n;
  // Breadth first through k's columns: each layer adds the rows coupled to the last one's. The set after
  // a layer does not depend on the order in which the frontier is visited.
  std::vector<char> added(unite ? static_cast<std::size_t>(n) : 0, 0);
  for (int layer = 0; layer < options.max_layers && static_cast<double>(count) < wanted && !frontier.empty();
       ++layer) {
    std::vector<int> next;
    for (const int j : frontier)
      for (Eigen::SparseMatrix<double>::InnerIterator it(k, j); it; ++it) {
        const auto i = static_cast<std::size_t>(it.row());
        if (!in[i]) {
          in[i] = 1;
          next.push_back(static_cast<int>(i));
        }
      }
    if (unite) {  // the layer as the other processes' summands grow it too
      for (const int i : next) added[static_cast<std::size_t>(i)] = 1;
      unite(added);
      next.clear();
      for (int i = 0; i < n; ++i)
        if (added[static_cast<std::size_t>(i)]) {
          added[static_cast<std::size_t>(i)] = 0;
          in[static_cast<std::size_t>(i)] = 1;
          next.push_back(i);
        }
    }
    count += next.size();
    frontier.swap(next);
  }
  std::vector<int> rows;
  rows.reserve(count);
  for (int i = 0; i < n; ++i)
    if (in[static_cast<std::size_t>(i)]) rows.push_back(i);
  return rows;
}

Eigen::SparseMatrix<double> principal_submatrix(const Eigen::SparseMatrix<double>& k, const std::vector<int>& rows) {
  const int m = static_cast<int>(rows.size());
  std::vector<int> local(static_cast<std::size_t>(k.rows()), -1);
  for (int a = 0; a < m; ++a) local[static_cast<std::size_t>(rows[static_cast<std::size_t>(a)])] = a;
  // Column by column: the rows of each of S's columns that lie in S keep k's row order, which the sorted
  // `rows` map to increasing local indices.
  Eigen::SparseMatrix<double> kss(m, m);
  std::vector<int> column_start(static_cast<std::size_t>(m) + 1, 0);
  for (int a = 0; a < m; ++a) {
    int entries = 0;
    for (Eigen::SparseMatrix<double>::InnerIterator it(k, rows[static_cast<std::size_t>(a)]); it; ++it)
      entries += local[static_cast<std::size_t>(it.row())] >= 0;
    column_start[static_cast<std::size_t>(a) + 1] = column_start[static_cast<std::size_t>(a)] + entries;
  }
  kss.resizeNonZeros(column_start.back());
  std::copy(column_start.begin(), column_start.end(), kss.outerIndexPtr());
  for (int a = 0; a < m; ++a) {
    int p = column_start[static_cast<std::size_t>(a)];
    for (Eigen::SparseMatrix<double>::InnerIterator it(k, rows[static_cast<std::size_t>(a)]); it; ++it) {
      const int i = local[static_cast<std::size_t>(it.row())];
      if (i < 0) continue;
      kss.innerIndexPtr()[p] = i;
      kss.valuePtr()[p++] = it.value();
    }
  }
  return kss;
}

namespace {

// r on the rows S.
Eigen::VectorXd rows_of(const Eigen::VectorXd& r, const std::vector<int>& rows) {
  Eigen::VectorXd rs(static_cast<Eigen::Index>(rows.size()));
  for (std::size_t a = 0; a < rows.size(); ++a) rs[static_cast<Eigen::Index>(a)] = r[rows[a]];
  return rs;
}

// The update ds on S spread to all n rows (dq = 0 elsewhere); false, dq untouched, for a non-finite ds.
bool spread(const Eigen::VectorXd& ds, const std::vector<int>& rows, Eigen::Index n, Eigen::VectorXd& dq) {
  if (!ds.allFinite()) return false;
  dq.setZero(n);
  for (std::size_t a = 0; a < rows.size(); ++a) dq[rows[a]] = ds[static_cast<Eigen::Index>(a)];
  return true;
}

bool fits(const Eigen::SparseMatrix<double>& kss, const std::vector<int>& rows) {
  const auto m = static_cast<Eigen::Index>(rows.size());
  return m > 0 && kss.rows() == m && kss.cols() == m;
}

}  // namespace

Eigen::SparseMatrix<double> local_matrix(const Eigen::SparseMatrix<double>& tangent, const std::vector<int>& rows,
                                         const RankOneTerms& apart) {
  Eigen::SparseMatrix<double> kss = principal_submatrix(tangent, rows);
  if (apart.empty()) return kss;
  // Exact zeros go only within the blocks of the terms' elements (RankOneTerms::fill_rows), so that elsewhere
  // K_SS keeps the tangent's pattern, structurally symmetric.
  std::vector<char> fill(rows.size(), 0);
  for (const int r : apart.fill_rows) {
    const auto at = std::lower_bound(rows.begin(), rows.end(), r);
    if (at != rows.end() && *at == r) fill[static_cast<std::size_t>(at - rows.begin())] = 1;
  }
  kss.prune([&fill](Eigen::Index i, Eigen::Index j, double v) {
    return v != 0.0 || !fill[static_cast<std::size_t>(i)] || !fill[static_cast<std::size_t>(j)];
  });
  return kss;
}

bool local_update(const Eigen::VectorXd& r, const Eigen::SparseMatrix<double>& kss, const RankOneTerms& apart,
                  bool symmetric, const std::vector<int>& rows, Eigen::VectorXd& dq) {
  LocalFactorization once;
  return once.update(r, kss, apart, symmetric, rows, 0, dq);
}

bool LocalFactorization::update(const Eigen::VectorXd& r, const Eigen::SparseMatrix<double>& kss,
                                const RankOneTerms& apart, bool symmetric, const std::vector<int>& rows,
                                int pattern_version, Eigen::VectorXd& dq) {
  if (!fits(kss, rows)) return false;
  const std::span<const int> starts(kss.outerIndexPtr(), static_cast<std::size_t>(kss.cols()) + 1);
  const std::span<const int> indices(kss.innerIndexPtr(), static_cast<std::size_t>(kss.nonZeros()));
  const bool same = solver_ && symmetric == symmetric_ && pattern_version == pattern_version_ && rows == rows_ &&
                    std::ranges::equal(starts, column_start_) && std::ranges::equal(indices, row_index_);
  if (!same) {
    solver_.reset();  // its factor first, before the new one is made
    solver_ = make_linear_solver("auto", symmetric);
    solver_->analyze(kss);
    ++analyses_;
    rows_ = rows;
    pattern_version_ = pattern_version;
    column_start_.assign(starts.begin(), starts.end());
    row_index_.assign(indices.begin(), indices.end());
    symmetric_ = symmetric;
  }
  ++factorizations_;
  if (!solver_->factorize(kss)) {
    solver_.reset();
    return false;
  }
  Eigen::MatrixXd u;
  Eigen::VectorXd c;
  apart.on_rows(rows, u, c);
  return spread(solve_with_rank_one_terms(*solver_, u, c, -rows_of(r, rows)), rows, r.size(), dq);
}

void LocalFactorization::release() {
  solver_.reset();
  column_start_ = {};
  row_index_ = {};
}

}  // namespace fibrane::solve
