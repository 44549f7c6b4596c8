#include "linalg/principal_lower.hpp"

#include <algorithm>
#include <numeric>

namespace fibrane::solve {

// Two counting sorts (the entries by row, then by column in the order of their rows) leave every column's
// rows sorted.
PrincipalLower principal_lower(const Eigen::SparseMatrix<double>& a, const std::vector<int>& rows) {
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
  PrincipalLower out;
  out.column_start.assign(static_cast<std::size_t>(n) + 1, 0);
  for (const int c : row_column) ++out.column_start[static_cast<std::size_t>(c) + 1];
  std::partial_sum(out.column_start.begin(), out.column_start.end(), out.column_start.begin());
  next.assign(out.column_start.begin(), out.column_start.end() - 1);
  out.row.resize(entries);
  out.source.resize(entries);
  for (int r = 0; r < n; ++r)
    for (auto k = static_cast<std::size_t>(row_start[static_cast<std::size_t>(r)]);
         k < static_cast<std::size_t>(row_start[static_cast<std::size_t>(r) + 1]); ++k) {
      const auto q = static_cast<std::size_t>(next[static_cast<std::size_t>(row_column[k])]++);
      out.row[q] = r;
      out.source[q] = row_source[k];
    }
  return out;
}

}  // namespace fibrane::solve
