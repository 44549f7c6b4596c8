#pragma once
// A bounding-volume hierarchy over axis-aligned boxes (beam elements: the box of an element's control
// polygon holds the element by the convex-hull property of B-splines and NURBS with positive weights).
// Built once by median splits along the longest side; when the points move, refit() recomputes the boxes
// bottom-up on the same topology (O(n)), and rebuild() is only needed when the topology has become poor.
// Queries: the leaves within a distance of a point, and all pairs of leaves of two trees (or of one tree
// with itself) whose boxes come within a distance (the law's cut-off plus the radii).
#include <Eigen/Geometry>
#include <functional>
#include <utility>
#include <vector>

namespace fibrane::interaction {

// BVH over the boxes of items 0..n-1; see the file comment.
class BoxTree {
 public:
  BoxTree() = default;
  explicit BoxTree(const std::vector<Eigen::AlignedBox3d>& boxes) { rebuild(boxes); }
  void rebuild(const std::vector<Eigen::AlignedBox3d>& boxes);
  // New boxes for the same items (same count), same topology. Throws std::invalid_argument on a count change.
  void refit(const std::vector<Eigen::AlignedBox3d>& boxes);

  // Items whose box lies within `distance` of p (exact box distance), appended to `out` unsorted.
  void near_point(const Eigen::Vector3d& p, double distance, std::vector<int>& out) const;
  // Calls visit(i, j) for every item i of this tree and j of `other` whose boxes are within `distance`.
  // With other == *this each unordered pair i < j is visited once (and i == j never).
  void near_pairs(const BoxTree& other, double distance, const std::function<void(int, int)>& visit) const;

  int size() const { return static_cast<int>(boxes_.size()); }
  const Eigen::AlignedBox3d& box(int item) const { return boxes_[static_cast<std::size_t>(item)]; }

 private:
  struct Node {
    Eigen::AlignedBox3d box;
    int left = -1, right = -1;  // children, or -1 for a leaf
    int item = -1;              // leaf: its item
  };
  int build(std::vector<int>& items, int first, int count);
  void refit_node(int node);
  void pairs(const BoxTree& other, int a, int b, double distance, bool self,
             const std::function<void(int, int)>& visit) const;
  std::vector<Eigen::AlignedBox3d> boxes_;
  std::vector<Node> nodes_;
  int root_ = -1;
};

// Squared distance between two boxes (0 if they overlap).
double squared_distance(const Eigen::AlignedBox3d& a, const Eigen::AlignedBox3d& b);

}  // namespace fibrane::interaction
