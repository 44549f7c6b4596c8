// principal_lower: the lower triangle of a(rows, rows) with each entry's place in a's values, for rows in
// ascending order (one pass over the columns, side by side on threads), in any order (two counting sorts),
// and for a matrix whose columns are not sorted (the ascending rows then take the counting sorts).
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <map>
#include <random>
#include <utility>

#include "linalg/principal_lower.hpp"

namespace fibrane::solve {
namespace {

using SpMat = Eigen::SparseMatrix<double>;

// A random symmetric pattern of n rows (both triangles, the diagonal full), each stored entry's value its
// own index in the value array, so that a source is checked by the value found there.
SpMat numbered_symmetric(int n, double density, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Eigen::Triplet<double>> t;
  for (int j = 0; j < n; ++j) {
    t.emplace_back(j, j, 1.0);
    for (int i = j + 1; i < n; ++i)
      if (u(rng) < density) t.emplace_back(i, j, 1.0), t.emplace_back(j, i, 1.0);
  }
  SpMat a(n, n);
  a.setFromTriplets(t.begin(), t.end());
  a.makeCompressed();
  for (int p = 0; p < a.nonZeros(); ++p) a.valuePtr()[p] = p;
  return a;
}

// The expected entries: (local row, local column) with row >= column, to the index in a's values of the
// entry (i, j) of a's lower triangle (i >= j) that it comes from.
std::map<std::pair<int, int>, int> expected_entries(const SpMat& a, const std::vector<int>& rows) {
  std::map<int, int> local;
  for (int k = 0; k < static_cast<int>(rows.size()); ++k) local[rows[static_cast<std::size_t>(k)]] = k;
  std::map<std::pair<int, int>, int> out;
  for (int j = 0; j < a.cols(); ++j)
    for (int p = a.outerIndexPtr()[j]; p < a.outerIndexPtr()[j + 1]; ++p) {
      const int i = a.innerIndexPtr()[p];
      if (i < j || !local.count(i) || !local.count(j)) continue;
      const int li = local[i], lj = local[j];
      out[{std::max(li, lj), std::min(li, lj)}] = p;
    }
  return out;
}

// Checks `got` against the expected entries, and that every column's rows are strictly ascending.
void expect_principal_lower(const SpMat& a, const std::vector<int>& rows, const PrincipalLower& got) {
  ASSERT_EQ(got.size(), static_cast<int>(rows.size()));
  const auto expected = expected_entries(a, rows);
  ASSERT_EQ(got.row.size(), expected.size());
  ASSERT_EQ(got.source.size(), expected.size());
  for (int c = 0; c < got.size(); ++c)
    for (int q = got.column_start[static_cast<std::size_t>(c)]; q < got.column_start[static_cast<std::size_t>(c) + 1]; ++q) {
      const int r = got.row[static_cast<std::size_t>(q)];
      if (q > got.column_start[static_cast<std::size_t>(c)]) {
        ASSERT_LT(got.row[static_cast<std::size_t>(q) - 1], r);
      }
      const auto it = expected.find({r, c});
      ASSERT_NE(it, expected.end()) << "entry (" << r << ", " << c << ")";
      EXPECT_EQ(got.source[static_cast<std::size_t>(q)], it->second);
    }
}

std::vector<int> random_rows(int n, int count, unsigned seed) {
  std::vector<int> all(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) all[static_cast<std::size_t>(i)] = i;
  std::mt19937 rng(seed);
  std::shuffle(all.begin(), all.end(), rng);
  all.resize(static_cast<std::size_t>(count));
  return all;
}

TEST(PrincipalLower, RowsInAnyOrder) {
  const SpMat a = numbered_symmetric(300, 0.05, 1);
  const std::vector<int> rows = random_rows(300, 170, 2);
  expect_principal_lower(a, rows, principal_lower(a, rows));
}

// Ascending rows above the threshold of the threaded pass (10 000), on one thread and on three: the same
// arrays either way.
TEST(PrincipalLower, AscendingRowsOnAnyNumberOfThreads) {
  const SpMat a = numbered_symmetric(12'500, 0.0008, 3);
  std::vector<int> rows = random_rows(12'500, 11'000, 4);
  std::sort(rows.begin(), rows.end());
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const PrincipalLower one = principal_lower(a, rows);
  omp_set_num_threads(3);
  const PrincipalLower three = principal_lower(a, rows);
  omp_set_num_threads(threads);
  expect_principal_lower(a, rows, one);
  EXPECT_EQ(one.column_start, three.column_start);
  EXPECT_EQ(one.row, three.row);
  EXPECT_EQ(one.source, three.source);
  const std::vector<int> descending(rows.rbegin(), rows.rend());  // the counting sorts
  expect_principal_lower(a, descending, principal_lower(a, descending));
}

// A column of a whose rows are not in ascending order: the one-pass path refuses it, and the counting sorts
// still give every column sorted.
TEST(PrincipalLower, UnsortedColumnsOfTheMatrix) {
  SpMat a = numbered_symmetric(200, 0.08, 5);
  int column = -1;
  for (int j = 0; j < a.cols() && column < 0; ++j)
    if (a.outerIndexPtr()[j + 1] - a.outerIndexPtr()[j] >= 4) column = j;
  ASSERT_GE(column, 0);
  const int last = a.outerIndexPtr()[column + 1] - 1;
  std::swap(a.innerIndexPtr()[last], a.innerIndexPtr()[last - 1]);
  std::vector<int> rows(200);
  for (int i = 0; i < 200; ++i) rows[static_cast<std::size_t>(i)] = i;
  const PrincipalLower got = principal_lower(a, rows);
  expect_principal_lower(a, rows, got);
}

}  // namespace
}  // namespace fibrane::solve
