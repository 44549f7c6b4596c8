// The permuted lower triangle for cholmod_super_numeric: its pattern and source map built once per pattern
// with CHOLMOD's own transposes, its values gathered at each factorisation.
#include "linalg/cholmod_permuted_lower.hpp"

#include <numeric>

#include "common/system_memory.hpp"

namespace fibrane::solve {
cholmod_sparse cholmod_lower_view(int n, const int* column_starts, const int* rows, double* values) {
  cholmod_sparse v{};
  v.nrow = v.ncol = static_cast<size_t>(n);
  v.nzmax = static_cast<size_t>(column_starts[n]);
  v.p = const_cast<int*>(column_starts);
  v.i = const_cast<int*>(rows);
  v.x = values;
  v.stype = -1;  // only the lower triangle is read, as Eigen's CholmodSupernodalLLT<..., Lower> has it
  v.itype = CHOLMOD_INT;
  v.xtype = values ? CHOLMOD_REAL : CHOLMOD_PATTERN;
  v.dtype = CHOLMOD_DOUBLE;
  v.sorted = 1;
  v.packed = 1;
  return v;
}

bool CholmodPermutedLower::build(const cholmod_sparse& lower, const cholmod_factor& factor, cholmod_common& common) {
  clear();
  // The values are the entries' own indices (exact in double below 2^53), so that the transposes carry
  // each entry's source along. These are cholmod_factorize's two steps for a lower triangle:
  // upper = triu(P A P^T), then its transpose.
  std::vector<double> index(lower.nzmax);
  std::iota(index.begin(), index.end(), 0.0);
  cholmod_sparse a = cholmod_lower_view(static_cast<int>(lower.ncol), static_cast<const int*>(lower.p),
                                        static_cast<const int*>(lower.i), index.data());
  cholmod_sparse* upper = cholmod_ptranspose(&a, 2, static_cast<int*>(factor.Perm), nullptr, 0, &common);
  release_storage(index);
  if (!upper) return false;
  cholmod_sparse* permuted = cholmod_ptranspose(upper, 2, nullptr, nullptr, 0, &common);
  cholmod_free_sparse(&upper, &common);
  if (!permuted) return false;

  const auto n = static_cast<std::size_t>(permuted->ncol);
  const auto* p = static_cast<const int*>(permuted->p);
  const auto* i = static_cast<const int*>(permuted->i);
  const auto* x = static_cast<const double*>(permuted->x);
  const auto nnz = static_cast<std::size_t>(p[n]);
  column_starts_.assign(p, p + n + 1);
  rows_.assign(i, i + nnz);
  source_.resize(nnz);
  for (std::size_t k = 0; k < nnz; ++k) source_[k] = static_cast<int>(x[k]);
  view_ = *permuted;  // shape, stype (-1), sorted and packed as cholmod_factorize's matrix
  cholmod_free_sparse(&permuted, &common);
  view_.p = column_starts_.data();
  view_.i = rows_.data();
  view_.x = nullptr;
  view_.nz = nullptr;
  return true;
}

void CholmodPermutedLower::map_through(const std::vector<int>& outer) {
  for (int& s : source_) s = outer[static_cast<std::size_t>(s)];
}

cholmod_sparse* CholmodPermutedLower::fill(const double* from) {
  const long nnz = entries();
  values_.resize(static_cast<std::size_t>(nnz));
  double* to = values_.data();
  const int* source = source_.data();
#pragma omp parallel for schedule(static)
  for (long k = 0; k < nnz; ++k) to[k] = from[source[k]];
  view_.x = to;
  return &view_;
}

void CholmodPermutedLower::drop_values() {
  std::vector<double>().swap(values_);
  view_.x = nullptr;
}

void CholmodPermutedLower::release_values() {
  release_storage(values_);
  view_.x = nullptr;
}

void CholmodPermutedLower::clear() {
  release_values();
  release_storage(column_starts_);
  release_storage(rows_);
  release_storage(source_);
  view_ = cholmod_sparse{};
}

}  // namespace fibrane::solve
