#pragma once
// The lower triangle of a principal submatrix, as index arrays that point into the whole matrix's values.
#include <Eigen/SparseCore>
#include <vector>

namespace fibrane::solve {

/// The pattern of the lower triangle of a(rows, rows) (rows in the given order) in compressed columns, each
/// column's rows sorted, and for each entry its index in a's value array. `a` is compressed and holds its
/// lower triangle or both triangles (an entry (i, j) of a with i >= j is read once).
struct PrincipalLower {
  std::vector<int> column_start, row;  // column_start has rows.size() + 1 entries
  std::vector<int> source;
  int size() const { return static_cast<int>(column_start.size()) - 1; }
};
PrincipalLower principal_lower(const Eigen::SparseMatrix<double>& a, const std::vector<int>& rows);

}  // namespace fibrane::solve
