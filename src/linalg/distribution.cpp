#include "linalg/distribution.hpp"

#include <algorithm>
#include <stdexcept>

namespace fibrane::solve {

std::vector<int> Distribution::partition(const Graph& /*graph*/, std::string& why) const {
  why = "this distribution does not partition graphs";
  return {};
}

int Distribution::range_begin(int p, int n) const {
  const int q = n / size(), extra = n % size();
  return p * q + std::min(p, extra);
}

int Distribution::owner(int i, int n) const {
  const int q = n / size(), extra = n % size();
  // The first `extra` processes hold q + 1 unknowns each, the others q.
  const int big = extra * (q + 1);
  if (i < big) return i / (q + 1);
  return extra + (q > 0 ? (i - big) / q : 0);
}

UnknownOwnership UnknownOwnership::contiguous(int n, int processes) {
  UnknownOwnership o;
  o.owner_.resize(static_cast<std::size_t>(n));
  o.begin_.assign(static_cast<std::size_t>(processes) + 1, 0);
  const int q = n / processes, extra = n % processes;
  for (std::size_t p = 0; p < static_cast<std::size_t>(processes); ++p) {
    o.begin_[p + 1] = o.begin_[p] + q + (static_cast<int>(p) < extra ? 1 : 0);
    std::fill(o.owner_.begin() + o.begin_[p], o.owner_.begin() + o.begin_[p + 1], static_cast<int>(p));
  }
  return o;
}

UnknownOwnership UnknownOwnership::from_owners(std::vector<int> owner, int processes) {
  UnknownOwnership o;
  o.begin_.assign(static_cast<std::size_t>(processes) + 1, 0);
  for (int p : owner) {
    if (p < 0 || p >= processes) throw std::invalid_argument("UnknownOwnership: an owner outside 0 .. processes - 1");
    ++o.begin_[static_cast<std::size_t>(p) + 1];
  }
  for (std::size_t p = 0; p < static_cast<std::size_t>(processes); ++p) o.begin_[p + 1] += o.begin_[p];
  std::vector<int> next(o.begin_.begin(), o.begin_.end() - 1);
  o.row_.resize(owner.size());
  o.unknown_.resize(owner.size());
  o.identity_ = true;
  for (std::size_t i = 0; i < owner.size(); ++i) {
    const int r = next[static_cast<std::size_t>(owner[i])]++;
    o.row_[i] = r;
    o.unknown_[static_cast<std::size_t>(r)] = static_cast<int>(i);
    o.identity_ = o.identity_ && r == static_cast<int>(i);
  }
  if (o.identity_) {
    o.row_.clear();
    o.unknown_.clear();
  }
  o.owner_ = std::move(owner);
  return o;
}

}  // namespace fibrane::solve
