#include "linalg/assembler.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>

#include <omp.h>

namespace fibrane::solve {

void SparseAssembler::begin(bool with_matrix, const Eigen::VectorXd* prescribed_rate) {
  if (!constraints_) throw std::logic_error("SparseAssembler::begin before set_pattern");
  if (prescribed_rate && !with_matrix)
    throw std::logic_error("SparseAssembler::begin: the load derivative needs the element matrices");
  if (prescribed_rate && prescribed_rate->size() != constraints_->num_dofs())
    throw std::invalid_argument("SparseAssembler::begin: prescribed rate of the wrong size");
  with_matrix_ = with_matrix;
  prescribed_rate_ = prescribed_rate;
  if (with_matrix) {
    double* values = matrix_.valuePtr();
    const Eigen::Index nnz = matrix_.nonZeros();
    // Zeroing is memory-bound (~430 MB at the bending example's paper mesh): both threads' bandwidth.
#pragma omp parallel for schedule(static) if (nnz > 200000)
    for (Eigen::Index i = 0; i < nnz; ++i) values[i] = 0.0;
  }
  full_residual_.setZero();
  const size_t nnz = static_cast<size_t>(matrix_.nonZeros());
  const size_t n = static_cast<size_t>(full_residual_.size());
  if (prescribed_rate) full_rate_.setZero(static_cast<Eigen::Index>(n));
  buffers_.resize(strategy_ == Strategy::Atomic ? 0 : static_cast<size_t>(omp_get_max_threads()));
  // A thread's buffer is allocated at its first add (thread_buffer): threads that add nothing, or only
  // inside coloured loops, cost no memory. Buffers from earlier passes are resized or cleaned here.
  for (size_t i = 1; i < buffers_.size(); ++i) {
    Buffer& b = buffers_[i];
    if (b.residual.empty()) continue;
    if (b.used || b.residual.size() != n || (with_matrix && b.values.size() != nnz) ||
        (prescribed_rate && b.rate.size() != n))
      reset(b);
  }
  // The overflow buffer's matrix values (a copy of the whole value array) are allocated by its first
  // caller with an element matrix (overflow_values), which is rare: most runs never need them.
  if (overflow_.used || overflow_.residual.size() != n || (prescribed_rate && overflow_.rate.size() != n)) {
    overflow_.residual.assign(n, 0.0);
    overflow_.rate.assign(prescribed_rate ? n : 0, 0.0);
    if (overflow_.values.size() == nnz) std::fill(overflow_.values.begin(), overflow_.values.end(), 0.0);
    overflow_.used = false;
  }
  if (overflow_.values.size() != nnz) std::vector<double>().swap(overflow_.values);
}

double* SparseAssembler::overflow_values() {
  const size_t nnz = static_cast<size_t>(matrix_.nonZeros());
#pragma omp critical(fibrane_assembler_overflow)
  if (overflow_.values.size() != nnz) overflow_.values.assign(nnz, 0.0);
  return overflow_.values.data();
}

void SparseAssembler::reset(Buffer& b) const {
  const size_t nnz = static_cast<size_t>(matrix_.nonZeros());
  const size_t n = static_cast<size_t>(full_residual_.size());
  if (with_matrix_ && b.values.capacity() < nnz) b.values.reserve(nnz + nnz / 10);
  b.values.assign(with_matrix_ ? nnz : 0, 0.0);
  b.residual.assign(n, 0.0);
  b.rate.assign(prescribed_rate_ ? n : 0, 0.0);
  b.used = false;
}

SparseAssembler::Buffer* SparseAssembler::thread_buffer() {
  // Thread numbers identify a buffer only in the outermost parallel region (level <= 1).
  if (strategy_ == Strategy::Atomic || omp_get_level() > 1) return nullptr;
  const size_t tid = static_cast<size_t>(omp_get_thread_num());
  if (tid == 0 || tid >= buffers_.size()) return nullptr;
  Buffer& b = buffers_[tid];
  const size_t n = static_cast<size_t>(full_residual_.size());
  if (b.residual.size() != n || (with_matrix_ && b.values.size() != static_cast<size_t>(matrix_.nonZeros())) ||
      (prescribed_rate_ && b.rate.size() != n))
    reset(b);  // first use since the pattern (or the kind of pass) changed: end() keeps it zeroed after
  return &b;
}

template <class Local>
void SparseAssembler::scatter_rate(const ElementTable& t, int e, int n, Local local, const Eigen::MatrixXd& k_local,
                                   double* rate, bool atomic) const {
  const int* dofs = t.dofs.data() + t.dof_begin[static_cast<size_t>(e)];
  const Eigen::VectorXd& g_t = *prescribed_rate_;
  for (int b = 0; b < n; ++b) {
    const double gb = g_t[dofs[local(b)]];
    if (gb == 0.0) continue;  // most elements have no prescribed DOF
    for (int a = 0; a < n; ++a) {
      double& target = rate[dofs[local(a)]];
      const double v = k_local(a, b) * gb;
      if (atomic) {
#pragma omp atomic
        target += v;
      } else {
        target += v;
      }
    }
  }
}

template <class Local>
void SparseAssembler::scatter(const ElementTable& t, int e, int n, Local local, const Eigen::VectorXd& r_local,
                              const Eigen::MatrixXd* k_local, double* values, double* residual, double* rate,
                              bool atomic) const {
  const int first = t.dof_begin[static_cast<size_t>(e)];
  for (int a = 0; a < n; ++a) {
    double& target = residual[t.dofs[static_cast<size_t>(first + local(a))]];
    if (atomic) {
#pragma omp atomic
      target += r_local[a];
    } else {
      target += r_local[a];
    }
  }
  if (!k_local || !with_matrix_) return;
  if (prescribed_rate_) scatter_rate(t, e, n, local, *k_local, rate, atomic);
  // K_red += T_e^T k T_e, walking k column by column (column-major storage).
  const int m = t.reduced_count(e);
  const int* offset = t.offset.data() + t.offset_begin[static_cast<size_t>(e)];
  const int* reduced = t.reduced.data() + t.reduced_begin[static_cast<size_t>(e)];
  const int* outer = matrix_.outerIndexPtr();
  const int* eb = t.entry_begin.data() + first;
  const int* slot = t.entry_slot.data();
  const double* coef = t.entry_coef.data();
  for (int b = 0; b < n; ++b) {
    const int lb = local(b);
    for (int jb = eb[lb]; jb < eb[lb + 1]; ++jb) {
      const int* column = offset + static_cast<size_t>(slot[jb]) * m;
      double* column_values = values + outer[reduced[slot[jb]]];
      const double cb = coef[jb];
      for (int a = 0; a < n; ++a) {
        const int la = local(a);
        const double kab = (*k_local)(a, b) * cb;
        for (int ja = eb[la]; ja < eb[la + 1]; ++ja) {
          double& target = column_values[column[slot[ja]]];
          const double v = coef[ja] * kab;
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

std::pair<const SparseAssembler::ElementTable&, int> SparseAssembler::table_of(int element, const char* caller) const {
  if (element < 0 || element >= num_elements())
    throw std::out_of_range(std::string("SparseAssembler::") + caller + ": element " + std::to_string(element) +
                            " out of range");
  if (element < fixed_.size()) return {fixed_, element};
  return {variable_, element - fixed_.size()};
}

template <class Local>
void SparseAssembler::add_block(int element, int n, Local local, const Eigen::VectorXd& r_local,
                                const Eigen::MatrixXd* k_local) {
  const auto [t, e] = table_of(element, "add");
  const int size = t.dof_begin[static_cast<size_t>(e) + 1] - t.dof_begin[static_cast<size_t>(e)];
  if (r_local.size() != n || (k_local && (k_local->rows() != n || k_local->cols() != n)))
    throw std::invalid_argument("SparseAssembler::add: element " + std::to_string(element) +
                                " contribution has the wrong size");
  for (int a = 0; a < n; ++a)
    if (local(a) < 0 || local(a) >= size)
      throw std::out_of_range("SparseAssembler::add: local DOF outside element " + std::to_string(element));
  if (strategy_ == Strategy::Atomic) {
    scatter(t, e, n, local, r_local, k_local, matrix_.valuePtr(), full_residual_.data(), full_rate_.data(), true);
    return;
  }
  if (strategy_ == Strategy::Colours && exclusive(element)) {
    scatter(t, e, n, local, r_local, k_local, matrix_.valuePtr(), full_residual_.data(), full_rate_.data(), false);
    return;
  }
  const bool outermost = omp_get_level() <= 1;
  if (outermost && omp_get_thread_num() == 0) {
    scatter(t, e, n, local, r_local, k_local, matrix_.valuePtr(), full_residual_.data(), full_rate_.data(), false);
  } else if (Buffer* b = thread_buffer()) {
    b->used = true;
    scatter(t, e, n, local, r_local, k_local, b->values.data(), b->residual.data(), b->rate.data(), false);
  } else {
#pragma omp atomic write
    overflow_.used = true;
    scatter(t, e, n, local, r_local, k_local, k_local && with_matrix_ ? overflow_values() : nullptr,
            overflow_.residual.data(), overflow_.rate.data(), true);
  }
}

void SparseAssembler::add(int element, const Eigen::VectorXd& r_local, const Eigen::MatrixXd* k_local) {
  if (element >= 0 && element < num_elements()) {
    const auto [t, index] = table_of(element, "add");
    const auto e = static_cast<size_t>(index);
    if (r_local.size() != t.dof_begin[e + 1] - t.dof_begin[e])
      throw std::invalid_argument("SparseAssembler::add: element " + std::to_string(element) +
                                  " contribution has the wrong size");
  }
  add_block(element, static_cast<int>(r_local.size()), [](int a) { return a; }, r_local, k_local);
}

void SparseAssembler::add(int element, std::span<const int> local, const Eigen::VectorXd& r_local,
                          const Eigen::MatrixXd* k_local) {
  if (static_cast<Eigen::Index>(local.size()) != r_local.size())
    throw std::invalid_argument("SparseAssembler::add: " + std::to_string(local.size()) + " local DOFs for " +
                                std::to_string(r_local.size()) + " values");
  add_block(element, static_cast<int>(local.size()), [local](int a) { return local[static_cast<size_t>(a)]; },
            r_local, k_local);
}

Eigen::SparseVector<double> SparseAssembler::reduce(int element, std::span<const int> local,
                                                    const Eigen::VectorXd& v) const {
  const auto [t, index] = table_of(element, "reduce");
  if (static_cast<Eigen::Index>(local.size()) != v.size())
    throw std::invalid_argument("SparseAssembler::reduce: size mismatch");
  const auto e = static_cast<size_t>(index);
  const int first = t.dof_begin[e], size = t.dof_begin[e + 1] - first;
  const int* reduced = t.reduced.data() + t.reduced_begin[e];
  std::vector<Eigen::Triplet<double>> entries;
  for (std::size_t a = 0; a < local.size(); ++a) {
    if (local[a] < 0 || local[a] >= size)
      throw std::out_of_range("SparseAssembler::reduce: local DOF outside element " + std::to_string(element));
    const int j = first + local[a];
    for (int k = t.entry_begin[static_cast<size_t>(j)]; k < t.entry_begin[static_cast<size_t>(j) + 1]; ++k)
      entries.emplace_back(reduced[t.entry_slot[static_cast<size_t>(k)]], 0,
                           t.entry_coef[static_cast<size_t>(k)] * v[static_cast<Eigen::Index>(a)]);
  }
  Eigen::SparseMatrix<double> column(matrix_.rows(), 1);
  column.setFromTriplets(entries.begin(), entries.end());  // duplicates summed
  return column.col(0);
}

std::span<const int> SparseAssembler::reduced_unknowns(int element) const {
  const auto [t, e] = table_of(element, "reduced_unknowns");
  return {t.reduced.data() + t.reduced_begin[static_cast<size_t>(e)], static_cast<size_t>(t.reduced_count(e))};
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

void SparseAssembler::add_rate(std::span<const int> dofs, const Eigen::VectorXd& r_t) {
  if (!prescribed_rate_) return;
  if (static_cast<Eigen::Index>(dofs.size()) != r_t.size())
    throw std::invalid_argument("SparseAssembler::add_rate: size mismatch");
  for (size_t a = 0; a < dofs.size(); ++a) {
    if (dofs[a] < 0 || dofs[a] >= full_residual_.size())
      throw std::out_of_range("SparseAssembler::add_rate: DOF " + std::to_string(dofs[a]) + " out of range");
    double& target = overflow_.rate[static_cast<size_t>(dofs[a])];
#pragma omp atomic
    target += r_t[static_cast<Eigen::Index>(a)];
  }
#pragma omp atomic write
  overflow_.used = true;
}

void SparseAssembler::end(const Distribution* distribution) {
  const Eigen::Index nnz = matrix_.nonZeros();
  double* values = matrix_.valuePtr();
  // Sum and clear in one pass, so the next begin() finds the buffers zeroed already.
  auto reduce = [&](Buffer& b) {
    if (!b.used) return;
    if (with_matrix_ && b.values.size() == static_cast<size_t>(nnz)) {
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
    if (prescribed_rate_)
      for (size_t i = 0; i < b.rate.size(); ++i) {
        full_rate_[static_cast<Eigen::Index>(i)] += b.rate[i];
        b.rate[i] = 0.0;
      }
    b.used = false;
  };
  for (size_t i = 1; i < buffers_.size(); ++i) reduce(buffers_[i]);
  reduce(overflow_);
  if (distribution) {
    distribution->sum({full_residual_.data(), static_cast<size_t>(full_residual_.size())});
    if (prescribed_rate_) distribution->sum({full_rate_.data(), static_cast<size_t>(full_rate_.size())});
  }
  reduced_residual_ = constraints_->restrict_vector(full_residual_);
  if (prescribed_rate_) reduced_rate_ = constraints_->restrict_vector(full_rate_);
  else reduced_rate_.resize(0);
}

}  // namespace fibrane::solve
