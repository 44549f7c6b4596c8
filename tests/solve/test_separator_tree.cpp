// Nested dissection (SeparatorTree) and the split Cholesky on more than two domains
// (make_cholmod_split_llt with levels 2 and 3): the tree divides the graph and its boundaries are the
// fronts' row sets; the solutions are the whole factorisation's to round-off.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "grid_matrix.hpp"
#include "linalg/cholmod_split.hpp"
#include "linalg/direct_solvers.hpp"
#include "linalg/linear_solver.hpp"
#include "linalg/separator_tree.hpp"

namespace fibrane::solve {
namespace {

using SpMat = Eigen::SparseMatrix<double>;

// 10 000 unknowns: three levels leave domains of ~1 200 rows. SPD with condition ~ 5 (grid_matrix).
SpMat spd(unsigned seed) { return grid_matrix(100, 2.0, 0.0, 0.3, seed); }

// The rows of node t's subtree.
std::set<int> subtree_rows(const SeparatorTree& tree, int t) {
  std::set<int> rows;
  for (int k = tree.nodes()[static_cast<std::size_t>(t)].first; k <= t; ++k)
    rows.insert(tree.nodes()[static_cast<std::size_t>(k)].rows.begin(), tree.nodes()[static_cast<std::size_t>(k)].rows.end());
  return rows;
}

// The tree divides a's graph, numbers the rows by a permutation, and gives every node its boundary.
void expect_tree_of(const SpMat& a, const SeparatorTree& tree) {
  EXPECT_TRUE(tree.divides(a));
  // every row in one node; positions a permutation
  std::vector<int> positions;
  for (int r = 0; r < a.rows(); ++r) positions.push_back(tree.position(r));
  std::sort(positions.begin(), positions.end());
  for (int r = 0; r < a.rows(); ++r) ASSERT_EQ(positions[static_cast<std::size_t>(r)], r);
  // The boundary of every node is exactly the set of rows outside its subtree that an entry joins to a
  // row inside it (the rows its subtree's elimination couples), and those are rows of its ancestors.
  for (int t = 0; t < static_cast<int>(tree.nodes().size()); ++t) {
    const std::set<int> inside = subtree_rows(tree, t);
    std::set<int> expected;
    for (int j = 0; j < a.cols(); ++j)
      for (SpMat::InnerIterator it(a, j); it; ++it)
        if (inside.count(j) && !inside.count(static_cast<int>(it.row()))) expected.insert(static_cast<int>(it.row()));
    const std::vector<int>& boundary = tree.nodes()[static_cast<std::size_t>(t)].boundary;
    EXPECT_EQ(std::set<int>(boundary.begin(), boundary.end()), expected) << "node " << t;
    EXPECT_TRUE(std::is_sorted(boundary.begin(), boundary.end(),
                               [&](int x, int y) { return tree.position(x) < tree.position(y); }));
    for (const int r : boundary) EXPECT_TRUE(tree.above(tree.node_of(r), t));
  }
  // postorder: a node's subtree is [first, node], its children's subtrees within it
  for (int t = 0; t < static_cast<int>(tree.nodes().size()); ++t) {
    const SeparatorTree::Node& node = tree.nodes()[static_cast<std::size_t>(t)];
    if (node.domain()) {
      EXPECT_EQ(node.first, t);
      EXPECT_EQ(node.height, 0);
      continue;
    }
    const SeparatorTree::Node& c0 = tree.nodes()[static_cast<std::size_t>(node.children[0])];
    EXPECT_EQ(node.children[1], t - 1);
    EXPECT_EQ(node.children[0] + 1, tree.nodes()[static_cast<std::size_t>(t - 1)].first);
    EXPECT_EQ(node.first, c0.first);
    EXPECT_EQ(c0.parent, t);
    EXPECT_EQ(tree.nodes()[static_cast<std::size_t>(t - 1)].parent, t);
    EXPECT_EQ(node.height, 1 + std::max(c0.height, tree.nodes()[static_cast<std::size_t>(t - 1)].height));
  }
}

TEST(SeparatorTree, DividesTheGraphAndBoundsEachSubtree) {
  const SpMat a = spd(1);
  SeparatorTree tree;
  ASSERT_TRUE(tree.build(a, {.levels = 3, .min_rows = 1000, .max_separator = 5000}));
  EXPECT_EQ(tree.domains(), 8);
  EXPECT_EQ(tree.nodes().size(), 15u);
  expect_tree_of(a, tree);
  // an entry joining two domains of different halves no longer fits the tree
  const auto& nodes = tree.nodes();
  const int first = nodes.front().rows.front(), last = nodes[nodes.size() - 2].rows.front();
  SpMat joined = a;
  joined.coeffRef(first, last) = joined.coeffRef(last, first) = -0.01;
  joined.makeCompressed();
  EXPECT_FALSE(tree.divides(joined));
}

// A domain bisected once more: two domains and a separator in its place, the nodes after it renumbered.
TEST(SeparatorTree, ADomainBisectedAgain) {
  const SpMat a = spd(1);
  const SeparatorTree::Options options{.levels = 2, .min_rows = 1000, .max_separator = 5000};
  SeparatorTree tree;
  ASSERT_TRUE(tree.build(a, options));
  ASSERT_EQ(tree.nodes().size(), 7u);
  const std::vector<int> third = tree.nodes()[3].rows;  // the second subtree's first domain
  ASSERT_TRUE(tree.nodes()[3].domain());
  const std::vector<SeparatorTree::Node> before = tree.nodes();
  const SeparatorTree::Options too_small{.levels = 2, .min_rows = 10'000, .max_separator = 5000};
  EXPECT_FALSE(tree.refine(a, 3, too_small));  // a piece below min_rows: the tree as it was
  ASSERT_EQ(tree.nodes().size(), 7u);
  EXPECT_EQ(tree.nodes()[3].rows, third);
  ASSERT_TRUE(tree.refine(a, 3, options));
  ASSERT_EQ(tree.nodes().size(), 9u);
  EXPECT_EQ(tree.domains(), 5);
  const auto& nodes = tree.nodes();
  EXPECT_FALSE(nodes[5].domain());
  std::vector<int> rows = nodes[3].rows;  // the two parts and their separator hold the domain's rows
  rows.insert(rows.end(), nodes[4].rows.begin(), nodes[4].rows.end());
  rows.insert(rows.end(), nodes[5].rows.begin(), nodes[5].rows.end());
  std::sort(rows.begin(), rows.end());
  EXPECT_EQ(rows, third);
  EXPECT_EQ(nodes[8].height, 3);
  expect_tree_of(a, tree);
  // the nodes outside the refined domain keep their rows and boundaries (the split solver reuses their
  // domains' analyses): 0-2 where they were, 4-6 two places on
  for (const auto& [old_node, new_node] : {std::pair{0, 0}, {1, 1}, {2, 2}, {4, 6}, {5, 7}, {6, 8}}) {
    EXPECT_EQ(nodes[static_cast<std::size_t>(new_node)].rows, before[static_cast<std::size_t>(old_node)].rows) << old_node;
    EXPECT_EQ(nodes[static_cast<std::size_t>(new_node)].boundary, before[static_cast<std::size_t>(old_node)].boundary) << old_node;
  }
  EXPECT_FALSE(tree.refine(a, 5, options));  // a separator
  EXPECT_FALSE(tree.refine(a, 9, options));  // no such node
  // the first domain, and one of the new halves again
  ASSERT_TRUE(tree.refine(a, 0, options));
  EXPECT_EQ(tree.domains(), 6);
  expect_tree_of(a, tree);
  ASSERT_TRUE(tree.refine(a, 6, options));  // the second half of the domain refined above (4, two places on)
  EXPECT_EQ(tree.domains(), 7);
  expect_tree_of(a, tree);
  EXPECT_EQ(tree.nodes().back().parent, -1);
}

// The split solver with `levels` levels for matrices from 1 000 unknowns on, with `threads` threads.
std::unique_ptr<LinearSolver> split_solver(int levels, int threads) {
  omp_set_num_threads(threads);
  return make_cholmod_split_llt({.memory_limit_megabytes = kAvailableMemory, .min_unknowns = 1000,
                                 .max_separator = 5000, .max_work_share = 0.75, .levels = levels});
}

Eigen::MatrixXd whole_solve(const SpMat& a, const Eigen::MatrixXd& b) {
  auto whole = make_cholmod_llt();
  whole->analyze(a);
  EXPECT_TRUE(whole->factorize(a));
  return whole->solve_columns(b);
}

double relative(const Eigen::MatrixXd& x, const Eigen::MatrixXd& ref) { return (x - ref).norm() / ref.norm(); }

class SplitLevels : public ::testing::TestWithParam<int> {};

TEST_P(SplitLevels, SolvesAsTheWholeFactorisation) {
  const int levels = GetParam();
  const SpMat a = spd(1), a2 = spd(2);
  auto solver = split_solver(levels, 4);
  solver->analyze(a);
  EXPECT_EQ(cholmod_split_domains(*solver), 1 << levels) << solver->analysis_summary();
  ASSERT_TRUE(solver->factorize(a));
  EXPECT_EQ(solver->negative_eigenvalues(), 0);
  Eigen::MatrixXd b(a.rows(), 3);
  b << Eigen::VectorXd::LinSpaced(a.rows(), -1.0, 2.0), Eigen::VectorXd::Ones(a.rows()),
      Eigen::VectorXd::LinSpaced(a.rows(), 3.0, 0.5).array().sin().matrix();
  // condition ~5: the two factorisations' solutions agree to a few ulps times that
  const Eigen::MatrixXd x = solver->solve_columns(b);
  EXPECT_LT(relative(x, whole_solve(a, b)), 1e-14);
  EXPECT_LT(relative(solver->solve(b.col(0)), whole_solve(a, b.col(0))), 1e-14);
  EXPECT_LT((a * x - b).norm(), 1e-13 * b.norm());
  // new values of the pattern, after the factor was handed back
  solver->release_factor();
  EXPECT_EQ(solver->held_factor_entries(), 0);
  ASSERT_TRUE(solver->factorize(a2));
  EXPECT_EQ(solver->held_factor_entries(), solver->factor_nonzeros());
  const Eigen::MatrixXd ref2 = whole_solve(a2, b);
  EXPECT_LT(relative(solver->solve_columns(b), ref2), 1e-14);
  EXPECT_GT(relative(ref2, x), 1e-6);  // the values did change the solution
}

TEST_P(SplitLevels, ThePivotOrderIsAPermutation) {
  auto solver = split_solver(GetParam(), 2);
  const SpMat a = spd(1);
  solver->analyze(a);
  std::vector<int> order = cholmod_pivot_order(*solver);
  ASSERT_EQ(order.size(), static_cast<std::size_t>(a.rows()));
  std::sort(order.begin(), order.end());
  for (int r = 0; r < a.rows(); ++r) ASSERT_EQ(order[static_cast<std::size_t>(r)], r);
}

// An indefinite matrix (1 114 of its 10 000 eigenvalues negative): where CHOLMOD's LL^T finds a domain not
// positive definite, MUMPS's LDL^T factorises it with its boundary as Schur complement, and fronts that
// are indefinite take LAPACK's LDL^T. The inertia is the matrix's, the solution MUMPS's whole LDL^T's. The
// eigenvalue nearest 0 is 2.6e-4, the largest 6.7: condition 2.5e4. The residual is held to 1e-10 of |b|
// (eps times the condition is 2.8e-12; threshold pivoting may take other pivots from one run to the next,
// as the domains' round-off differs with the BLAS threads they get: 5e-13 to 1.1e-11 measured), and the two
// solutions, which the condition bounds by 2.5e4 times their residuals, to 1e-8.
TEST_P(SplitLevels, AnIndefiniteMatrixIsFactorisedByLdlt) {
  auto solver = split_solver(GetParam(), 4);
  const SpMat a = grid_matrix(100, -1.3, 0.0);
  solver->analyze(a);
  ASSERT_GT(cholmod_split_domains(*solver), 0);
  if (!mumps_available()) {
    EXPECT_FALSE(solver->factorize(a));
    EXPECT_EQ(solver->negative_eigenvalues(), -1);
    GTEST_SKIP() << "built without MUMPS: an indefinite matrix is refused";
  }
  ASSERT_TRUE(solver->factorize(a)) << solver->analysis_summary();
  const int expected = grid_negative_eigenvalues(100, -1.3);
  ASSERT_EQ(expected, 1114);
  EXPECT_EQ(solver->negative_eigenvalues(), expected);
  auto whole = make_mumps();
  whole->analyze(a);
  ASSERT_TRUE(whole->factorize(a));
  EXPECT_EQ(whole->negative_eigenvalues(), expected);
  Eigen::MatrixXd b(a.rows(), 2);
  b << Eigen::VectorXd::LinSpaced(a.rows(), -1.0, 2.0), Eigen::VectorXd::Ones(a.rows());
  const Eigen::MatrixXd x = solver->solve_columns(b);
  EXPECT_LT((a * x - b).norm(), 1e-10 * b.norm());
  EXPECT_LT(relative(x, whole->solve_columns(b)), 1e-8);
  EXPECT_LT(relative(solver->solve(b.col(1)), x.col(1)), 1e-8);  // MUMPS blocks several columns otherwise
  // positive definite again, the same pattern: the indefinite domains try the LDL^T first once, find their
  // K_DD positive definite, and the next factorisation is LL^T everywhere, with MUMPS's factors freed
  const SpMat positive = grid_matrix(100, 0.1, 0.0);
  ASSERT_TRUE(solver->factorize(positive));
  EXPECT_EQ(solver->negative_eigenvalues(), 0);
  ASSERT_TRUE(solver->factorize(positive));
  EXPECT_EQ(solver->negative_eigenvalues(), 0);
  EXPECT_EQ(solver->held_factor_entries(), solver->factor_nonzeros());
  EXPECT_LT(relative(solver->solve_columns(b), whole_solve(positive, b)), 1e-13);
}

INSTANTIATE_TEST_SUITE_P(Levels, SplitLevels, ::testing::Values(1, 2, 3));

// The solver's account (linear_solver_statistics) says where it took the LDL^T: a matrix indefinite
// everywhere in the domains; one whose separator's diagonal is lowered just until the whole matrix is
// indefinite (the whole CHOLMOD factorisation tells) in the separator's front only, the domains (each with
// the separator's rows) staying positive definite. The inertia is MUMPS's whole LDL^T's.
TEST(SplitLevels, TheAccountSaysWhereTheMatrixWasIndefinite) {
  if (!mumps_available()) GTEST_SKIP() << "built without MUMPS";
  auto solver = split_solver(1, 2);
  const SpMat a = grid_matrix(100, 0.01, 0.0);
  solver->analyze(a);
  ASSERT_EQ(cholmod_split_domains(*solver), 2);
  ASSERT_TRUE(solver->factorize(grid_matrix(100, -1.3, 0.0)));
  EXPECT_NE(solver->analysis_summary().find("LDL^T where not positive definite: 2 in a domain"), std::string::npos)
      << solver->analysis_summary();
  const std::vector<int> order = cholmod_pivot_order(*solver);
  const long s = cholmod_split_separator(*solver);
  auto whole = make_cholmod_llt();
  whole->analyze(a);
  for (double lowered = 0.0; lowered < 4.0; lowered += 0.005) {
    SpMat b = a;
    for (auto k = order.size() - static_cast<std::size_t>(s); k < order.size(); ++k) b.coeffRef(order[k], order[k]) -= lowered;
    if (whole->factorize(b)) continue;
    auto fresh = split_solver(1, 2);
    fresh->analyze(b);
    ASSERT_TRUE(fresh->factorize(b));
    EXPECT_NE(fresh->analysis_summary().find("LDL^T where not positive definite: 0 in a domain, 1 in a front; failed: 0"),
              std::string::npos)
        << fresh->analysis_summary() << " (separator's diagonal lowered by " << lowered << ")";
    auto mumps = make_mumps();
    mumps->analyze(b);
    ASSERT_TRUE(mumps->factorize(b));
    EXPECT_EQ(fresh->negative_eigenvalues(), mumps->negative_eigenvalues());
    EXPECT_GT(fresh->negative_eigenvalues(), 0);
    return;
  }
  FAIL() << "the matrix stayed positive definite";
}

// With many threads and few fronts of a height (two fronts at height 1 of 4 domains on 16 threads), the
// fronts are factorised one after the other on all BLAS threads instead of side by side: the same solution.
TEST(SplitLevels, FewFrontsOnManyThreadsSolveAsTheWholeFactorisation) {
  const SpMat a = spd(3);
  auto solver = split_solver(2, 16);
  solver->analyze(a);
  ASSERT_EQ(cholmod_split_domains(*solver), 4);
  ASSERT_TRUE(solver->factorize(a));
  const Eigen::MatrixXd b = Eigen::VectorXd::LinSpaced(a.rows(), -2.0, 1.0);
  EXPECT_LT(relative(solver->solve_columns(b), whole_solve(a, b)), 1e-14);
  omp_set_num_threads(2);
}

TEST(SplitLevels, TheThreadsSetTheDomains) {
  const SpMat a = spd(1);
  for (const auto& [threads, domains] : {std::pair{2, 2}, {3, 4}, {4, 4}, {8, 8}}) {
    auto solver = split_solver(0, threads);
    solver->analyze(a);
    EXPECT_EQ(cholmod_split_domains(*solver), domains) << threads << " threads";
  }
}

// spd(1) with the rows of its grid's 16 x 16 corner joined to each other (-1e-4 apiece: still diagonally
// dominant), a dense block whose elimination holds most of the flops of the domain it lies in: two halves
// of 11.6 and 6.2 MFlop (65 %, where the split still serves: below 75 %), four domains of 16.2 MFlop with
// the largest 9.0 (more than twice an even share on 4 threads, 8.1). A larger block leaves the two halves
// beyond 75 %.
SpMat with_dense_corner() {
  SpMat a = spd(1);
  std::vector<int> corner;
  for (int i = 0; i < 16; ++i)
    for (int j = 0; j < 16; ++j) corner.push_back(i * 100 + j);
  for (const int r : corner)
    for (const int c : corner)
      if (r != c && a.coeff(r, c) == 0.0) a.coeffRef(r, c) = -1e-4;
  a.makeCompressed();
  return a;
}

// With the depth from the threads (levels 0), a domain with more than twice an even share of the domains'
// flops is bisected again: on 4 threads the corner's domain, so that there are 5 domains (the largest then
// 6.6 of 15.4 MFlop), and the solution is still the whole factorisation's. On 2 threads no domain can hold
// twice an even share; a depth given keeps its tree.
TEST(SplitLevels, AHeavyDomainIsBisectedAgain) {
  const SpMat a = with_dense_corner();
  auto two = split_solver(0, 2);
  two->analyze(a);
  EXPECT_EQ(cholmod_split_domains(*two), 2) << two->analysis_summary();
  auto fixed = split_solver(2, 4);  // a depth given: the tree as it is
  fixed->analyze(a);
  EXPECT_EQ(cholmod_split_domains(*fixed), 4) << fixed->analysis_summary();
  auto solver = split_solver(0, 4);
  solver->analyze(a);
  EXPECT_EQ(cholmod_split_domains(*solver), 5) << solver->analysis_summary();
  EXPECT_EQ(cholmod_split_kept_analyses(*solver).second, 6);  // 4, then the two new domains alone
  ASSERT_TRUE(solver->factorize(a));
  const Eigen::MatrixXd b = Eigen::VectorXd::LinSpaced(a.rows(), -2.0, 1.0);
  EXPECT_LT(relative(solver->solve_columns(b), whole_solve(a, b)), 1e-14);
  std::vector<int> order = cholmod_pivot_order(*solver);
  std::sort(order.begin(), order.end());
  for (int r = 0; r < a.rows(); ++r) ASSERT_EQ(order[static_cast<std::size_t>(r)], r);
  omp_set_num_threads(2);
}

// The last place where two pivot orders differ (-1 where they are equal).
long last_difference(const std::vector<int>& x, const std::vector<int>& y) {
  for (auto k = static_cast<long>(x.size()) - 1; k >= 0; --k)
    if (x[static_cast<std::size_t>(k)] != y[static_cast<std::size_t>(k)]) return k;
  return -1;
}

TEST(SplitLevels, ANewPatternWithinADomainKeepsTheTree) {
  auto solver = split_solver(2, 4);
  const SpMat a = spd(1);
  solver->analyze(a);
  const std::vector<int> order = cholmod_pivot_order(*solver);
  const auto quarter = static_cast<long>(order.size() / 4);
  // an entry between the first domain's first two pivots
  SpMat within = a;
  within.coeffRef(order[0], order[1]) = within.coeffRef(order[1], order[0]) = -0.05;
  within.makeCompressed();
  // a fresh solver divides the new pattern otherwise: its order differs beyond the first domain
  auto fresh = split_solver(2, 4);
  fresh->analyze(within);
  ASSERT_GT(last_difference(cholmod_pivot_order(*fresh), order), quarter);
  // the kept tree: only the first domain (the first pivots, less than a quarter) is ordered anew
  solver->analyze(within);
  const std::vector<int> kept = cholmod_pivot_order(*solver);
  const long last = last_difference(kept, order);
  EXPECT_LT(last, quarter);
  EXPECT_EQ(std::set<int>(kept.begin(), kept.begin() + last + 1), std::set<int>(order.begin(), order.begin() + last + 1));
  ASSERT_TRUE(solver->factorize(within));
  const Eigen::MatrixXd b = Eigen::VectorXd::LinSpaced(a.rows(), 1.0, -1.0);
  EXPECT_LT(relative(solver->solve_columns(b), whole_solve(within, b)), 1e-14);
}

}  // namespace
}  // namespace fibrane::solve
