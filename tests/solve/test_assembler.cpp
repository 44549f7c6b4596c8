// Reduced assembly against the dense definition K_red = T^T K T, r_red = T^T r, and parallel vs serial.
#include <gtest/gtest.h>

#include <omp.h>

#include <random>

#include "solve/assembler.hpp"
#include "solve/constraints.hpp"

namespace fibrane::solve {
namespace {

struct RandomProblem {
  ConstraintSet constraints;
  std::vector<std::vector<int>> element_dofs;
  std::vector<Eigen::VectorXd> r_local;
  std::vector<Eigen::MatrixXd> k_local;  // deliberately unsymmetric: the assembler must not assume symmetry
};

// n_dofs DOFs, elements of `per_element` distinct random DOFs, every 7th DOF fixed (some by a curve),
// every 11th a slave of two masters, one of them DOF 5 which is itself a slave.
RandomProblem make_problem(int n_dofs, int n_elements, int per_element, unsigned seed) {
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

Eigen::MatrixXd dense_t(const ConstraintSet& cs) {
  Eigen::MatrixXd t = Eigen::MatrixXd::Zero(cs.num_dofs(), cs.num_free());
  for (int d = 0; d < cs.num_dofs(); ++d)
    for (const auto& [i, c] : cs.expansion(d)) t(d, i) += c;
  return t;
}

void assemble(SparseAssembler& a, const RandomProblem& p, bool parallel) {
  a.begin(true);
  const int n = static_cast<int>(p.element_dofs.size());
#pragma omp parallel for schedule(dynamic, 4) if (parallel)
  for (int e = 0; e < n; ++e) a.add(e, p.r_local[static_cast<size_t>(e)], &p.k_local[static_cast<size_t>(e)]);
  a.end();
}

TEST(SparseAssembler, ReducedSystemEqualsDenseTransformation) {
  const RandomProblem p = make_problem(60, 40, 6, 1);
  SparseAssembler a;
  a.set_pattern(p.constraints, p.element_dofs);
  assemble(a, p, false);
  // Dense reference: full K and r, then T^T K T and T^T r.
  Eigen::MatrixXd k_full = Eigen::MatrixXd::Zero(60, 60);
  Eigen::VectorXd r_full = Eigen::VectorXd::Zero(60);
  for (size_t e = 0; e < p.element_dofs.size(); ++e)
    for (size_t i = 0; i < p.element_dofs[e].size(); ++i) {
      r_full[p.element_dofs[e][i]] += p.r_local[e][static_cast<Eigen::Index>(i)];
      for (size_t j = 0; j < p.element_dofs[e].size(); ++j)
        k_full(p.element_dofs[e][i], p.element_dofs[e][j]) +=
            p.k_local[e](static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
    }
  const Eigen::MatrixXd t = dense_t(p.constraints);
  ASSERT_GT((t.array() != 0.0 && t.array() != 1.0).count(), 5) << "problem should contain real MPCs";
  const Eigen::MatrixXd k_red = t.transpose() * k_full * t;
  // Same sums in a different order: agreement to 1e-13 relative to the largest entry (entries are O(10)).
  EXPECT_LE((Eigen::MatrixXd(a.matrix()) - k_red).cwiseAbs().maxCoeff(), 1e-13 * k_red.cwiseAbs().maxCoeff());
  EXPECT_LE((a.full_residual() - r_full).cwiseAbs().maxCoeff(), 1e-14 * r_full.cwiseAbs().maxCoeff());
  const Eigen::VectorXd r_red = t.transpose() * r_full;
  EXPECT_LE((a.reduced_residual() - r_red).cwiseAbs().maxCoeff(), 1e-13 * r_red.cwiseAbs().maxCoeff());
}

TEST(SparseAssembler, ParallelEqualsSerialForBothStrategies) {
  const RandomProblem p = make_problem(3000, 4000, 12, 2);
  SparseAssembler serial;
  serial.set_pattern(p.constraints, p.element_dofs);
  assemble(serial, p, false);
  const Eigen::SparseMatrix<double> k_serial = serial.matrix();
  const Eigen::VectorXd r_serial = serial.full_residual();
  for (auto strategy : {SparseAssembler::Strategy::ThreadBuffers, SparseAssembler::Strategy::Atomic}) {
    omp_set_num_threads(2);
    SparseAssembler par;
    par.set_strategy(strategy);
    par.set_pattern(p.constraints, p.element_dofs);
    for (int repeat = 0; repeat < 2; ++repeat) {  // second pass checks that begin() really zeroes buffers
      assemble(par, p, true);
      // Only the summation order differs: 1e-14 relative to the largest entry.
      const double kmax = Eigen::Map<const Eigen::VectorXd>(k_serial.valuePtr(), k_serial.nonZeros()).cwiseAbs().maxCoeff();
      ASSERT_EQ(par.matrix().nonZeros(), k_serial.nonZeros());  // same pattern -> compare value arrays
      const Eigen::Map<const Eigen::VectorXd> v_par(par.matrix().valuePtr(), k_serial.nonZeros());
      const Eigen::Map<const Eigen::VectorXd> v_serial(k_serial.valuePtr(), k_serial.nonZeros());
      EXPECT_LE((v_par - v_serial).cwiseAbs().maxCoeff(), 1e-14 * kmax);
      EXPECT_LE((par.full_residual() - r_serial).cwiseAbs().maxCoeff(), 1e-14 * r_serial.cwiseAbs().maxCoeff());
      EXPECT_LE((par.reduced_residual() - serial.reduced_residual()).cwiseAbs().maxCoeff(),
                1e-14 * serial.reduced_residual().cwiseAbs().maxCoeff());
    }
  }
}

TEST(SparseAssembler, ResidualOnlyPassAndPointLoads) {
  const RandomProblem p = make_problem(40, 20, 5, 3);
  SparseAssembler a;
  a.set_pattern(p.constraints, p.element_dofs);
  const int v0 = a.pattern_version();
  assemble(a, p, false);
  const Eigen::SparseMatrix<double> k_before = a.matrix();
  a.begin(false);
  for (int e = 0; e < 20; ++e) a.add(e, p.r_local[static_cast<size_t>(e)], &p.k_local[static_cast<size_t>(e)]);
  const int point_dofs[2] = {3, 8};  // 3 is fixed: the load only shows up in the full residual
  a.add_vector(point_dofs, Eigen::Vector2d(10.0, -20.0));
  a.end();
  EXPECT_EQ((a.matrix() - k_before).norm(), 0.0);  // matrix untouched by a residual-only pass
  Eigen::VectorXd r_full = Eigen::VectorXd::Zero(40);
  for (size_t e = 0; e < p.element_dofs.size(); ++e)
    for (size_t i = 0; i < p.element_dofs[e].size(); ++i)
      r_full[p.element_dofs[e][i]] += p.r_local[e][static_cast<Eigen::Index>(i)];
  r_full[3] += 10.0;
  r_full[8] -= 20.0;
  EXPECT_LE((a.full_residual() - r_full).cwiseAbs().maxCoeff(), 1e-13);
  EXPECT_LE((a.reduced_residual() - dense_t(p.constraints).transpose() * r_full).cwiseAbs().maxCoeff(), 1e-12);
  a.set_pattern(p.constraints, p.element_dofs);
  EXPECT_GT(a.pattern_version(), v0);
}

}  // namespace
}  // namespace fibrane::solve
