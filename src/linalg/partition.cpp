#include "linalg/partition.hpp"

#include <algorithm>
#include <numeric>
#include <utility>

namespace fibrane::solve {

namespace {

// The elements that touch each unknown, in compressed rows: unknown u's are at [begin[u], begin[u + 1]).
struct Touching {
  std::vector<int> begin, elements;
};

Touching touching(const std::vector<std::vector<int>>& unknowns, int n) {
  Touching t;
  t.begin.assign(static_cast<std::size_t>(n) + 1, 0);
  for (const auto& list : unknowns)
    for (int u : list) ++t.begin[static_cast<std::size_t>(u) + 1];
  std::partial_sum(t.begin.begin(), t.begin.end(), t.begin.begin());
  t.elements.resize(static_cast<std::size_t>(t.begin.back()));
  std::vector<int> next(t.begin.begin(), t.begin.end() - 1);
  for (std::size_t e = 0; e < unknowns.size(); ++e)
    for (int u : unknowns[e]) {
      const auto slot = static_cast<std::size_t>(next[static_cast<std::size_t>(u)]++);
      t.elements[slot] = static_cast<int>(e);
    }
  return t;
}

// Elements, weight per process, interface unknowns and imbalance of `p`.
void describe(ElementPartition& p, const std::vector<std::vector<int>>& unknowns, const Graph& graph, int processes) {
  p.elements.assign(static_cast<std::size_t>(processes), 0);
  p.weight.assign(static_cast<std::size_t>(processes), 0.0);
  for (std::size_t e = 0; e < p.element_owner.size(); ++e) {
    const auto owner = static_cast<std::size_t>(p.element_owner[e]);
    ++p.elements[owner];
    p.weight[owner] += graph.weight[e];
  }
  const int n = p.unknowns.unknowns();
  std::vector<int> first_process(static_cast<std::size_t>(n), -1);
  std::vector<char> shared(static_cast<std::size_t>(n), 0);
  for (std::size_t e = 0; e < unknowns.size(); ++e)
    for (int u : unknowns[e]) {
      int& first = first_process[static_cast<std::size_t>(u)];
      if (first < 0) first = p.element_owner[e];
      else if (first != p.element_owner[e]) shared[static_cast<std::size_t>(u)] = 1;
    }
  p.interface_unknowns = static_cast<int>(std::count(shared.begin(), shared.end(), 1));
  const double total = std::accumulate(p.weight.begin(), p.weight.end(), 0.0);
  const double largest = *std::max_element(p.weight.begin(), p.weight.end());
  p.imbalance = total > 0 ? largest / (total / processes) : 1.0;
}

}  // namespace

std::vector<std::vector<int>> element_unknowns(const ConstraintSet& constraints,
                                               const std::vector<std::vector<int>>& element_dofs) {
  std::vector<std::vector<int>> out(element_dofs.size());
  for (std::size_t e = 0; e < element_dofs.size(); ++e) {
    auto& list = out[e];
    for (int d : element_dofs[e])
      for (const auto& [i, coef] : constraints.expansion(d)) list.push_back(i);
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  return out;
}

Graph element_graph(const std::vector<std::vector<int>>& unknowns, const std::vector<std::vector<int>>& dofs, int n) {
  const Touching t = touching(unknowns, n);
  Graph g;
  const int count = static_cast<int>(unknowns.size());
  g.begin.reserve(static_cast<std::size_t>(count) + 1);
  std::vector<int> seen(static_cast<std::size_t>(count), -1), slot(static_cast<std::size_t>(count), 0);
  std::vector<std::pair<int, int>> row;  // (neighbour, shared unknowns)
  for (int e = 0; e < count; ++e) {
    row.clear();
    seen[static_cast<std::size_t>(e)] = e;
    for (int u : unknowns[static_cast<std::size_t>(e)])
      for (int k = t.begin[static_cast<std::size_t>(u)]; k < t.begin[static_cast<std::size_t>(u) + 1]; ++k) {
        const auto other = static_cast<std::size_t>(t.elements[static_cast<std::size_t>(k)]);
        if (seen[other] == e) {
          if (static_cast<int>(other) != e) ++row[static_cast<std::size_t>(slot[other])].second;
          continue;
        }
        seen[other] = e;
        slot[other] = static_cast<int>(row.size());
        row.emplace_back(static_cast<int>(other), 1);
      }
    std::sort(row.begin(), row.end());
    for (const auto& [other, shared] : row) {
      g.adjacency.push_back(other);
      g.edge_weight.push_back(shared);
    }
    g.begin.push_back(static_cast<int>(g.adjacency.size()));
  }
  double total = 0.0;
  g.weight.resize(static_cast<std::size_t>(count));
  for (int e = 0; e < count; ++e) {
    const double size = static_cast<double>(dofs[static_cast<std::size_t>(e)].size());
    total += std::max(1.0, size * size);
  }
  const double scale = std::max(1.0, total / double(1 << 30) * 1.01);
  for (int e = 0; e < count; ++e) {
    const double size = static_cast<double>(dofs[static_cast<std::size_t>(e)].size());
    g.weight[static_cast<std::size_t>(e)] = std::max(1, static_cast<int>(size * size / scale));
  }
  return g;
}

int smallest_unknown_owner(const std::vector<int>& unknowns, const UnknownOwnership& ownership) {
  return unknowns.empty() ? 0 : ownership.owner(unknowns.front());
}

UnknownOwnership owners_by_elements(const std::vector<std::vector<int>>& unknowns, const std::vector<int>& element_owner,
                                    int n, int processes) {
  const Touching t = touching(unknowns, n);
  std::vector<int> owner(static_cast<std::size_t>(n), 0), votes(static_cast<std::size_t>(processes), 0);
  for (int u = 0; u < n; ++u) {
    const auto b = static_cast<std::size_t>(t.begin[static_cast<std::size_t>(u)]);
    const auto e = static_cast<std::size_t>(t.begin[static_cast<std::size_t>(u) + 1]);
    auto process = [&](std::size_t k) {
      return static_cast<std::size_t>(element_owner[static_cast<std::size_t>(t.elements[k])]);
    };
    for (std::size_t k = b; k < e; ++k) ++votes[process(k)];
    std::size_t best = 0;
    for (std::size_t p = 1; p < votes.size(); ++p)
      if (votes[p] > votes[best]) best = p;
    for (std::size_t k = b; k < e; ++k) votes[process(k)] = 0;
    owner[static_cast<std::size_t>(u)] = static_cast<int>(best);
  }
  return UnknownOwnership::from_owners(std::move(owner), processes);
}

ElementPartition partition_elements(const std::vector<std::vector<int>>& unknowns,
                                    const std::vector<std::vector<int>>& dofs, int n, const Distribution& distribution) {
  ElementPartition p;
  const int processes = distribution.size();
  const Graph graph = element_graph(unknowns, dofs, n);
  if (distribution.partitioning() == Partitioning::graph) {
    std::string why;
    std::vector<int> parts = distribution.partition(graph, why);
    if (!parts.empty()) {
      p.method = Partitioning::graph;
      p.element_owner = std::move(parts);
      p.unknowns = owners_by_elements(unknowns, p.element_owner, n, processes);
    } else {
      p.note = "no graph partition (" + why + "): the unknowns are owned in contiguous ranges";
    }
  }
  if (p.method == Partitioning::contiguous) {
    p.unknowns = UnknownOwnership::contiguous(n, processes);
    p.element_owner.reserve(unknowns.size());
    for (const auto& list : unknowns) p.element_owner.push_back(smallest_unknown_owner(list, p.unknowns));
  }
  describe(p, unknowns, graph, processes);
  return p;
}

}  // namespace fibrane::solve
