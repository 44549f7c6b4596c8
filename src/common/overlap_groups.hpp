#pragma once
// Groups of sets joined through shared members: two sets are in one group when they share a member, or
// are joined through a chain of such sets (a union-find over the sets).
#include <cstddef>
#include <numeric>
#include <unordered_map>
#include <vector>

namespace fibrane {

// The group of each set, numbered 0, 1, ... in the order of each group's first set (so that the numbers do
// not depend on the hashing of the members).
inline std::vector<int> overlap_groups(const std::vector<const std::vector<int>*>& sets) {
  const int n = static_cast<int>(sets.size());
  std::vector<int> parent(static_cast<std::size_t>(n));
  std::iota(parent.begin(), parent.end(), 0);
  auto up = [&](int k) -> int& { return parent[static_cast<std::size_t>(k)]; };
  auto root = [&](int k) {
    while (up(k) != k) k = up(k) = up(up(k));  // path halving
    return k;
  };
  std::unordered_map<int, int> first_with;  // member -> the first set that holds it
  for (int k = 0; k < n; ++k)
    for (int member : *sets[static_cast<std::size_t>(k)]) {
      const auto [it, inserted] = first_with.emplace(member, k);
      if (!inserted) up(root(k)) = root(it->second);
    }
  std::vector<int> group_of_root(static_cast<std::size_t>(n), -1), group(static_cast<std::size_t>(n));
  int groups = 0;
  for (int k = 0; k < n; ++k) {
    int& g = group_of_root[static_cast<std::size_t>(root(k))];
    if (g < 0) g = groups++;
    group[static_cast<std::size_t>(k)] = g;
  }
  return group;
}

}  // namespace fibrane
