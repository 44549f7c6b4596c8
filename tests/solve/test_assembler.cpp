// Reduced assembly against the dense definition K_red = T^T K T, r_red = T^T r, and parallel vs serial.
#include <gtest/gtest.h>

#include <omp.h>

#include "linalg/assembler.hpp"
#include "random_assembly.hpp"

namespace fibrane::solve {
namespace {

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

TEST(SparseAssembler, ParallelEqualsSerialForEveryStrategy) {
  const RandomProblem p = make_problem(3000, 4000, 12, 2);
  SparseAssembler serial;
  serial.set_pattern(p.constraints, p.element_dofs);
  assemble(serial, p, false);
  const Eigen::SparseMatrix<double> k_serial = serial.matrix();
  const Eigen::VectorXd r_serial = serial.full_residual();
  for (auto strategy : {SparseAssembler::Strategy::Colours, SparseAssembler::Strategy::ThreadBuffers,
                        SparseAssembler::Strategy::Atomic}) {
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

// Callers in a nested parallel region have no buffer of their own: they add atomically into the overflow
// buffer, whose matrix copy is made by its first caller and resized after a pattern change.
TEST(SparseAssembler, NestedCallersUseTheOverflowBuffer) {
  SparseAssembler nested;
  for (unsigned seed : {3u, 4u}) {  // the second pattern has another size
    const RandomProblem p = make_problem(seed == 3 ? 500 : 700, 600, 8, seed);
    SparseAssembler serial;
    serial.set_pattern(p.constraints, p.element_dofs);
    nested.set_pattern(p.constraints, p.element_dofs);
    assemble(serial, p, false);
    const int n = static_cast<int>(p.element_dofs.size());
    for (int repeat = 0; repeat < 2; ++repeat) {  // the second pass finds the overflow copy zeroed
      nested.begin(true);
#pragma omp parallel num_threads(2)
      {
        const int half = omp_get_thread_num();
#pragma omp parallel for num_threads(2)
        for (int e = half; e < n; e += 2) {
          EXPECT_GE(omp_get_level(), 2);
          nested.add(e, p.r_local[static_cast<size_t>(e)], &p.k_local[static_cast<size_t>(e)]);
        }
      }
      nested.end();
      expect_same_sums(nested, serial);
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

// The dense reduced matrix of elements [begin, end) of p, in the assembler's numbering from `first_id`.
Eigen::MatrixXd dense_reduced(const RandomProblem& p, size_t begin, size_t end) {
  const int n = p.constraints.num_dofs();
  Eigen::MatrixXd k_full = Eigen::MatrixXd::Zero(n, n);
  for (size_t e = begin; e < end; ++e)
    for (size_t i = 0; i < p.element_dofs[e].size(); ++i)
      for (size_t j = 0; j < p.element_dofs[e].size(); ++j)
        k_full(p.element_dofs[e][i], p.element_dofs[e][j]) +=
            p.k_local[e](static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
  const Eigen::MatrixXd t = dense_t(p.constraints);
  return t.transpose() * k_full * t;
}

// Fixed elements [0, n_fixed), then two different sets of variable elements in turn (the second
// replacement moves the fixed positions a second time). Each state must equal the dense definition, and
// the pattern must hold exactly the entries the elements touch (no stale entries of the first set).
TEST(SparseAssembler, VariableElementsReplaceOnlyTheirPart) {
  const RandomProblem p = make_problem(200, 90, 7, 4);
  const size_t n_fixed = 50;
  const std::vector<std::vector<int>> fixed(p.element_dofs.begin(), p.element_dofs.begin() + n_fixed);
  SparseAssembler a;
  a.set_pattern(p.constraints, fixed);
  const size_t sets[][2] = {{50, 70}, {70, 90}, {50, 90}};
  int version = a.pattern_version();
  for (const auto& [begin, end] : sets) {
    a.set_variable_elements({p.element_dofs.begin() + begin, p.element_dofs.begin() + end});
    EXPECT_GT(a.pattern_version(), version);
    version = a.pattern_version();
    ASSERT_EQ(a.num_elements(), static_cast<int>(n_fixed + end - begin));
    for (int pass = 0; pass < 2; ++pass) {  // both threads: the buffers' sizes follow the pattern
      a.begin(true);
#pragma omp parallel for schedule(dynamic, 3) num_threads(2)
      for (int e = 0; e < a.num_elements(); ++e) {
        const size_t source = static_cast<size_t>(e) < n_fixed ? static_cast<size_t>(e) : begin + e - n_fixed;
        a.add(e, p.r_local[source], &p.k_local[source]);
      }
      a.end();
    }
    Eigen::MatrixXd expected = dense_reduced(p, 0, n_fixed) + dense_reduced(p, begin, end);
    const Eigen::MatrixXd assembled(a.matrix());
    EXPECT_LE((assembled - expected).cwiseAbs().maxCoeff(), 1e-13 * expected.cwiseAbs().maxCoeff());
    // The same elements all fixed give the same pattern.
    SparseAssembler all;
    std::vector<std::vector<int>> together = fixed;
    together.insert(together.end(), p.element_dofs.begin() + begin, p.element_dofs.begin() + end);
    all.set_pattern(p.constraints, together);
    EXPECT_EQ(all.matrix().nonZeros(), a.matrix().nonZeros());
    EXPECT_TRUE(std::equal(all.matrix().innerIndexPtr(), all.matrix().innerIndexPtr() + all.matrix().nonZeros(),
                           a.matrix().innerIndexPtr()));
  }
}

// A sub-block add equals the whole element's add with the other rows and columns zero.
TEST(SparseAssembler, SubBlockAddEqualsMaskedElement) {
  const RandomProblem p = make_problem(80, 12, 9, 5);
  SparseAssembler whole, part;
  whole.set_pattern(p.constraints, {p.element_dofs.begin(), p.element_dofs.begin() + 6});
  part.set_pattern(p.constraints, {p.element_dofs.begin(), p.element_dofs.begin() + 6});
  whole.set_variable_elements({p.element_dofs.begin() + 6, p.element_dofs.end()});
  part.set_variable_elements({p.element_dofs.begin() + 6, p.element_dofs.end()});
  const std::vector<int> local{7, 2, 5, 0};  // any order
  whole.begin(true);
  part.begin(true);
  for (int e : {1, 8}) {  // a fixed and a variable element
    Eigen::VectorXd r = Eigen::VectorXd::Zero(9), r_sub(4);
    Eigen::MatrixXd k = Eigen::MatrixXd::Zero(9, 9), k_sub(4, 4);
    for (int i = 0; i < 4; ++i) {
      r[local[i]] = r_sub[i] = p.r_local[e][i];
      for (int j = 0; j < 4; ++j) k(local[i], local[j]) = k_sub(i, j) = p.k_local[e](i, j);
    }
    whole.add(e, r, &k);
    part.add(e, local, r_sub, &k_sub);
  }
  whole.end();
  part.end();
  EXPECT_EQ((Eigen::MatrixXd(whole.matrix()) - Eigen::MatrixXd(part.matrix())).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((whole.full_residual() - part.full_residual()).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_GT(Eigen::MatrixXd(part.matrix()).cwiseAbs().maxCoeff(), 0.0);
  const std::vector<int> outside{9};
  EXPECT_THROW(part.add(1, outside, Eigen::VectorXd::Zero(1), nullptr), std::out_of_range);
  EXPECT_THROW(part.add(1, Eigen::VectorXd::Zero(4), nullptr), std::invalid_argument);
}

// A rank-one term held apart (reduce): c (T^T v)(T^T v)^T is what adding the element matrix c v v^T on the
// same local DOFs adds to the reduced matrix, for a fixed and a variable element, with real MPCs in T.
TEST(SparseAssembler, ReducedVectorOfARankOneTermIsWhatItsMatrixAdds) {
  const RandomProblem p = make_problem(80, 12, 9, 6);
  SparseAssembler a;
  a.set_pattern(p.constraints, {p.element_dofs.begin(), p.element_dofs.begin() + 6});
  a.set_variable_elements({p.element_dofs.begin() + 6, p.element_dofs.end()});
  ASSERT_GT((dense_t(p.constraints).array() != 0.0 && dense_t(p.constraints).array() != 1.0).count(), 5);
  const std::vector<int> local{7, 2, 5, 0};
  const Eigen::VectorXd v = Eigen::VectorXd::LinSpaced(4, -1.5, 2.0);
  for (int e : {1, 8}) {
    a.begin(true);
    const Eigen::MatrixXd k = -2.5 * v * v.transpose();
    a.add(e, local, Eigen::VectorXd::Zero(4), &k);
    a.end();
    const Eigen::SparseVector<double> u = a.reduce(e, local, v);
    EXPECT_EQ(u.size(), a.matrix().rows());
    const Eigen::MatrixXd term = -2.5 * Eigen::VectorXd(u) * Eigen::VectorXd(u).transpose();
    EXPECT_LE((Eigen::MatrixXd(a.matrix()) - term).cwiseAbs().maxCoeff(), 1e-14 * term.cwiseAbs().maxCoeff());
    EXPECT_GT(term.cwiseAbs().maxCoeff(), 0.0);
  }
  const std::vector<int> outside{9};
  EXPECT_THROW(a.reduce(1, outside, Eigen::VectorXd::Zero(1)), std::out_of_range);
  EXPECT_THROW(a.reduce(1, local, Eigen::VectorXd::Zero(3)), std::invalid_argument);
  EXPECT_THROW(a.reduce(12, local, v), std::out_of_range);
}

}  // namespace
}  // namespace fibrane::solve
