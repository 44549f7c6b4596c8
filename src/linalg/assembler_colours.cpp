// The colouring side of SparseAssembler (Strategy::Colours): elements of one colour share no DOF and no
// reduced unknown, so a loop over one colour may write straight into the matrix from every thread.
#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "linalg/assembler.hpp"

namespace fibrane::solve {

namespace {

// The element the calling thread visits in a coloured loop, and its assembler (null outside such loops).
struct ExclusiveTarget {
  const SparseAssembler* assembler = nullptr;
  int element = -1;
};
thread_local ExclusiveTarget exclusive_target;

}  // namespace

SparseAssembler::Exclusive::Exclusive(const SparseAssembler& a, int element) {
  exclusive_target = {&a, element};
}

SparseAssembler::Exclusive::~Exclusive() { exclusive_target = {}; }

bool SparseAssembler::exclusive(int element) const {
  if (exclusive_target.assembler != this) return false;
  if (exclusive_target.element != element)
    throw std::logic_error("SparseAssembler::add: element " + std::to_string(element) +
                           " added in the coloured loop's visit of element " +
                           std::to_string(exclusive_target.element) + " (a visit adds its own element only)");
  return true;
}

std::vector<int> SparseAssembler::colour_elements(const ElementTable& t, int num_dofs, int num_free) {
  // Per resource (DOF d, or reduced unknown i as num_dofs + i) a bit set of the colours of the elements
  // holding it; `words` 64-bit words each, doubled when an element finds every colour taken.
  const size_t resources = static_cast<size_t>(num_dofs) + static_cast<size_t>(num_free);
  std::vector<int> colour(static_cast<size_t>(t.size()), 0);
  for (size_t words = 1;; words *= 2) {
    std::vector<std::uint64_t> used(resources * words, 0), taken(words);
    bool fits = true;
    for (int e = 0; e < t.size() && fits; ++e) {
      auto each_resource = [&](auto&& f) {
        for (int k = t.dof_begin[e]; k < t.dof_begin[e + 1]; ++k) f(static_cast<size_t>(t.dofs[k]));
        for (int k = t.reduced_begin[e]; k < t.reduced_begin[e + 1]; ++k)
          f(static_cast<size_t>(num_dofs) + static_cast<size_t>(t.reduced[k]));
      };
      std::fill(taken.begin(), taken.end(), 0);
      each_resource([&](size_t r) {
        for (size_t w = 0; w < words; ++w) taken[w] |= used[r * words + w];
      });
      size_t w = 0;
      while (w < words && taken[w] == ~std::uint64_t{0}) ++w;
      if (w == words) {
        fits = false;
        break;
      }
      const int bit = __builtin_ctzll(~taken[w]);
      colour[static_cast<size_t>(e)] = static_cast<int>(w * 64) + bit;
      each_resource([&](size_t r) { used[r * words + w] |= std::uint64_t{1} << bit; });
    }
    if (fits) return colour;
  }
}

void SparseAssembler::append_colours(const ElementTable& t, int first) {
  const std::vector<int> colour = colour_elements(t, constraints_->num_dofs(), constraints_->num_free());
  const int count = colour.empty() ? 0 : *std::max_element(colour.begin(), colour.end()) + 1;
  std::vector<int> next(static_cast<size_t>(count) + 1, 0);
  for (int c : colour) ++next[static_cast<size_t>(c) + 1];
  for (int c = 0; c < count; ++c) next[c + 1] += next[c];
  const int base = static_cast<int>(colour_order_.size());
  for (int c = 1; c <= count; ++c) colour_begin_.push_back(base + next[c]);
  colour_order_.resize(colour_order_.size() + colour.size());
  for (size_t e = 0; e < colour.size(); ++e)  // in id order: ascending within each colour
    colour_order_[static_cast<size_t>(base + next[colour[e]]++)] = first + static_cast<int>(e);
}

std::span<const int> SparseAssembler::coloured(int colour, int first, int count) const {
  if (colour < 0 || colour >= num_colours())
    throw std::out_of_range("SparseAssembler::coloured: colour " + std::to_string(colour) + " out of range");
  const int* begin = colour_order_.data() + colour_begin_[static_cast<size_t>(colour)];
  const int* end = colour_order_.data() + colour_begin_[static_cast<size_t>(colour) + 1];
  const int* lo = std::lower_bound(begin, end, first);
  const int* hi = std::lower_bound(lo, end, first + count);
  return {lo, static_cast<size_t>(hi - lo)};
}

std::size_t SparseAssembler::buffer_bytes() const {
  std::size_t values = 0;
  auto count = [&](const Buffer& b) { values += b.values.capacity() + b.residual.capacity() + b.rate.capacity(); };
  for (const Buffer& b : buffers_) count(b);
  count(overflow_);
  return values * sizeof(double);
}

}  // namespace fibrane::solve
