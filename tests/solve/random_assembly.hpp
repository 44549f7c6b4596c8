#pragma once
// Random assembly problems for the SparseAssembler tests: constraints with fixes, prescribed values and
// chained multi-point constraints, elements of random DOFs with unsymmetric element matrices.
#include <algorithm>
#include <random>
#include <vector>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "linalg/assembler.hpp"
#include "linalg/constraints.hpp"

namespace fibrane::solve {

struct RandomProblem {
  ConstraintSet constraints;
  std::vector<std::vector<int>> element_dofs;
  std::vector<Eigen::VectorXd> r_local;
  std::vector<Eigen::MatrixXd> k_local;  // deliberately unsymmetric: the assembler must not assume symmetry
};

// n_dofs DOFs, elements of `per_element` distinct random DOFs, every 7th DOF fixed (some by a curve),
// every 11th a slave of two masters, one of them DOF 5 which is itself a slave.
inline RandomProblem make_problem(int n_dofs, int n_elements, int per_element, unsigned seed) {
  RandomProblem p;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> value(-1, 1);
  for (int d = 3; d < n_dofs; d += 7) p.constraints.fix(d, value(rng), d % 2 ? 0 : -1);
  for (int d = 4; d < n_dofs; d += 11) {
    if (d % 7 == 3) continue;  // already fixed
    // Master 5 is itself a slave (chain); master d + 1 may be a fixed DOF (chain to a prescribed value).
    p.constraints.add({d, {{5, value(rng)}, {(d + 1) % n_dofs, value(rng)}}, value(rng), -1});
  }
  p.constraints.add({5, {{1, 0.5}, {2, -0.25}}, 0.0, -1});
  p.constraints.finalize(n_dofs);
  std::uniform_int_distribution<int> pick(0, n_dofs - 1);
  for (int e = 0; e < n_elements; ++e) {
    std::vector<int> dofs;
    while (static_cast<int>(dofs.size()) < per_element) {
      const int d = pick(rng);
      if (std::find(dofs.begin(), dofs.end(), d) == dofs.end()) dofs.push_back(d);
    }
    p.element_dofs.push_back(dofs);
    p.r_local.push_back(Eigen::VectorXd::NullaryExpr(per_element, [&] { return value(rng); }));
    p.k_local.push_back(Eigen::MatrixXd::NullaryExpr(per_element, per_element, [&] { return value(rng); }));
  }
  return p;
}

// `a` and the serial assembler `serial` (ended, same pattern) hold the same matrix values and full and
// reduced residuals; only the summation order differs: 1e-14 relative to the largest entry.
inline void expect_same_sums(const SparseAssembler& a, const SparseAssembler& serial) {
  const Eigen::Map<const Eigen::VectorXd> v(a.matrix().valuePtr(), a.matrix().nonZeros());
  const Eigen::Map<const Eigen::VectorXd> v_serial(serial.matrix().valuePtr(), serial.matrix().nonZeros());
  ASSERT_EQ(v.size(), v_serial.size());
  EXPECT_LE((v - v_serial).cwiseAbs().maxCoeff(), 1e-14 * v_serial.cwiseAbs().maxCoeff());
  EXPECT_LE((a.full_residual() - serial.full_residual()).cwiseAbs().maxCoeff(),
            1e-14 * serial.full_residual().cwiseAbs().maxCoeff());
  EXPECT_LE((a.reduced_residual() - serial.reduced_residual()).cwiseAbs().maxCoeff(),
            1e-14 * serial.reduced_residual().cwiseAbs().maxCoeff());
}

inline Eigen::MatrixXd dense_t(const ConstraintSet& cs) {
  Eigen::MatrixXd t = Eigen::MatrixXd::Zero(cs.num_dofs(), cs.num_free());
  for (int d = 0; d < cs.num_dofs(); ++d)
    for (const auto& [i, c] : cs.expansion(d)) t(d, i) += c;
  return t;
}

}  // namespace fibrane::solve
