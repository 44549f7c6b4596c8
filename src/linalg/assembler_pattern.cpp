// The sparsity side of SparseAssembler: element tables (which reduced unknowns an element touches and
// where its entries sit in the matrix), merging the variable elements into the fixed pattern, and
// locating element entries. The numeric side (begin/add/end) is in assembler.cpp.
#include "linalg/assembler.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>

#include <omp.h>

#include "common/parallel_errors.hpp"
#include "linalg/release_storage.hpp"

namespace fibrane::solve {

SparseAssembler::ElementTable SparseAssembler::make_table(const ConstraintSet& c,
                                                         const std::vector<std::vector<int>>& element_dofs,
                                                         int first_id) {
  ElementTable t;
  std::vector<int> local;
  for (size_t e = 0; e < element_dofs.size(); ++e) {
    local.clear();
    for (int d : element_dofs[e]) {
      if (d < 0 || d >= c.num_dofs())
        throw std::out_of_range("SparseAssembler: element " + std::to_string(first_id + static_cast<int>(e)) +
                                " has DOF " + std::to_string(d) + " outside the DOF map");
      for (const auto& [i, coef] : c.expansion(d)) local.push_back(i);
    }
    std::sort(local.begin(), local.end());
    local.erase(std::unique(local.begin(), local.end()), local.end());
    for (int d : element_dofs[e]) {
      t.dofs.push_back(d);
      for (const auto& [i, coef] : c.expansion(d)) {
        t.entry_slot.push_back(static_cast<int>(std::lower_bound(local.begin(), local.end(), i) - local.begin()));
        t.entry_coef.push_back(coef);
      }
      t.entry_begin.push_back(static_cast<int>(t.entry_slot.size()));
    }
    t.dof_begin.push_back(static_cast<int>(t.dofs.size()));
    t.reduced.insert(t.reduced.end(), local.begin(), local.end());
    t.reduced_begin.push_back(static_cast<int>(t.reduced.size()));
  }
  return t;
}

SparseAssembler::Pattern SparseAssembler::merge(int n, const Pattern& base, const ElementTable& t,
                                                std::vector<int>& base_position) {
  // The elements of every column (each element's reduced unknowns are its rows and its columns).
  std::vector<int> column_begin(static_cast<size_t>(n) + 1, 0), column_elements(t.reduced.size());
  for (int col : t.reduced) ++column_begin[static_cast<size_t>(col) + 1];
  for (int col = 0; col < n; ++col) column_begin[col + 1] += column_begin[col];
  {
    std::vector<int> next(column_begin.begin(), column_begin.end() - 1);
    for (int e = 0; e < t.size(); ++e)
      for (int k = t.reduced_begin[e]; k < t.reduced_begin[e + 1]; ++k) column_elements[next[t.reduced[k]]++] = e;
  }
  // Rows each column gains over the base, sorted: one marker array per thread, so the work is the sum of
  // the elements' block sizes, not a sort of them.
  std::vector<std::vector<int>> added(static_cast<size_t>(n));
  FirstError error;  // std::bad_alloc: every thread still meets the loop's barrier
#pragma omp parallel
  {
    std::vector<int> mark;
    error.run([&] { mark.assign(static_cast<size_t>(n), -1); });
#pragma omp for schedule(dynamic, 256)
    for (int col = 0; col < n; ++col) error.run([&] {
      if (error.failed() || column_begin[col] == column_begin[col + 1]) return;
      for (int k = base.outer[col]; k < base.outer[col + 1]; ++k) mark[base.inner[k]] = col;
      auto& rows = added[col];
      for (int j = column_begin[col]; j < column_begin[col + 1]; ++j) {
        const int e = column_elements[j];
        for (int k = t.reduced_begin[e]; k < t.reduced_begin[e + 1]; ++k)
          if (const int row = t.reduced[k]; mark[row] != col) {
            mark[row] = col;
            rows.push_back(row);
          }
      }
      std::sort(rows.begin(), rows.end());
    });
  }
  error.rethrow();
  Pattern p;
  p.outer.assign(static_cast<size_t>(n) + 1, 0);
  for (int col = 0; col < n; ++col)
    p.outer[col + 1] = p.outer[col] + (base.outer[col + 1] - base.outer[col]) + static_cast<int>(added[col].size());
  p.inner.resize(static_cast<size_t>(p.outer[n]));
  base_position.resize(base.inner.size());
#pragma omp parallel for schedule(dynamic, 1024)
  for (int col = 0; col < n; ++col) {
    int out = p.outer[col], k = base.outer[col];
    const int k_end = base.outer[col + 1];
    auto a = added[col].begin();
    while (k < k_end || a != added[col].end()) {
      if (a == added[col].end() || (k < k_end && base.inner[k] < *a)) {
        base_position[k] = out;
        p.inner[out++] = base.inner[k++];
      } else {
        p.inner[out++] = *a++;
      }
    }
    std::vector<int>().swap(added[col]);
  }
  return p;
}

void SparseAssembler::locate(ElementTable& t, const Pattern& p) {
  t.offset_begin.assign(1, 0);
  for (int e = 0; e < t.size(); ++e) {
    const size_t m = static_cast<size_t>(t.reduced_count(e));
    t.offset_begin.push_back(t.offset_begin.back() + m * m);
  }
  t.offset.resize(t.offset_begin.back());
#pragma omp parallel for schedule(dynamic, 64)
  for (int e = 0; e < t.size(); ++e) {
    const int* r = t.reduced.data() + t.reduced_begin[e];
    const int m = t.reduced_count(e);
    int* offset = t.offset.data() + t.offset_begin[e];
    for (int s = 0; s < m; ++s) {
      const int* col_begin = p.inner.data() + p.outer[r[s]];
      const int* col_end = p.inner.data() + p.outer[r[s] + 1];
      const int* it = col_begin;
      for (int q = 0; q < m; ++q) {  // rows r[q] increase, so the search resumes where it stopped
        it = std::lower_bound(it, col_end, r[q]);
        *offset++ = static_cast<int>(it - col_begin);
      }
    }
  }
}

// The matrix and the thread buffers keep their storage across patterns (with 10 % slack when they grow):
// fresh storage for every new pattern costs allocations and page faults (docs/performance.md, "Sparse
// assembler").
void SparseAssembler::set_matrix(const Pattern& p) {
  const int n = static_cast<int>(p.outer.size()) - 1;
  // A larger pattern needs new storage: the old is freed first (its values are not kept), its pages handed
  // back, so that the two never coexist in memory. A smaller one reuses the storage.
  if (matrix_.data().allocatedSize() < static_cast<Eigen::Index>(p.inner.size())) release_storage(matrix_);
  matrix_.resize(n, n);  // empty, compressed; the value and index storage keeps its capacity
  matrix_.data().resize(static_cast<Eigen::Index>(p.inner.size()), 0.1);
  std::copy(p.outer.begin(), p.outer.end(), matrix_.outerIndexPtr());
  std::copy(p.inner.begin(), p.inner.end(), matrix_.innerIndexPtr());
  std::fill_n(matrix_.valuePtr(), p.inner.size(), 0.0);
}

void SparseAssembler::reset_vectors() {
  full_residual_ = Eigen::VectorXd::Zero(constraints_->num_dofs());
  reduced_residual_ = Eigen::VectorXd::Zero(constraints_->num_free());
  ++version_;  // begin() resizes the buffers (they are zero: end() clears them)
}

void SparseAssembler::set_pattern(const ConstraintSet& c, const std::vector<std::vector<int>>& element_dofs) {
  if (!c.finalized()) throw std::logic_error("SparseAssembler::set_pattern: ConstraintSet not finalized");
  constraints_ = &c;
  const int n = c.num_free();
  fixed_ = make_table(c, element_dofs, 0);
  variable_ = ElementTable{};
  Pattern empty;
  empty.outer.assign(static_cast<size_t>(n) + 1, 0);
  std::vector<int> unused;
  fixed_pattern_ = merge(n, empty, fixed_, unused);
  locate(fixed_, fixed_pattern_);
  set_matrix(fixed_pattern_);
  fixed_in_matrix_.resize(fixed_pattern_.inner.size());
  std::iota(fixed_in_matrix_.begin(), fixed_in_matrix_.end(), 0);
  colour_order_.clear();
  colour_begin_.assign(1, 0);
  append_colours(fixed_, 0);
  fixed_colours_ = num_colours();
  reset_vectors();
}

void SparseAssembler::set_variable_elements(const std::vector<std::vector<int>>& element_dofs) {
  if (!constraints_) throw std::logic_error("SparseAssembler::set_variable_elements before set_pattern");
  const int n = constraints_->num_free();
  variable_ = make_table(*constraints_, element_dofs, fixed_.size());
  std::vector<int> fixed_position;
  const Pattern p = merge(n, fixed_pattern_, variable_, fixed_position);
  // A fixed entry keeps its offset within its column unless variable rows before it came or went: find
  // those columns and map their old offsets to the new ones, then update the fixed elements there.
  const int* old_outer = matrix_.outerIndexPtr();
  std::vector<int> remap_begin(static_cast<size_t>(n), -1), remap;
  for (int col = 0; col < n; ++col) {
    bool moved = false;
    for (int k = fixed_pattern_.outer[col]; k < fixed_pattern_.outer[col + 1] && !moved; ++k)
      moved = fixed_in_matrix_[k] - old_outer[col] != fixed_position[k] - p.outer[col];
    if (!moved) continue;
    remap_begin[col] = static_cast<int>(remap.size());
    remap.resize(remap.size() + static_cast<size_t>(old_outer[col + 1] - old_outer[col]), -1);
    for (int k = fixed_pattern_.outer[col]; k < fixed_pattern_.outer[col + 1]; ++k)
      remap[remap_begin[col] + fixed_in_matrix_[k] - old_outer[col]] = fixed_position[k] - p.outer[col];
  }
  if (!remap.empty()) {
#pragma omp parallel for schedule(dynamic, 256)
    for (int e = 0; e < fixed_.size(); ++e) {
      const int* r = fixed_.reduced.data() + fixed_.reduced_begin[e];
      const int m = fixed_.reduced_count(e);
      for (int s = 0; s < m; ++s) {
        if (remap_begin[r[s]] < 0) continue;
        const int* map = remap.data() + remap_begin[r[s]];
        int* column = fixed_.offset.data() + fixed_.offset_begin[e] + static_cast<size_t>(s) * m;
        for (int q = 0; q < m; ++q) column[q] = map[column[q]];
      }
    }
  }
  fixed_in_matrix_ = std::move(fixed_position);
  locate(variable_, p);
  set_matrix(p);
  colour_begin_.resize(static_cast<size_t>(fixed_colours_) + 1);
  colour_order_.resize(static_cast<size_t>(colour_begin_.back()));
  append_colours(variable_, fixed_.size());
  reset_vectors();
}

}  // namespace fibrane::solve
