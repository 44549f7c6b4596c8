#pragma once
// The matrix that CHOLMOD's supernodal numeric factorisation reads, kept from one factorisation to the next.
#include <cholmod.h>

#include <Eigen/SparseCore>
#include <vector>

namespace fibrane::solve {

/// A CHOLMOD view (no copy) of an n x n matrix in compressed columns whose lower triangle CHOLMOD is to read
/// (stype -1), with `values` as its values (of its length), or its pattern alone where `values` is null.
cholmod_sparse cholmod_lower_view(int n, const int* column_starts, const int* rows, double* values);
/// The same for a compressed Eigen matrix.
inline cholmod_sparse cholmod_lower_view(const Eigen::SparseMatrix<double>& lower, double* values) {
  return cholmod_lower_view(static_cast<int>(lower.rows()), lower.outerIndexPtr(), lower.innerIndexPtr(), values);
}

/// The lower triangle of P A P^T in compressed columns, where A is a symmetric matrix given by its lower
/// triangle and P the fill-reducing permutation of a CHOLMOD factor (cholmod_factor::Perm).
///
/// cholmod_super_numeric factorises exactly this matrix. cholmod_factorize builds it anew for every
/// factorisation, by two permuted transposes of the lower triangle, each a scatter of all of A's entries. As
/// A's pattern stays between analyses, this class builds the pattern once, with the source of each entry in
/// A's value array, and each factorisation only gathers the values (`fill`). The entries and their order are
/// the ones cholmod_factorize builds (the same CHOLMOD routines make the pattern), so the factor is the same
/// to the last bit.
class CholmodPermutedLower {
 public:
  /// Builds the pattern and the source map for the lower triangle `lower` (its pattern) and the permutation
  /// of `factor`; returns false where CHOLMOD runs out of memory (status in `common`).
  bool build(const Eigen::SparseMatrix<double>& lower, const cholmod_factor& factor, cholmod_common& common) {
    return build(cholmod_lower_view(lower, nullptr), factor, common);
  }
  /// The same for a pattern given as a CHOLMOD view (cholmod_lower_view without values).
  bool build(const cholmod_sparse& lower, const cholmod_factor& factor, cholmod_common& common);
  /// Whether build() has run since the last clear().
  bool built() const { return !source_.empty(); }
  /// The permuted lower triangle with the values of `lower`, which must have the pattern given to build().
  /// The view stays valid until the next fill(), drop_values(), release_values() or clear().
  cholmod_sparse* fill(const Eigen::SparseMatrix<double>& lower) { return fill(lower.valuePtr()); }
  /// The same from a value array that map_through() has made the sources point into.
  cholmod_sparse* fill(const double* values);
  /// Makes the sources indices into another array: source[k] becomes outer[source[k]] (for a matrix whose
  /// entries are a subset of a larger one's, `outer` their indices there).
  void map_through(const std::vector<int>& outer);
  /// Frees the values (the pattern and the map stay for the next fill()), leaving their memory to the
  /// allocator for what runs between factorisations (the assembly) and for the next fill().
  void drop_values();
  /// Frees the values and hands their pages back to the system (the pattern and the map stay).
  void release_values();
  /// Frees everything.
  void clear();
  /// Entries of the pattern.
  long entries() const { return static_cast<long>(source_.size()); }

 private:
  std::vector<int> column_starts_, rows_;
  std::vector<int> source_;  // source_[k]: the index in the lower triangle's values of entry k
  std::vector<double> values_;
  cholmod_sparse view_{};
};

}  // namespace fibrane::solve
