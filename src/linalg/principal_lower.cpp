#include "linalg/principal_lower.hpp"

#include <algorithm>
#include <functional>
#include <numeric>

namespace fibrane::solve {

namespace {

// Rows in ascending order keep a's order within each column, so that column j = rows[c] of a, less its
// entries above the diagonal and outside `rows`, is column c of the result: one pass, the columns side by
// side on the process's threads. False where a column's entries in a are not sorted (out is then unfinished).
bool ascending_principal_lower(const Eigen::SparseMatrix<double>& a, const std::vector<int>& rows,
                               const std::vector<int>& local, PrincipalLower& out) {
  const int n = static_cast<int>(rows.size());
  const int* outer = a.outerIndexPtr();
  const int* inner = a.innerIndexPtr();
  out.column_start.assign(static_cast<std::size_t>(n) + 1, 0);
  int unsorted = 0;
#pragma omp parallel for schedule(static) reduction(+ : unsorted) if (n >= 10'000)
  for (int c = 0; c < n; ++c) {
    const int j = rows[static_cast<std::size_t>(c)];
    int count = 0, last = -1;
    for (int p = outer[j]; p < outer[j + 1]; ++p) {
      const int i = inner[p];
      if (i < j || local[static_cast<std::size_t>(i)] < 0) continue;
      unsorted += i <= last ? 1 : 0;
      last = i;
      ++count;
    }
    out.column_start[static_cast<std::size_t>(c) + 1] = count;
  }
  if (unsorted > 0) return false;
  std::partial_sum(out.column_start.begin(), out.column_start.end(), out.column_start.begin());
  out.row.resize(static_cast<std::size_t>(out.column_start.back()));
  out.source.resize(out.row.size());
#pragma omp parallel for schedule(static) if (n >= 10'000)
  for (int c = 0; c < n; ++c) {
    const int j = rows[static_cast<std::size_t>(c)];
    auto q = static_cast<std::size_t>(out.column_start[static_cast<std::size_t>(c)]);
    for (int p = outer[j]; p < outer[j + 1]; ++p) {
      const int i = inner[p], li = local[static_cast<std::size_t>(i)];
      if (i < j || li < 0) continue;
      out.row[q] = li;
      out.source[q++] = p;
    }
  }
  return true;
}

}  // namespace

// Rows in any order: two counting sorts (the entries by row, then by column in the order of their rows)
// leave every column's rows sorted.
PrincipalLower principal_lower(const Eigen::SparseMatrix<double>& a, const std::vector<int>& rows) {
  const int n = static_cast<int>(rows.size());
  std::vector<int> local(static_cast<std::size_t>(a.rows()), -1);
  for (int i = 0; i < n; ++i) local[static_cast<std::size_t>(rows[static_cast<std::size_t>(i)])] = i;
  PrincipalLower out;
  const bool ascending = std::adjacent_find(rows.begin(), rows.end(), std::greater_equal<>()) == rows.end();
  if (ascending && ascending_principal_lower(a, rows, local, out)) return out;
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
