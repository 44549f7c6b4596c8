#pragma once
// Nested dissection of a symmetric matrix's graph by METIS's node bisector: the tree of separators and
// domains that the split Cholesky (cholmod_split.hpp) factorises part by part.
#include <Eigen/SparseCore>
#include <vector>

namespace fibrane::solve {

/// A symmetric matrix's rows divided by `levels` rounds of METIS's node bisection (cholmod_bisect): every
/// separator splits its piece into two pieces that no entry of the matrix joins, so that the domains
/// (the leaves) are independent of each other once their separators are known. Nodes are numbered in
/// postorder (a node's subtree is the range [first, node]; the root is the last node), and a row's
/// elimination position is its node's rank in that order, then its place in the node's rows.
///
/// The boundary of a node is the set of rows of its proper ancestors (separators above it) that its
/// subtree's elimination couples: the rows of ancestors adjacent to the node's rows, and its children's
/// boundaries less its own rows (the fronts of a multifrontal factorisation). It is sorted by elimination
/// position.
class SeparatorTree {
 public:
  struct Node {
    std::vector<int> rows;  // a domain's rows, or a separator's
    std::vector<int> boundary;
    int children[2] = {-1, -1};  // a domain's: -1
    int parent = -1;
    int first = 0;   // the first node of the subtree
    int height = 0;  // 0 for domains; 1 + the children's larger height for separators
    bool domain() const { return children[0] < 0; }
  };

  /// Options of the bisection. A piece below `min_rows` rows, or whose bisection leaves a part below a
  /// fifth of the piece or a separator above `max_separator` rows, stays a domain.
  struct Options {
    int levels = 1;
    long min_rows = 1000;
    long max_separator = 5000;
  };

  /// Bisects the graph of `a` (compressed; its lower triangle, or both, is read); false where the top
  /// bisection fails or does not serve (the tree is then empty).
  bool build(const Eigen::SparseMatrix<double>& a, const Options& options);
  /// Whether the tree still divides `a`'s graph: every entry joins rows of one node, or of a node and one of
  /// its ancestors. Where it does, a new pattern can keep the tree; update_boundaries() then renews the rest.
  bool divides(const Eigen::SparseMatrix<double>& a) const;
  /// The boundaries for `a`'s pattern (build() computes them).
  void update_boundaries(const Eigen::SparseMatrix<double>& a);
  /// Bisects the domain `node` once more (the rule of build()'s bisections), where that serves: its two parts
  /// become domains below a new separator in its place. The nodes are numbered anew (in postorder, the two
  /// parts and the separator where the domain was, the nodes after it two places on), and the boundaries
  /// are made for `a`'s pattern; false (the tree as it was) where the bisection does not serve.
  bool refine(const Eigen::SparseMatrix<double>& a, int node, const Options& options);
  void clear() { nodes_.clear(), node_of_.clear(), position_.clear(); }

  bool empty() const { return nodes_.empty(); }
  const std::vector<Node>& nodes() const { return nodes_; }
  int node_of(int row) const { return node_of_[static_cast<std::size_t>(row)]; }
  /// The row's elimination position.
  int position(int row) const { return position_[static_cast<std::size_t>(row)]; }
  /// Whether node u is a proper ancestor of node v.
  bool above(int u, int v) const { return u > v && nodes_[static_cast<std::size_t>(u)].first <= v; }
  /// The domains' count and the separators' rows together.
  int domains() const;
  long separator_rows() const;

 private:
  static bool bisects(const Eigen::SparseMatrix<double>& a, const std::vector<int>& rows, const Options& options,
                      std::vector<int> (&parts)[3]);
  int bisect(const Eigen::SparseMatrix<double>& a, std::vector<int> rows, int levels, const Options& options);
  void number();

  std::vector<Node> nodes_;
  std::vector<int> node_of_, position_;
};

}  // namespace fibrane::solve
