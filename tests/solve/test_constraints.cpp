// DOF numbering and exact constraint elimination: every check is against the defining equations
// u_slave = sum c u_master + value * curve(t) evaluated independently of the elimination code.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "common/error.hpp"
#include "linalg/constraints.hpp"
#include "linalg/dof_map.hpp"

namespace fibrane::solve {
namespace {

TEST(DofMap, NodeMajorNumberingAcrossBlocks) {
  DofMap map;
  const int shell = map.add_block("shell", 4, 3);
  const int beam = map.add_block("beam", 5, 4);
  EXPECT_EQ(map.num_blocks(), 2);
  EXPECT_EQ(map.size(), 4 * 3 + 5 * 4);
  EXPECT_EQ(map.block_offset(beam), 12);
  EXPECT_EQ(map.block_size(beam), 20);
  EXPECT_EQ(map.dofs_per_node(shell), 3);
  EXPECT_EQ(map.block_name(beam), "beam");
  EXPECT_EQ(map.find_block("beam"), beam);
  EXPECT_EQ(map.find_block("none"), -1);
  EXPECT_EQ(map.dof(shell, 2, 1), 2 * 3 + 1);
  EXPECT_EQ(map.dof(beam, 3, 2), 12 + 3 * 4 + 2);
  // The numbering is a bijection onto [0, size).
  std::vector<int> seen(static_cast<size_t>(map.size()), 0);
  for (int b = 0; b < map.num_blocks(); ++b)
    for (int n = 0; n < map.block_size(b) / map.dofs_per_node(b); ++n)
      for (int c = 0; c < map.dofs_per_node(b); ++c) ++seen[static_cast<size_t>(map.dof(b, n, c))];
  for (int count : seen) EXPECT_EQ(count, 1);
  EXPECT_THROW(map.dof(beam, 5, 0), std::out_of_range);
  EXPECT_THROW(map.dof(shell, 0, 3), std::out_of_range);
  EXPECT_THROW(map.add_block("bad", 2, 0), InputError);
}

double curve_value(int curve, double t) { return curve == 3 ? t * t : std::sin(t) + 2.0 * curve; }

// Checks every original constraint on the expanded vector, to round-off (1e-13: a handful of products of
// O(1) numbers).
void expect_constraints_hold(const std::vector<LinearConstraint>& list, const Eigen::VectorXd& u, double t) {
  for (const LinearConstraint& c : list) {
    double rhs = c.value * (c.curve < 0 ? 1.0 : curve_value(c.curve, t));
    for (const auto& [m, coef] : c.masters) rhs += coef * u[m];
    EXPECT_NEAR(u[c.slave], rhs, 1e-13) << "constraint on dof " << c.slave;
  }
}

TEST(ConstraintSet, ChainsAreResolvedAndHoldExactly) {
  // 0,1,2 free-ish; 3 = 2*5 + 1.5 f3(t); 5 = 0.5*0 - 1*1 + 0.25 (5 is a slave used as a master: chain);
  // 6 = 3 + 7 (two-level chain); 4 fixed by a curve; 7 free.
  std::vector<LinearConstraint> list = {
      {3, {{5, 2.0}}, 1.5, 3},
      {5, {{0, 0.5}, {1, -1.0}}, 0.25, -1},
      {6, {{3, 1.0}, {7, 1.0}}, 0.0, -1},
      {4, {}, 2.0, 3},
  };
  ConstraintSet cs;
  for (const auto& c : list) cs.add(c);
  cs.finalize(8);
  EXPECT_EQ(cs.num_free(), 4);  // 0, 1, 2, 7
  EXPECT_EQ(cs.constrained_dofs(), (std::vector<int>{3, 4, 5, 6}));
  EXPECT_TRUE(cs.is_constrained(5));
  EXPECT_FALSE(cs.is_constrained(7));
  // Row of 6 = 3 + 7 = 2*(0.5 u0 - u1 + 0.25) + 1.5 f + u7: free indices 0 (dof 0), 1 (dof 1), 3 (dof 7).
  const auto& row6 = cs.expansion(6);
  ASSERT_EQ(row6.size(), 3u);
  EXPECT_EQ(row6[0], (std::pair<int, double>{0, 1.0}));
  EXPECT_EQ(row6[1], (std::pair<int, double>{1, -2.0}));
  EXPECT_EQ(row6[2], (std::pair<int, double>{3, 1.0}));

  std::mt19937 rng(7);
  std::uniform_real_distribution<double> dist(-1, 1);
  for (double t : {0.0, 0.3, 1.7}) {
    Eigen::VectorXd q(4);
    for (int i = 0; i < 4; ++i) q[i] = dist(rng);
    const Eigen::VectorXd u = cs.expand(q, t, curve_value);
    expect_constraints_hold(list, u, t);
    EXPECT_NEAR(u[4], 2.0 * t * t, 1e-15);       // prescribed value scaled by its curve
    EXPECT_EQ(cs.free_values(u), q);             // free DOFs are copied, so exactly
  }
}

TEST(ConstraintSet, RestrictIsTransposeOfExpansion) {
  ConstraintSet cs;
  cs.add({2, {{0, 0.3}, {4, -0.7}}, 0.1, -1});
  cs.add({4, {{1, 2.0}}, 0.0, -1});
  cs.fix(3, 1.0);
  cs.finalize(6);
  // Dense T from the homogeneous part of expand(): column i = expand(e_i) - expand(0).
  const auto zero_curves = [](int, double) { return 0.0; };
  Eigen::MatrixXd t_dense(6, cs.num_free());
  const Eigen::VectorXd g = cs.expand(Eigen::VectorXd::Zero(cs.num_free()), 0.0, zero_curves);
  for (int i = 0; i < cs.num_free(); ++i)
    t_dense.col(i) = cs.expand(Eigen::VectorXd::Unit(cs.num_free(), i), 0.0, zero_curves) - g;
  EXPECT_DOUBLE_EQ(g[3], 1.0);
  Eigen::VectorXd r(6);
  r << 1.0, -2.0, 3.0, 0.5, 4.0, -1.5;
  const Eigen::VectorXd expected = t_dense.transpose() * r;
  EXPECT_LE((cs.restrict_vector(r) - expected).norm(), 1e-14 * expected.norm());
}

TEST(ConstraintSet, IdenticalDuplicatesAreAccepted) {
  ConstraintSet cs;
  cs.fix(0);          // a corner fixed by two edges
  cs.fix(0, 0.0);
  cs.add({2, {{1, 0.5}}, 0.0, -1});
  cs.add({2, {{1, 0.25}, {1, 0.25}}, 0.0, -1});  // same after merging the repeated master
  EXPECT_NO_THROW(cs.finalize(3));
  EXPECT_EQ(cs.num_free(), 1);
}

// Symmetry ties meeting at a corner: the corner is fixed by one edge, its neighbour is fixed by the other
// edge and tied to the corner by the first. Both constraints on the neighbour say u = 0 once resolved.
TEST(ConstraintSet, DuplicatesThatAgreeAfterResolutionAreAccepted) {
  ConstraintSet cs;
  cs.fix(0);
  cs.add({1, {{0, 1.0}}, 0.0, -1});
  cs.fix(1);
  cs.add({3, {{2, 2.0}}, 1.0, -1});
  cs.add({4, {{2, 1.0}}, 0.0, -1});
  cs.add({3, {{4, 2.0}}, 1.0, -1});  // 2 u4 + 1 = 2 u2 + 1
  EXPECT_NO_THROW(cs.finalize(5));
  EXPECT_EQ(cs.num_free(), 1);
  const Eigen::VectorXd u = cs.expand(Eigen::VectorXd::Constant(1, 0.5), 0.0, [](int, double) { return 1.0; });
  EXPECT_DOUBLE_EQ(u[1], 0.0);
  EXPECT_DOUBLE_EQ(u[3], 2.0);
}

void expect_input_error_naming(ConstraintSet& cs, int n, const std::string& fragment) {
  try {
    cs.finalize(n);
    ADD_FAILURE() << "expected InputError mentioning '" << fragment << "'";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(ConstraintSet, ConflictingDuplicatesAreRejectedWithTheDof) {
  ConstraintSet a;
  a.fix(4, 0.0);
  a.fix(4, 1.0);
  expect_input_error_naming(a, 6, "DOF 4");
  ConstraintSet b;
  b.fix(5, 1.0, 2);
  b.fix(5, 1.0, 3);  // same value, different curve
  expect_input_error_naming(b, 6, "DOF 5");
  ConstraintSet c;
  c.add({1, {{0, 1.0}}, 0.0, -1});
  c.fix(1);
  expect_input_error_naming(c, 6, "DOF 1");
}

TEST(ConstraintSet, CyclesAreRejectedWithTheDofs) {
  ConstraintSet a;
  a.add({0, {{1, 1.0}}, 0.0, -1});
  a.add({1, {{2, 1.0}}, 0.0, -1});
  a.add({2, {{0, 0.5}}, 0.0, -1});
  expect_input_error_naming(a, 3, "cyclic constraints: DOF 0 -> 1 -> 2 -> 0");
  ConstraintSet self;
  self.add({3, {{3, 0.5}}, 0.0, -1});
  expect_input_error_naming(self, 4, "DOF 3");
  ConstraintSet range;
  range.add({1, {{9, 1.0}}, 0.0, -1});
  expect_input_error_naming(range, 4, "DOF 9");
}

TEST(ConstraintSet, UseBeforeFinalizeIsALogicError) {
  ConstraintSet cs;
  cs.fix(0);
  EXPECT_THROW(cs.is_constrained(0), std::logic_error);
}

}  // namespace
}  // namespace fibrane::solve
