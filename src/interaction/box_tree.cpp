#include "interaction/box_tree.hpp"

#include <algorithm>
#include <stdexcept>

namespace fibrane::interaction {

double squared_distance(const Eigen::AlignedBox3d& a, const Eigen::AlignedBox3d& b) {
  const Eigen::Vector3d gap =
      (a.min() - b.max()).cwiseMax(b.min() - a.max()).cwiseMax(Eigen::Vector3d::Zero());
  return gap.squaredNorm();
}

void BoxTree::rebuild(const std::vector<Eigen::AlignedBox3d>& boxes) {
  boxes_ = boxes;
  nodes_.clear();
  nodes_.reserve(2 * boxes.size());
  std::vector<int> items(boxes.size());
  for (std::size_t i = 0; i < items.size(); ++i) items[i] = static_cast<int>(i);
  root_ = items.empty() ? -1 : build(items, 0, static_cast<int>(items.size()));
}

int BoxTree::build(std::vector<int>& items, int first, int count) {
  const int node = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  if (count == 1) {
    nodes_[node].item = items[first];
    nodes_[node].box = boxes_[items[first]];
    return node;
  }
  Eigen::AlignedBox3d centres;
  for (int i = first; i < first + count; ++i) centres.extend(boxes_[items[i]].center());
  int axis = 0;
  centres.sizes().maxCoeff(&axis);
  const int half = count / 2;
  std::nth_element(items.begin() + first, items.begin() + first + half, items.begin() + first + count,
                   [&](int a, int b) { return boxes_[a].center()[axis] < boxes_[b].center()[axis]; });
  const int left = build(items, first, half);
  const int right = build(items, first + half, count - half);
  nodes_[node].left = left;
  nodes_[node].right = right;
  nodes_[node].box = nodes_[left].box.merged(nodes_[right].box);
  return node;
}

void BoxTree::refit(const std::vector<Eigen::AlignedBox3d>& boxes) {
  if (boxes.size() != boxes_.size()) throw std::invalid_argument("BoxTree::refit: the number of boxes changed");
  boxes_ = boxes;
  if (root_ >= 0) refit_node(root_);
}

void BoxTree::refit_node(int node) {
  Node& n = nodes_[node];
  if (n.item >= 0) {
    n.box = boxes_[n.item];
    return;
  }
  refit_node(n.left);
  refit_node(n.right);
  nodes_[node].box = nodes_[nodes_[node].left].box.merged(nodes_[nodes_[node].right].box);
}

void BoxTree::near_point(const Eigen::Vector3d& p, double distance, std::vector<int>& out) const {
  if (root_ < 0) return;
  const double limit = distance * distance;
  std::vector<int> stack{root_};
  while (!stack.empty()) {
    const Node& n = nodes_[stack.back()];
    stack.pop_back();
    if (n.box.squaredExteriorDistance(p) > limit) continue;
    if (n.item >= 0) {
      out.push_back(n.item);
    } else {
      stack.push_back(n.left);
      stack.push_back(n.right);
    }
  }
}

void BoxTree::near_pairs(const BoxTree& other, double distance, const std::function<void(int, int)>& visit) const {
  if (root_ < 0 || other.root_ < 0) return;
  pairs(other, root_, other.root_, distance * distance, &other == this, visit);
}

void BoxTree::pairs(const BoxTree& other, int a, int b, double limit, bool self,
                    const std::function<void(int, int)>& visit) const {
  const Node& na = nodes_[a];
  const Node& nb = other.nodes_[b];
  if (self && a == b) {  // a node with itself: its children with themselves and with each other
    if (na.item >= 0) return;
    pairs(other, na.left, na.left, limit, true, visit);
    pairs(other, na.right, na.right, limit, true, visit);
    pairs(other, na.left, na.right, limit, true, visit);
    return;
  }
  if (squared_distance(na.box, nb.box) > limit) return;
  if (na.item >= 0 && nb.item >= 0) {
    if (self && na.item > nb.item) visit(nb.item, na.item);
    else visit(na.item, nb.item);
    return;
  }
  // Descend into the larger node (or the only internal one).
  const bool split_a = nb.item >= 0 || (na.item < 0 && na.box.volume() >= nb.box.volume());
  if (split_a) {
    pairs(other, na.left, b, limit, self, visit);
    pairs(other, na.right, b, limit, self, visit);
  } else {
    pairs(other, a, nb.left, limit, self, visit);
    pairs(other, a, nb.right, limit, self, visit);
  }
}

}  // namespace fibrane::interaction
