#include "linalg/separator_tree.hpp"

#include <cholmod.h>

#include <algorithm>

#include "linalg/cholmod_permuted_lower.hpp"
#include "linalg/principal_lower.hpp"

namespace fibrane::solve {

bool SeparatorTree::build(const Eigen::SparseMatrix<double>& a, const Options& options) {
  clear();
  std::vector<int> all(static_cast<std::size_t>(a.rows()));
  for (int i = 0; i < a.rows(); ++i) all[static_cast<std::size_t>(i)] = i;
  const int root = bisect(a, std::move(all), options.levels, options);
  if (nodes_[static_cast<std::size_t>(root)].domain()) {
    clear();
    return false;
  }
  number();
  update_boundaries(a);
  return true;
}

namespace {

// METIS's node bisection of the graph of a(rows, rows) (cholmod_bisect): partition[k] 0 or 1 for the two
// parts, 2 for the separator; the separator's size, or a negative number where CHOLMOD failed. The pieces
// are bisected one after the other: Debian's METIS draws its random numbers from the C library's rand(),
// one state for the process, so that two bisections side by side would each depend on the other's timing.
long bisection(const Eigen::SparseMatrix<double>& a, const std::vector<int>& rows, std::vector<int>& partition) {
  const PrincipalLower piece = principal_lower(a, rows);
  cholmod_sparse view = cholmod_lower_view(piece.size(), piece.column_start.data(), piece.row.data(), nullptr);
  cholmod_common common;
  cholmod_start(&common);
  common.print = 0;
  const long s = cholmod_bisect(&view, nullptr, 0, 1, partition.data(), &common);
  cholmod_finish(&common);
  return s;
}

}  // namespace

// The three parts of METIS's bisection of `rows` (parts[2] the separator), where it serves: a piece of
// `min_rows` at least, a separator of one row to `max_separator`, each part a fifth of the piece at least.
bool SeparatorTree::bisects(const Eigen::SparseMatrix<double>& a, const std::vector<int>& rows, const Options& options,
                            std::vector<int> (&parts)[3]) {
  const auto n = static_cast<long>(rows.size());
  if (n < options.min_rows) return false;
  std::vector<int> partition(rows.size(), 0);
  const long s = bisection(a, rows, partition);
  if (s <= 0 || s > options.max_separator) return false;
  for (std::vector<int>& part : parts) part.clear();
  for (std::size_t i = 0; i < rows.size(); ++i) parts[partition[i]].push_back(rows[i]);
  return 5 * static_cast<long>(std::min(parts[0].size(), parts[1].size())) >= n;
}

// The node for `rows`: a separator with two subtrees where the bisection serves and levels are left, a
// domain otherwise. Nodes are appended in postorder.
int SeparatorTree::bisect(const Eigen::SparseMatrix<double>& a, std::vector<int> rows, int levels,
                          const Options& options) {
  std::vector<int> parts[3];
  if (levels > 0 && bisects(a, rows, options, parts)) {
    rows.clear();
    rows.shrink_to_fit();
    const int c0 = bisect(a, std::move(parts[0]), levels - 1, options);
    const int c1 = bisect(a, std::move(parts[1]), levels - 1, options);
    Node node;
    node.rows = std::move(parts[2]);
    node.children[0] = c0;
    node.children[1] = c1;
    node.first = nodes_[static_cast<std::size_t>(c0)].first;
    node.height = 1 + std::max(nodes_[static_cast<std::size_t>(c0)].height, nodes_[static_cast<std::size_t>(c1)].height);
    nodes_.push_back(std::move(node));
    const int id = static_cast<int>(nodes_.size()) - 1;
    nodes_[static_cast<std::size_t>(c0)].parent = nodes_[static_cast<std::size_t>(c1)].parent = id;
    return id;
  }
  Node node;
  node.rows = std::move(rows);
  node.first = static_cast<int>(nodes_.size());
  nodes_.push_back(std::move(node));
  return static_cast<int>(nodes_.size()) - 1;
}

// The domain k becomes nodes k and k + 1 (its two parts) and k + 2 (their separator, in k's place below
// its parent); the nodes after k move two places on.
bool SeparatorTree::refine(const Eigen::SparseMatrix<double>& a, int k, const Options& options) {
  const auto uk = static_cast<std::size_t>(k);
  std::vector<int> parts[3];
  if (k < 0 || uk >= nodes_.size() || !nodes_[uk].domain() || !bisects(a, nodes_[uk].rows, options, parts)) return false;
  auto moved = [k](int t) { return t < k ? t : t + 2; };
  for (Node& node : nodes_) {
    for (int& c : node.children)
      if (c >= 0) c = moved(c);
    if (node.parent >= 0) node.parent = moved(node.parent);
    if (node.first > k) node.first += 2;
  }
  Node separator = std::move(nodes_[uk]);
  separator.rows = std::move(parts[2]);
  separator.children[0] = k;
  separator.children[1] = k + 1;
  Node halves[2];
  for (int i = 0; i < 2; ++i) {
    halves[i].rows = std::move(parts[i]);
    halves[i].first = k + i;
    halves[i].parent = k + 2;
  }
  nodes_[uk] = std::move(separator);
  nodes_.insert(nodes_.begin() + k, std::make_move_iterator(halves), std::make_move_iterator(halves + 2));
  for (Node& node : nodes_)  // postorder: children before their parent
    if (!node.domain())
      node.height = 1 + std::max(nodes_[static_cast<std::size_t>(node.children[0])].height,
                                 nodes_[static_cast<std::size_t>(node.children[1])].height);
  number();
  update_boundaries(a);
  return true;
}

void SeparatorTree::number() {
  std::size_t n = 0;
  for (const Node& node : nodes_) n += node.rows.size();
  node_of_.assign(n, -1);
  position_.assign(n, -1);
  int position = 0;
  for (std::size_t k = 0; k < nodes_.size(); ++k)
    for (const int r : nodes_[k].rows) {
      node_of_[static_cast<std::size_t>(r)] = static_cast<int>(k);
      position_[static_cast<std::size_t>(r)] = position++;
    }
}

bool SeparatorTree::divides(const Eigen::SparseMatrix<double>& a) const {
  if (empty() || node_of_.size() != static_cast<std::size_t>(a.rows())) return false;
  for (int j = 0; j < a.cols(); ++j) {
    const int v = node_of(j);
    for (int p = a.outerIndexPtr()[j]; p < a.outerIndexPtr()[j + 1]; ++p) {
      const int u = node_of(a.innerIndexPtr()[p]);
      if (u != v && !above(u, v) && !above(v, u)) return false;
    }
  }
  return true;
}

void SeparatorTree::update_boundaries(const Eigen::SparseMatrix<double>& a) {
  for (Node& node : nodes_) node.boundary.clear();
  // the ancestors' rows adjacent to each node's rows (every entry seen from both of its ends)
  for (int j = 0; j < a.cols(); ++j) {
    const int v = node_of(j);
    for (int p = a.outerIndexPtr()[j]; p < a.outerIndexPtr()[j + 1]; ++p) {
      const int i = a.innerIndexPtr()[p], u = node_of(i);
      if (above(u, v)) nodes_[static_cast<std::size_t>(v)].boundary.push_back(i);
      if (above(v, u)) nodes_[static_cast<std::size_t>(u)].boundary.push_back(j);
    }
  }
  // and the children's boundaries less the node's own rows, in postorder (children first)
  auto by_position = [this](int x, int y) { return position(x) < position(y); };
  for (std::size_t k = 0; k < nodes_.size(); ++k) {
    Node& node = nodes_[k];
    if (!node.domain())
      for (const int c : node.children)
        for (const int r : nodes_[static_cast<std::size_t>(c)].boundary)
          if (node_of(r) != static_cast<int>(k)) node.boundary.push_back(r);
    std::sort(node.boundary.begin(), node.boundary.end(), by_position);
    node.boundary.erase(std::unique(node.boundary.begin(), node.boundary.end()), node.boundary.end());
  }
}

int SeparatorTree::domains() const {
  return static_cast<int>(std::count_if(nodes_.begin(), nodes_.end(), [](const Node& n) { return n.domain(); }));
}

long SeparatorTree::separator_rows() const {
  long s = 0;
  for (const Node& node : nodes_)
    if (!node.domain()) s += static_cast<long>(node.rows.size());
  return s;
}

}  // namespace fibrane::solve
