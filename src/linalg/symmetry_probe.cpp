#include "linalg/symmetry_probe.hpp"

#include <algorithm>
#include <cmath>

#include "common/system_memory.hpp"

namespace fibrane::solve {

// One pass: walking the columns in order meets the entries (row, col) of a fixed row in increasing col,
// which is the order of their mirrors (col, row) in column `row`, so a cursor per column finds them
// without a binary search per entry (docs/performance.md, "Linear solver").
void SymmetryProbe::build(const Eigen::SparseMatrix<double>& a) {
  release_storage(mirror_);  // the last pattern's map goes before the new one is built
  structurally_symmetric_ = false;
  if (a.rows() != a.cols() || !a.isCompressed()) return;
  const int* outer = a.outerIndexPtr();
  const int* inner = a.innerIndexPtr();
  std::vector<int> next(outer, outer + a.cols());
  std::vector<int> mirror(static_cast<size_t>(a.nonZeros()));
  for (Eigen::Index col = 0; col < a.cols(); ++col)
    for (int k = outer[col]; k < outer[col + 1]; ++k) {
      const int row = inner[k];
      const int m = next[row]++;
      if (m >= outer[row + 1] || inner[m] != col) return;
      mirror[static_cast<size_t>(k)] = m;
    }
  mirror_ = std::move(mirror);
  structurally_symmetric_ = true;
}

// Assembled tangents of symmetric element matrices differ from their transpose by summation-order
// round-off only (~1e-16 relative, measured 1e-16 on the bending example), while a genuinely unsymmetric
// load stiffness differs at O(load) level.
bool SymmetryProbe::symmetric(const Eigen::SparseMatrix<double>& a) const {
  return structurally_symmetric_ && a.nonZeros() == size() && skew_support(a).empty();
}

// One pass over the values, columns shared among the threads: each column's largest |a_ij - a_ji| and the
// largest |a_ij|, then the columns above the tolerance. A differing entry's mirror differs as much, so the
// columns that hold one are the rows that do, and no two threads write the same place.
std::vector<int> SymmetryProbe::skew_support(const Eigen::SparseMatrix<double>& a) const {
  if (!structurally_symmetric_ || a.nonZeros() != size()) return {};
  const double* v = a.valuePtr();
  const int* outer = a.outerIndexPtr();
  const Eigen::Index n = a.cols();
  std::vector<double> difference(static_cast<size_t>(n), 0.0);
  double largest = 0;
#pragma omp parallel for reduction(max : largest) schedule(static) if (a.nonZeros() > 200000)
  for (Eigen::Index col = 0; col < n; ++col) {
    double column_difference = 0;
    for (int k = outer[col]; k < outer[col + 1]; ++k) {
      largest = std::max(largest, std::abs(v[k]));
      column_difference = std::max(column_difference, std::abs(v[k] - v[mirror_[static_cast<size_t>(k)]]));
    }
    difference[static_cast<size_t>(col)] = column_difference;
  }
  const double tolerance = 1e-12 * largest;
  std::vector<int> rows;
  for (Eigen::Index i = 0; i < n; ++i)
    if (difference[static_cast<size_t>(i)] > tolerance) rows.push_back(static_cast<int>(i));
  return rows;
}

void SymmetryProbe::symmetric_part(const Eigen::SparseMatrix<double>& a, Eigen::SparseMatrix<double>& s) const {
  if (s.rows() != a.rows() || s.nonZeros() != a.nonZeros()) s = a;
  if (!structurally_symmetric_ || a.nonZeros() != size()) return;
  const double* v = a.valuePtr();
  double* w = s.valuePtr();
  const Eigen::Index nnz = a.nonZeros();
#pragma omp parallel for schedule(static) if (nnz > 200000)
  for (Eigen::Index k = 0; k < nnz; ++k) w[k] = 0.5 * (v[k] + v[mirror_[static_cast<size_t>(k)]]);
}

}  // namespace fibrane::solve
