// The sharing of elements and unknowns in distributed runs (linalg/partition.hpp, UnknownOwnership):
// exact integer checks on small element lists, with distributions that partition without communicating.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "linalg/partition.hpp"

namespace fibrane::solve {
namespace {

// `size` processes whose graph partition gives vertex v the part parts[v] (empty: no partitioner).
class FakeProcesses final : public Distribution {
 public:
  FakeProcesses(int size, std::vector<int> parts) : size_(size), parts_(std::move(parts)) {}
  int size() const override { return size_; }
  std::vector<int> partition(const Graph& graph, std::string& why) const override {
    EXPECT_TRUE(parts_.empty() || static_cast<int>(parts_.size()) == graph.vertices());
    if (parts_.empty()) why = "no partitioner here";
    return parts_;
  }

 private:
  int size_;
  std::vector<int> parts_;
};

// A chain of `count` elements, element e touching unknowns 2e .. 2e + 3 (neighbours share two unknowns).
std::vector<std::vector<int>> chain(int count) {
  std::vector<std::vector<int>> out;
  for (int e = 0; e < count; ++e) out.push_back({2 * e, 2 * e + 1, 2 * e + 2, 2 * e + 3});
  return out;
}

TEST(UnknownOwnership, ContiguousRangesAreTheIdentityNumbering) {
  const auto o = UnknownOwnership::contiguous(7, 3);
  EXPECT_TRUE(o.identity());
  EXPECT_EQ(o.processes(), 3);
  for (int p = 0; p <= 3; ++p) EXPECT_EQ(o.begin(p), p * 2 + std::min(p, 1));
  for (int i = 0; i < 7; ++i) {
    EXPECT_EQ(o.row(i), i);
    EXPECT_EQ(o.owner(i), i < 3 ? 0 : i < 5 ? 1 : 2);
  }
}

// Each process's unknowns are one range of rows, in the model's order; row() and unknown() are inverse.
TEST(UnknownOwnership, OwnersGiveContiguousRowsPerProcess) {
  const std::vector<int> owner{1, 0, 2, 1, 0, 0, 2, 1};
  const auto o = UnknownOwnership::from_owners(owner, 3);
  EXPECT_FALSE(o.identity());
  EXPECT_EQ(o.count(0), 3);
  EXPECT_EQ(o.count(1), 3);
  EXPECT_EQ(o.count(2), 2);
  EXPECT_EQ(o.begin(3), 8);
  for (int i = 0; i < 8; ++i) {
    EXPECT_EQ(o.owner(i), owner[static_cast<std::size_t>(i)]);
    EXPECT_GE(o.row(i), o.begin(o.owner(i)));
    EXPECT_LT(o.row(i), o.begin(o.owner(i) + 1));
    EXPECT_EQ(o.unknown(o.row(i)), i);
  }
  for (int r = 1; r < 8; ++r)
    if (o.owner(o.unknown(r)) == o.owner(o.unknown(r - 1))) {
      EXPECT_LT(o.unknown(r - 1), o.unknown(r));
    }
  EXPECT_TRUE(UnknownOwnership::from_owners({0, 0, 1, 1}, 2).identity());
  EXPECT_THROW(UnknownOwnership::from_owners({0, 3}, 2), std::invalid_argument);
}

// Adjacent: sharing an unknown; edge weight: how many. Symmetric, sorted, no self loops; vertex weight:
// DOF count squared.
TEST(ElementGraph, ElementsSharingUnknownsAreNeighbours) {
  auto unknowns = chain(4);
  unknowns.push_back({});  // touches no unknown: isolated
  std::vector<std::vector<int>> dofs = unknowns;
  dofs.back() = {0, 1};
  const Graph g = element_graph(unknowns, dofs, 10);
  ASSERT_EQ(g.vertices(), 5);
  const std::vector<std::set<int>> expected{{1}, {0, 2}, {1, 3}, {2}, {}};
  for (int v = 0; v < 5; ++v) {
    const std::vector<int> row(g.adjacency.begin() + g.begin[v], g.adjacency.begin() + g.begin[v + 1]);
    EXPECT_TRUE(std::is_sorted(row.begin(), row.end()));
    EXPECT_EQ(std::set<int>(row.begin(), row.end()), expected[static_cast<std::size_t>(v)]) << v;
    for (int k = g.begin[v]; k < g.begin[v + 1]; ++k) EXPECT_EQ(g.edge_weight[static_cast<std::size_t>(k)], 2);
    EXPECT_EQ(g.weight[static_cast<std::size_t>(v)], v < 4 ? 16 : 4);
  }
}

TEST(ElementGraph, EdgeWeightsCountTheSharedUnknowns) {
  const std::vector<std::vector<int>> unknowns{{0, 1, 2}, {1, 2, 3}, {2, 9}};
  const Graph g = element_graph(unknowns, unknowns, 10);
  EXPECT_EQ(g.adjacency, (std::vector<int>{1, 2, 0, 2, 0, 1}));
  EXPECT_EQ(g.edge_weight, (std::vector<int>{2, 1, 2, 1, 1, 1}));
}

// The process with the most touching elements owns an unknown; ties go to the lower rank; an unknown no
// element touches goes to process 0.
TEST(OwnersByElements, MajorityOfTouchingElementsWithTiesToTheLowerRank) {
  const std::vector<std::vector<int>> unknowns{{0, 1}, {1, 2}, {1, 2, 3}, {3}};
  const auto o = owners_by_elements(unknowns, {2, 1, 1, 2}, 5, 3);
  EXPECT_EQ(o.owner(0), 2);  // element 0 only
  EXPECT_EQ(o.owner(1), 1);  // elements 0 (2), 1 and 2 (1)
  EXPECT_EQ(o.owner(2), 1);
  EXPECT_EQ(o.owner(3), 1);  // elements 2 (1) and 3 (2): a tie
  EXPECT_EQ(o.owner(4), 0);  // untouched
}

// graph: elements by the partition, unknowns by them; the report counts elements, weights, interface.
TEST(PartitionElements, GraphPartitionAndItsReport) {
  const auto unknowns = chain(6);  // unknowns 0 .. 13
  const FakeProcesses d(2, {0, 0, 0, 1, 1, 1});
  const ElementPartition p = partition_elements(unknowns, unknowns, 14, d);
  EXPECT_EQ(p.method, Partitioning::graph);
  EXPECT_TRUE(p.note.empty());
  EXPECT_EQ(p.element_owner, (std::vector<int>{0, 0, 0, 1, 1, 1}));
  EXPECT_EQ(p.elements, (std::vector<int>{3, 3}));
  EXPECT_EQ(p.weight, (std::vector<double>{48, 48}));
  EXPECT_DOUBLE_EQ(p.imbalance, 1.0);
  // Elements 2 and 3 share unknowns 6 and 7: the interface; the tie gives them to process 0.
  EXPECT_EQ(p.interface_unknowns, 2);
  EXPECT_EQ(p.unknowns.count(0), 8);
  EXPECT_EQ(p.unknowns.count(1), 6);
  const FakeProcesses uneven(2, {0, 0, 0, 0, 1, 1});
  EXPECT_DOUBLE_EQ(partition_elements(unknowns, unknowns, 14, uneven).imbalance, 64.0 / 48.0);
}

// contiguous, and graph without a partitioner: ranges, and elements by their smallest unknown's owner.
TEST(PartitionElements, ContiguousRangesAndTheFallback) {
  const auto unknowns = chain(6);
  for (const bool ask_graph : {false, true}) {
    FakeProcesses d(2, {});
    d.set_partitioning(ask_graph ? Partitioning::graph : Partitioning::contiguous);
    const ElementPartition p = partition_elements(unknowns, unknowns, 14, d);
    EXPECT_EQ(p.method, Partitioning::contiguous);
    EXPECT_EQ(p.note.empty(), !ask_graph);
    if (ask_graph) {
      EXPECT_NE(p.note.find("no partitioner here"), std::string::npos) << p.note;
    }
    EXPECT_TRUE(p.unknowns.identity());
    // Unknowns 0 .. 6 on process 0: elements 0 .. 3 start there (element 3 at unknown 6).
    EXPECT_EQ(p.element_owner, (std::vector<int>{0, 0, 0, 0, 1, 1}));
    EXPECT_EQ(p.elements, (std::vector<int>{4, 2}));
    // Elements 3 (process 0) and 4 (process 1) share unknowns 8 and 9.
    EXPECT_EQ(p.interface_unknowns, 2);
  }
}

}  // namespace
}  // namespace fibrane::solve
