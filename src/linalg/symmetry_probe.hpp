#pragma once
// Whether an assembled sparse matrix is symmetric to round-off: the values are compared with their mirror
// entries through a map built once per sparsity pattern. Used where a model cannot promise a symmetric
// tangent but the case at hand may have one (point moments about a fixed axis): the symmetric
// factorisations are used while the values are symmetric.
#include <vector>

#include <Eigen/SparseCore>

namespace fibrane::solve {

class SymmetryProbe {
 public:
  // Builds the mirror map of a's pattern; afterwards structurally_symmetric() says whether it has one.
  // The matrix must be square and compressed (otherwise it counts as structurally unsymmetric).
  void build(const Eigen::SparseMatrix<double>& a);
  // The map of the entries a_ij with i and j both in `rows` (sorted, unique) only, for a matrix that is
  // symmetric in pattern and values outside them (a model's promise: the contributions that may be
  // unsymmetric act on these rows alone, NonlinearSystem::skew_candidates). Only that block's pattern is
  // checked. Where `rows` holds more than a quarter of the rows, the whole map is built instead.
  void build(const Eigen::SparseMatrix<double>& a, const std::vector<int>& rows);
  bool structurally_symmetric() const { return structurally_symmetric_; }
  // The number of entries of the pattern the map was built for (0 without a map).
  Eigen::Index size() const { return nonzeros_; }
  // Whether every |a_ij - a_ji| <= 1e-12 max|a| (false without a map); with a map of some rows only, max|a|
  // is taken over their columns. `a` must have the pattern of the last build(). One pass over the values
  // the map covers (skew_support() is empty).
  bool symmetric(const Eigen::SparseMatrix<double>& a) const;
  // The rows (sorted) where a differs from its transpose by more than that tolerance: the skew part
  // (a - a^T) / 2 lives in these rows and the same columns. Empty without a map, for another pattern, or
  // for a matrix that is symmetric(): a caller that needs both asks only this, in one pass.
  std::vector<int> skew_support(const Eigen::SparseMatrix<double>& a) const;

 private:
  bool start(const Eigen::SparseMatrix<double>& a, const std::vector<int>* rows);
  std::vector<int> whole_skew_support(const Eigen::SparseMatrix<double>& a) const;
  std::vector<int> block_skew_support(const Eigen::SparseMatrix<double>& a) const;

  // The whole map: mirror_[k] = value index of the entry transposed to entry k. The map of some rows:
  // mirror_[t] = that of entry entries_[t], and rows_ the rows.
  std::vector<int> mirror_, entries_, rows_;
  Eigen::Index nonzeros_ = 0;
  bool whole_ = false;
  bool structurally_symmetric_ = false;
};

}  // namespace fibrane::solve
