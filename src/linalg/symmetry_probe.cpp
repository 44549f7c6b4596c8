#include "linalg/symmetry_probe.hpp"

#include <algorithm>
#include <cmath>

#include "common/system_memory.hpp"

namespace fibrane::solve {

// The last pattern's map goes before the new one is built; false where `a` cannot have one.
bool SymmetryProbe::start(const Eigen::SparseMatrix<double>& a, const std::vector<int>* rows) {
  release_storage(mirror_);
  release_storage(entries_);
  rows_ = rows ? *rows : std::vector<int>{};
  whole_ = !rows;
  structurally_symmetric_ = false;
  nonzeros_ = 0;
  return a.rows() == a.cols() && a.isCompressed();
}

// One pass: walking the columns in order meets the entries (row, col) of a fixed row in increasing col,
// which is the order of their mirrors (col, row) in column `row`, so a cursor per column finds them
// without a binary search per entry (docs/performance.md, "Linear solver").
void SymmetryProbe::build(const Eigen::SparseMatrix<double>& a) {
  if (!start(a, nullptr)) return;
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
  nonzeros_ = a.nonZeros();
  structurally_symmetric_ = true;
}

// Each entry of the rows' columns whose row is one of them finds its mirror by a binary search in the
// mirror's column.
void SymmetryProbe::build(const Eigen::SparseMatrix<double>& a, const std::vector<int>& rows) {
  if (4 * static_cast<Eigen::Index>(rows.size()) > a.rows()) return build(a);
  if (!start(a, &rows)) return;
  const int* outer = a.outerIndexPtr();
  const int* inner = a.innerIndexPtr();
  const auto in_rows = [&](int i) { return std::binary_search(rows_.begin(), rows_.end(), i); };
  for (const int col : rows_) {
    if (col < 0 || col >= a.cols()) return;
    for (int k = outer[col]; k < outer[col + 1]; ++k) {
      const int row = inner[k];
      if (!in_rows(row)) continue;
      const int* found = std::lower_bound(inner + outer[row], inner + outer[row + 1], col);
      if (found == inner + outer[row + 1] || *found != col) return;
      entries_.push_back(k);
      mirror_.push_back(static_cast<int>(found - inner));
    }
  }
  nonzeros_ = a.nonZeros();
  structurally_symmetric_ = true;
}

// Assembled tangents of symmetric element matrices differ from their transpose by summation-order
// round-off only (~1e-16 relative, measured 1e-16 on the bending example), while a genuinely unsymmetric
// load stiffness differs at O(load) level.
bool SymmetryProbe::symmetric(const Eigen::SparseMatrix<double>& a) const {
  return structurally_symmetric_ && a.nonZeros() == size() && skew_support(a).empty();
}

std::vector<int> SymmetryProbe::skew_support(const Eigen::SparseMatrix<double>& a) const {
  if (!structurally_symmetric_ || a.nonZeros() != size()) return {};
  return whole_ ? whole_skew_support(a) : block_skew_support(a);
}

// One pass over the values, columns shared among the threads: each column's largest |a_ij - a_ji| and the
// largest |a_ij|, then the columns above the tolerance. A differing entry's mirror differs as much, so the
// columns that hold one are the rows that do, and no two threads write the same place.
std::vector<int> SymmetryProbe::whole_skew_support(const Eigen::SparseMatrix<double>& a) const {
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

// The same over the block's entries, with max|a| over the rows' columns.
std::vector<int> SymmetryProbe::block_skew_support(const Eigen::SparseMatrix<double>& a) const {
  const double* v = a.valuePtr();
  const int* outer = a.outerIndexPtr();
  const int* inner = a.innerIndexPtr();
  double largest = 0;
  for (const int col : rows_)
    for (int k = outer[col]; k < outer[col + 1]; ++k) largest = std::max(largest, std::abs(v[k]));
  const double tolerance = 1e-12 * largest;
  std::vector<int> rows;
  for (std::size_t t = 0; t < entries_.size(); ++t) {
    const int k = entries_[t];
    if (std::abs(v[k] - v[mirror_[t]]) > tolerance) rows.push_back(inner[k]);
  }
  std::sort(rows.begin(), rows.end());
  rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
  return rows;
}

}  // namespace fibrane::solve
