#include "solve/assembler.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include <omp.h>

namespace fibrane::solve {

void SparseAssembler::set_pattern(const ConstraintSet& c, const std::vector<std::vector<int>>& element_dofs) {
  if (!c.finalized()) throw std::logic_error("SparseAssembler::set_pattern: ConstraintSet not finalized");
  constraints_ = &c;
  const int n_free = c.num_free();
  const size_t n_elem = element_dofs.size();

  dof_begin_.assign(1, 0);
  dofs_.clear();
  entry_begin_.assign(1, 0);
  entry_slot_.clear();
  entry_coef_.clear();
  reduced_count_.assign(n_elem, 0);
  std::vector<int> reduced_begin(1, 0), reduced;  // sorted reduced unknowns of every element

  std::vector<std::vector<int>> column_rows(static_cast<size_t>(n_free));
  std::vector<int> local;
  for (size_t e = 0; e < n_elem; ++e) {
    local.clear();
    for (int d : element_dofs[e]) {
      if (d < 0 || d >= c.num_dofs())
        throw std::out_of_range("SparseAssembler: element " + std::to_string(e) + " has DOF " +
                                std::to_string(d) + " outside the DOF map");
      for (const auto& [i, coef] : c.expansion(d)) local.push_back(i);
    }
    std::sort(local.begin(), local.end());
    local.erase(std::unique(local.begin(), local.end()), local.end());
    for (int d : element_dofs[e]) {
      dofs_.push_back(d);
      for (const auto& [i, coef] : c.expansion(d)) {
        entry_slot_.push_back(static_cast<int>(std::lower_bound(local.begin(), local.end(), i) - local.begin()));
        entry_coef_.push_back(coef);
      }
      entry_begin_.push_back(static_cast<int>(entry_slot_.size()));
    }
    dof_begin_.push_back(static_cast<int>(dofs_.size()));
    reduced_count_[e] = static_cast<int>(local.size());
    reduced.insert(reduced.end(), local.begin(), local.end());
    reduced_begin.push_back(static_cast<int>(reduced.size()));
    for (int col : local) {
      auto& rows = column_rows[static_cast<size_t>(col)];
      rows.insert(rows.end(), local.begin(), local.end());
    }
  }

  // Compressed column-major pattern (sorted row indices per column), values zero.
  std::vector<Eigen::Triplet<double>> triplets;
  for (int col = 0; col < n_free; ++col) {
    auto& rows = column_rows[static_cast<size_t>(col)];
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
    for (int row : rows) triplets.emplace_back(row, col, 0.0);
    std::vector<int>().swap(rows);
  }
  matrix_.resize(n_free, n_free);
  matrix_.setFromTriplets(triplets.begin(), triplets.end());
  matrix_.makeCompressed();

  // Position of every (row slot, column slot) pair of every element in the value array.
  const int* outer = matrix_.outerIndexPtr();
  const int* inner = matrix_.innerIndexPtr();
  pos_begin_.assign(1, 0);
  pos_.clear();
  for (size_t e = 0; e < n_elem; ++e) {
    const int* r = reduced.data() + reduced_begin[e];
    const int m = reduced_count_[e];
    for (int s = 0; s < m; ++s) {
      const int* col_begin = inner + outer[r[s]];
      const int* col_end = inner + outer[r[s] + 1];
      const int* it = col_begin;
      for (int p = 0; p < m; ++p) {  // rows r[p] increase, so the search resumes where it stopped
        it = std::lower_bound(it, col_end, r[p]);
        pos_.push_back(static_cast<int>(it - inner));
      }
    }
    pos_begin_.push_back(pos_.size());
  }

  full_residual_ = Eigen::VectorXd::Zero(c.num_dofs());
  reduced_residual_ = Eigen::VectorXd::Zero(n_free);
  buffers_.clear();
  overflow_ = Buffer{};
  ++version_;
}

void SparseAssembler::begin(bool with_matrix) {
  if (!constraints_) throw std::logic_error("SparseAssembler::begin before set_pattern");
  with_matrix_ = with_matrix;
  if (with_matrix) std::fill_n(matrix_.valuePtr(), matrix_.nonZeros(), 0.0);
  full_residual_.setZero();
  const size_t nnz = static_cast<size_t>(matrix_.nonZeros());
  const size_t n = static_cast<size_t>(full_residual_.size());
  auto reset = [&](Buffer& b) {
    b.values.assign(with_matrix ? nnz : 0, 0.0);
    b.residual.assign(n, 0.0);
    b.used = false;
  };
  buffers_.resize(strategy_ == Strategy::ThreadBuffers ? static_cast<size_t>(omp_get_max_threads()) : 0);
  auto stale = [&](const Buffer& b) {
    return b.used || b.residual.size() != n || (with_matrix && b.values.size() != nnz);
  };
  for (size_t i = 1; i < buffers_.size(); ++i)
    if (stale(buffers_[i])) reset(buffers_[i]);
  if (stale(overflow_)) reset(overflow_);
}

SparseAssembler::Buffer* SparseAssembler::thread_buffer() {
  // Thread numbers identify a buffer only in the outermost parallel region (level <= 1).
  if (strategy_ != Strategy::ThreadBuffers || omp_get_level() > 1) return nullptr;
  const size_t tid = static_cast<size_t>(omp_get_thread_num());
  if (tid == 0 || tid >= buffers_.size()) return nullptr;
  return &buffers_[tid];
}

void SparseAssembler::scatter(int e, const Eigen::VectorXd& r_local, const Eigen::MatrixXd* k_local,
                              double* values, double* residual, bool atomic) const {
  const int first = dof_begin_[static_cast<size_t>(e)];
  const int n = dof_begin_[static_cast<size_t>(e) + 1] - first;
  if (r_local.size() != n || (k_local && (k_local->rows() != n || k_local->cols() != n)))
    throw std::invalid_argument("SparseAssembler::add: element " + std::to_string(e) +
                                " contribution has the wrong size");
  for (int a = 0; a < n; ++a) {
    double& target = residual[dofs_[static_cast<size_t>(first + a)]];
    if (atomic) {
#pragma omp atomic
      target += r_local[a];
    } else {
      target += r_local[a];
    }
  }
  if (!k_local || !with_matrix_) return;
  // K_red += T_e^T k T_e, walking k column by column (column-major storage).
  const int m = reduced_count_[static_cast<size_t>(e)];
  const int* pos = pos_.data() + pos_begin_[static_cast<size_t>(e)];
  const int* eb = entry_begin_.data() + first;
  for (int b = 0; b < n; ++b) {
    for (int jb = eb[b]; jb < eb[b + 1]; ++jb) {
      const int* column = pos + static_cast<size_t>(entry_slot_[static_cast<size_t>(jb)]) * m;
      const double cb = entry_coef_[static_cast<size_t>(jb)];
      for (int a = 0; a < n; ++a) {
        const double kab = (*k_local)(a, b) * cb;
        for (int ja = eb[a]; ja < eb[a + 1]; ++ja) {
          double& target = values[column[entry_slot_[static_cast<size_t>(ja)]]];
          const double v = entry_coef_[static_cast<size_t>(ja)] * kab;
          if (atomic) {
#pragma omp atomic
            target += v;
          } else {
            target += v;
          }
        }
      }
    }
  }
}

void SparseAssembler::add(int element, const Eigen::VectorXd& r_local, const Eigen::MatrixXd* k_local) {
  if (element < 0 || element >= num_elements())
    throw std::out_of_range("SparseAssembler::add: element " + std::to_string(element) + " out of range");
  if (strategy_ == Strategy::Atomic) {
    scatter(element, r_local, k_local, matrix_.valuePtr(), full_residual_.data(), true);
    return;
  }
  const bool outermost = omp_get_level() <= 1;
  if (outermost && omp_get_thread_num() == 0) {
    scatter(element, r_local, k_local, matrix_.valuePtr(), full_residual_.data(), false);
  } else if (Buffer* b = thread_buffer()) {
    b->used = true;
    scatter(element, r_local, k_local, b->values.data(), b->residual.data(), false);
  } else {
#pragma omp atomic write
    overflow_.used = true;
    scatter(element, r_local, k_local, overflow_.values.data(), overflow_.residual.data(), true);
  }
}

void SparseAssembler::add_vector(std::span<const int> dofs, const Eigen::VectorXd& r_local) {
  if (static_cast<Eigen::Index>(dofs.size()) != r_local.size())
    throw std::invalid_argument("SparseAssembler::add_vector: size mismatch");
  for (int d : dofs)
    if (d < 0 || d >= full_residual_.size())
      throw std::out_of_range("SparseAssembler::add_vector: DOF " + std::to_string(d) + " out of range");
  // Point loads are few: a shared atomic update keeps this independent of the buffer scheme.
  for (size_t a = 0; a < dofs.size(); ++a) {
    double& target = overflow_.residual[static_cast<size_t>(dofs[a])];
#pragma omp atomic
    target += r_local[static_cast<Eigen::Index>(a)];
  }
#pragma omp atomic write
  overflow_.used = true;
}

void SparseAssembler::end() {
  const Eigen::Index nnz = matrix_.nonZeros();
  double* values = matrix_.valuePtr();
  // Sum and clear in one pass, so the next begin() finds the buffers zeroed already.
  auto reduce = [&](Buffer& b) {
    if (!b.used) return;
    if (with_matrix_) {
      double* buffer = b.values.data();
      // A parallel region costs microseconds (milliseconds on an oversubscribed machine): only for big arrays.
#pragma omp parallel for schedule(static) if (nnz > 200000)
      for (Eigen::Index i = 0; i < nnz; ++i) {
        values[i] += buffer[i];
        buffer[i] = 0.0;
      }
    }
    for (size_t i = 0; i < b.residual.size(); ++i) {
      full_residual_[static_cast<Eigen::Index>(i)] += b.residual[i];
      b.residual[i] = 0.0;
    }
    b.used = false;
  };
  for (size_t i = 1; i < buffers_.size(); ++i) reduce(buffers_[i]);
  reduce(overflow_);
  reduced_residual_ = constraints_->restrict_vector(full_residual_);
}

}  // namespace fibrane::solve
