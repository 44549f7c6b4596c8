#pragma once
// Freeing a large sparse matrix so that its memory leaves the resident set at once where memory is short,
// for the places where a new sparsity pattern replaces an old one (common/system_memory.hpp, release_pages).
#include <Eigen/SparseCore>

#include "common/system_memory.hpp"

// In namespace fibrane beside the std::vector overload, so that both are found wherever either is.
namespace fibrane {

// Empties m and frees its storage, the pages of its values and row indices handed back first where memory
// is short.
inline void release_storage(Eigen::SparseMatrix<double>& m) {
  release_pages(m.data().valuePtr(), sizeof(double) * static_cast<std::size_t>(m.data().allocatedSize()));
  release_pages(m.data().indexPtr(), sizeof(int) * static_cast<std::size_t>(m.data().allocatedSize()));
  m = Eigen::SparseMatrix<double>();
}

}  // namespace fibrane
