// ElementSink: where a contribution's element vectors and matrices go (contribution.hpp).
#include "model/contribution.hpp"

#include <stdexcept>
#include <string>

#include <omp.h>

#include "linalg/assembler.hpp"
#include "linalg/distribution.hpp"
#include "linalg/rank_one_terms.hpp"

namespace fibrane::model {

namespace {

[[noreturn]] void not_owned(const char* what) {
  throw std::logic_error(std::string("ElementSink: ") + what +
                         " on a process that does not own it (a contribution must skip !sink.owns(e))");
}

}  // namespace

bool ElementSink::owns_global() const { return !distribution_ || distribution_->rank() == 0; }

bool ElementSink::distributed() const { return distribution_ && distribution_->size() > 1; }

void ElementSink::sum(std::span<double> values) const {
  if (distribution_) distribution_->sum(values);
}

void ElementSink::for_each_element(int n, int chunk, const std::function<void(int)>& body) {
  // One thread has nothing to keep apart: element order (the matrix's locality, and the sums of the
  // buffered assembly).
  if (assembler_.strategy() != solve::SparseAssembler::Strategy::Colours || omp_get_level() > 1 ||
      omp_get_num_threads() == 1) {
#pragma omp for schedule(static, chunk)
    for (int e = 0; e < n; ++e) body(e);
    return;
  }
  for (int c = 0; c < assembler_.num_colours(); ++c) {
    const std::span<const int> elements = assembler_.coloured(c, first_, n);
    const int m = static_cast<int>(elements.size());
    if (m == 0) continue;  // the same on every thread: no barrier
#pragma omp for schedule(static, chunk)
    for (int i = 0; i < m; ++i) {
      const int element = elements[static_cast<std::size_t>(i)];
      const solve::SparseAssembler::Exclusive visit(assembler_, element);
      body(element - first_);
    }
  }
}

void ElementSink::add(int element, const Eigen::VectorXd& r, const Eigen::MatrixXd* k) {
  if (!owns(element)) not_owned("element added");
  assembler_.add(first_ + element, r, k);
  if (external_) {
    const auto& dofs = (*element_dofs_)[static_cast<std::size_t>(element)];
    for (std::size_t a = 0; a < dofs.size(); ++a) (*external_)[dofs[a]] -= r[static_cast<Eigen::Index>(a)];
  }
}

void ElementSink::add(int element, std::span<const int> local, const Eigen::VectorXd& r, const Eigen::MatrixXd* k) {
  if (!owns(element)) not_owned("element added");
  assembler_.add(first_ + element, local, r, k);
  if (external_) {
    const auto& dofs = (*element_dofs_)[static_cast<std::size_t>(element)];
    for (std::size_t a = 0; a < local.size(); ++a) (*external_)[dofs[local[a]]] -= r[static_cast<Eigen::Index>(a)];
  }
}

void ElementSink::add_rank_one(int element, std::span<const int> local, double c, const Eigen::VectorXd& v) {
  if (!owns(element)) not_owned("rank-one term added");
  if (!rank_one_apart_) throw std::logic_error("ElementSink::add_rank_one: the sink holds no rank-one terms apart");
  rank_one_apart_->add(c, assembler_.reduce(first_ + element, local, v));
  const std::span<const int> rows = assembler_.reduced_unknowns(first_ + element);
  rank_one_apart_->fill_rows.insert(rank_one_apart_->fill_rows.end(), rows.begin(), rows.end());
}

void ElementSink::add_vector(std::span<const int> dofs, const Eigen::VectorXd& r) {
  if (!owns_global()) not_owned("vector added");
  assembler_.add_vector(dofs, r);
  if (external_)
    for (std::size_t a = 0; a < dofs.size(); ++a) (*external_)[dofs[a]] -= r[static_cast<Eigen::Index>(a)];
}

void ElementSink::add_rate(std::span<const int> dofs, const Eigen::VectorXd& r_t) { assembler_.add_rate(dofs, r_t); }

}  // namespace fibrane::model
