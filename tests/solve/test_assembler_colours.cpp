// The coloured assembly (SparseAssembler::Strategy::Colours): the colouring's promise (elements of one
// colour share no DOF and no reduced unknown) and a colour-by-colour loop against the serial assembly.
#include <gtest/gtest.h>

#include <omp.h>

#include <set>

#include "linalg/assembler.hpp"
#include "random_assembly.hpp"

namespace fibrane::solve {
namespace {

// Every element of [first, first + count) lies in exactly one colour, and two elements of one colour share
// neither a DOF nor a reduced unknown.
void expect_proper_colouring(const SparseAssembler& a, const RandomProblem& p, int first, int count,
                             int first_source) {
  std::vector<int> seen(static_cast<size_t>(count), 0);
  for (int c = 0; c < a.num_colours(); ++c) {
    std::set<int> dofs, reduced;
    for (int element : a.coloured(c, first, count)) {
      ASSERT_GE(element, first);
      ASSERT_LT(element, first + count);
      ++seen[static_cast<size_t>(element - first)];
      std::set<int> own_reduced;
      for (int d : p.element_dofs[static_cast<size_t>(first_source + element - first)]) {
        EXPECT_TRUE(dofs.insert(d).second) << "colour " << c << ": DOF " << d << " twice";
        for (const auto& [i, coef] : p.constraints.expansion(d)) own_reduced.insert(i);
      }
      for (int i : own_reduced)
        EXPECT_TRUE(reduced.insert(i).second) << "colour " << c << ": unknown " << i << " twice";
    }
  }
  for (int k : seen) EXPECT_EQ(k, 1);
}

TEST(ColouredAssembly, ColoursShareNoDofAndNoReducedUnknown) {
  // DOF 5's two masters are shared through the chained constraints by most elements: hundreds of colours,
  // more than one 64-bit word of colour flags per DOF.
  const RandomProblem p = make_problem(3000, 4000, 12, 2);
  SparseAssembler a;
  a.set_pattern(p.constraints, {p.element_dofs.begin(), p.element_dofs.begin() + 3000});
  EXPECT_GT(a.num_colours(), 64);
  expect_proper_colouring(a, p, 0, 3000, 0);
  expect_proper_colouring(a, p, 100, 250, 100);  // a contribution's sub-range
  const int fixed_colours = a.num_colours();
  for (size_t begin : {3000u, 3500u}) {  // the variable elements' colours follow the fixed ones'
    a.set_variable_elements({p.element_dofs.begin() + static_cast<long>(begin), p.element_dofs.end()});
    expect_proper_colouring(a, p, 3000, static_cast<int>(4000 - begin), static_cast<int>(begin));
    for (int c = 0; c < fixed_colours; ++c) EXPECT_TRUE(a.coloured(c, 3000, 1000).empty());
    for (int c = fixed_colours; c < a.num_colours(); ++c) EXPECT_TRUE(a.coloured(c, 0, 3000).empty());
  }
}

// A loop as ElementSink::for_each_element runs it: colour by colour, every add of the visited element
// straight into the matrix from both threads; the result equals the serial assembly to round-off, and no
// per-thread copy of the values is made.
TEST(ColouredAssembly, ColourByColourLoopEqualsSerialWithoutBuffers) {
  const RandomProblem p = make_problem(3000, 4000, 12, 6);
  SparseAssembler serial, coloured;
  serial.set_strategy(SparseAssembler::Strategy::ThreadBuffers);
  coloured.set_strategy(SparseAssembler::Strategy::Colours);
  const std::vector<std::vector<int>> fixed(p.element_dofs.begin(), p.element_dofs.begin() + 3500);
  const std::vector<std::vector<int>> variable(p.element_dofs.begin() + 3500, p.element_dofs.end());
  for (SparseAssembler* a : {&serial, &coloured}) {
    a->set_pattern(p.constraints, fixed);
    a->set_variable_elements(variable);
  }
  const int n = coloured.num_elements();
  serial.begin(true);
  for (int e = 0; e < n; ++e) serial.add(e, p.r_local[static_cast<size_t>(e)], &p.k_local[static_cast<size_t>(e)]);
  serial.end();
  for (int pass = 0; pass < 2; ++pass) {  // the second pass finds the matrix zeroed by begin()
    coloured.begin(true);
#pragma omp parallel num_threads(2)
    for (int c = 0; c < coloured.num_colours(); ++c) {
      const auto elements = coloured.coloured(c, 0, n);
#pragma omp for schedule(static, 4)
      for (size_t i = 0; i < elements.size(); ++i) {
        const SparseAssembler::Exclusive visit(coloured, elements[i]);
        const auto e = static_cast<size_t>(elements[i]);
        coloured.add(elements[i], p.r_local[e], &p.k_local[e]);
      }
    }
    coloured.end();
    expect_same_sums(coloured, serial);
    EXPECT_LT(coloured.buffer_bytes(), sizeof(double) * 4 * 3000u);  // the overflow's residual and rate only
  }
}

// A visit adds its own element only; outside a visit the ordinary thread-safe path is taken.
TEST(ColouredAssembly, AVisitAddsItsOwnElementOnly) {
  const RandomProblem p = make_problem(60, 40, 6, 1);
  SparseAssembler a;
  a.set_pattern(p.constraints, p.element_dofs);
  a.begin(true);
  {
    const SparseAssembler::Exclusive visit(a, 3);
    EXPECT_NO_THROW(a.add(3, p.r_local[3], &p.k_local[3]));
    EXPECT_THROW(a.add(4, p.r_local[4], &p.k_local[4]), std::logic_error);
  }
  EXPECT_NO_THROW(a.add(4, p.r_local[4], &p.k_local[4]));
  a.end();
}

}  // namespace
}  // namespace fibrane::solve
