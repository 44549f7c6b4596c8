// States that an overflowing time step produces (non-finite unknowns or time, coordinates near 1e200) are
// invalid states that Newton fails on, never exceptions out of the evaluation; and an exception inside an
// OpenMP parallel region is carried out of it (common/parallel_errors.hpp) instead of ending the process.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "case/case_reader.hpp"
#include "common/parallel_errors.hpp"

namespace fibrane {
namespace {

// The coupled dynamics case of the hostile runs (a beam over a membrane, Lennard-Jones FF).
casefile::Case coupled_case() {
  return casefile::read_case(std::string(FIBRANE_SOURCE_DIR) + "/tests/app/hostile_runs/dynamics_huge_dt.yaml");
}

TEST(InvalidStates, NonFiniteUnknownsOrTimeAreAnInvalidState) {
  casefile::Case c = coupled_case();
  model::Model& m = *c.model;
  const Eigen::VectorXd q0 = m.initial_unknowns();
  m.evaluate(q0, 0.0, true);
  ASSERT_TRUE(m.invalid_state().empty()) << m.invalid_state();
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (double bad : {nan, inf, -inf}) {
    Eigen::VectorXd q = q0;
    q[q.size() / 2] = bad;
    for (bool with_tangent : {false, true}) {
      ASSERT_NO_THROW(m.evaluate(q, 0.0, with_tangent));
      EXPECT_NE(m.invalid_state().find("not finite"), std::string::npos) << m.invalid_state();
      EXPECT_EQ(m.residual().size(), q0.size());
    }
  }
  ASSERT_NO_THROW(m.evaluate(q0, inf, false));
  EXPECT_NE(m.invalid_state().find("not finite"), std::string::npos);
  m.evaluate(q0, 0.0, true);  // a valid state is valid again
  EXPECT_TRUE(m.invalid_state().empty()) << m.invalid_state();
  EXPECT_TRUE(m.residual().allFinite());
}

// Finite but overflowing coordinates (squared distances infinite): the evaluation returns, with a state
// that Newton cannot accept (invalid, or a non-finite residual).
TEST(InvalidStates, OverflowingCoordinatesAreNotAnException) {
  casefile::Case c = coupled_case();
  model::Model& m = *c.model;
  const Eigen::VectorXd q0 = m.initial_unknowns();
  m.evaluate(q0, 0.0, false);
  for (double huge : {1e200, -1e300, 1e155}) {
    ASSERT_NO_THROW(m.evaluate(Eigen::VectorXd::Constant(q0.size(), huge), 0.0, true)) << huge;
    EXPECT_TRUE(!m.invalid_state().empty() || !m.residual().allFinite()) << huge;
  }
}

TEST(FirstError, AnExceptionInAParallelRegionIsRethrownAfterIt) {
  FirstError error;
  std::atomic<int> ran{0};
#pragma omp parallel for schedule(dynamic, 1)
  for (int i = 0; i < 64; ++i) error.run([&] {
    ++ran;
    if (i % 8 == 3) throw std::out_of_range("item " + std::to_string(i));
  });
  EXPECT_EQ(ran.load(), 64);  // the other items still ran
  EXPECT_TRUE(error.failed());
  EXPECT_THROW(error.rethrow(), std::out_of_range);
  FirstError none;
#pragma omp parallel for
  for (int i = 0; i < 8; ++i) none.run([] {});
  EXPECT_FALSE(none.failed());
  EXPECT_NO_THROW(none.rethrow());
}

}  // namespace
}  // namespace fibrane
