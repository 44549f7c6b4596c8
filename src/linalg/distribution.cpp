#include "linalg/distribution.hpp"

#include <algorithm>

namespace fibrane::solve {

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

}  // namespace fibrane::solve
