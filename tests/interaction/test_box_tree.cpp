// The bounding-volume hierarchy of interaction/box_tree.hpp against brute force: the items near a point,
// the pairs of two trees and of one tree with itself within a distance, before and after a refit that
// moves every box.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "interaction/box_tree.hpp"

namespace fibrane::interaction {
namespace {

std::vector<Eigen::AlignedBox3d> random_boxes(std::mt19937& rng, int n, double spread) {
  std::uniform_real_distribution<double> u(0, spread), size(0.01, 0.3);
  std::vector<Eigen::AlignedBox3d> boxes;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d lo(u(rng), u(rng), u(rng));
    boxes.emplace_back(lo, lo + Eigen::Vector3d(size(rng), size(rng), size(rng)));
  }
  return boxes;
}

std::set<std::pair<int, int>> brute_pairs(const std::vector<Eigen::AlignedBox3d>& a,
                                          const std::vector<Eigen::AlignedBox3d>& b, double distance, bool self) {
  std::set<std::pair<int, int>> out;
  for (int i = 0; i < static_cast<int>(a.size()); ++i)
    for (int j = self ? i + 1 : 0; j < static_cast<int>(b.size()); ++j)
      if (squared_distance(a[i], b[j]) <= distance * distance) out.emplace(i, j);
  return out;
}

TEST(BoxTree, QueriesMatchBruteForceBeforeAndAfterRefit) {
  std::mt19937 rng(11);
  auto a = random_boxes(rng, 300, 5.0), b = random_boxes(rng, 200, 5.0);
  BoxTree ta(a), tb(b);
  std::normal_distribution<double> move(0, 0.2);
  for (int round = 0; round < 2; ++round) {
    const double distance = 0.15;
    std::set<std::pair<int, int>> found, self_found;
    tb.near_pairs(ta, distance, [&](int i, int j) { found.emplace(j, i); });
    EXPECT_EQ(found, brute_pairs(a, b, distance, false));
    ta.near_pairs(ta, distance, [&](int i, int j) {
      EXPECT_LT(i, j);
      EXPECT_TRUE(self_found.emplace(i, j).second) << "pair visited twice";
    });
    EXPECT_EQ(self_found, brute_pairs(a, a, distance, true));
    EXPECT_GT(self_found.size(), 10u);
    for (int k = 0; k < 20; ++k) {
      const Eigen::Vector3d p(move(rng) + 2.5, move(rng) + 2.5, move(rng) + 2.5);
      std::vector<int> near;
      ta.near_point(p, 0.5, near);
      std::sort(near.begin(), near.end());
      std::vector<int> expected;
      for (int i = 0; i < static_cast<int>(a.size()); ++i)
        if (a[i].squaredExteriorDistance(p) <= 0.25) expected.push_back(i);
      EXPECT_EQ(near, expected);
    }
    // Every box moves (the topology stays): the refitted tree answers for the new boxes.
    for (auto& box : a) box.translate(Eigen::Vector3d(move(rng), move(rng), move(rng)));
    for (auto& box : b) box.translate(Eigen::Vector3d(move(rng), move(rng), move(rng)));
    ta.refit(a);
    tb.refit(b);
  }
  EXPECT_THROW(ta.refit(b), std::invalid_argument);
}

}  // namespace
}  // namespace fibrane::interaction
