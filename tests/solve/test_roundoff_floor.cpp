// Newton at a residual round-off floor it cannot get below: a system whose residual carries a known
// rounding error, r_i = ((k q_i + B) - B) - f_i with a large offset B, so |r| stalls at about ulp(B) per
// component whatever q is. With the floor reported (NonlinearSystem::roundoff_floor) Newton accepts the
// first iterate there; without it, a tolerance below the floor cannot be met.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "path/nonlinear.hpp"

namespace fibrane::solve {
namespace {

class OffsetSystem final : public NonlinearSystem {
 public:
  OffsetSystem(int n, bool reports_floor) : n_(n), reports_floor_(reports_floor) {
    k_.resize(n, n);
    for (int i = 0; i < n; ++i) k_.insert(i, i) = kStiffness;
    k_.makeCompressed();
  }
  int size() const override { return n_; }
  void evaluate(const Eigen::VectorXd& q, double, bool) override {
    r_.resize(n_);
    for (int i = 0; i < n_; ++i) {
      volatile double shifted = kStiffness * q[i] + kOffset;  // rounded to the grid of ulp(B)
      r_[i] = (shifted - kOffset) - load(i);
    }
  }
  const Eigen::VectorXd& residual() const override { return r_; }
  const Eigen::SparseMatrix<double>& tangent() const override { return k_; }
  int pattern_version() const override { return 0; }
  double residual_scale() const override { return 1.0; }
  // Each component is off by up to ulp(B) / 2 = eps B / 2, i.e. eps B sqrt(n) / sqrt(12) on average.
  double roundoff_floor() const override {
    return reports_floor_ ? std::numeric_limits<double>::epsilon() * kOffset * std::sqrt(n_ / 12.0) : 0.0;
  }
  static double load(int i) { return std::numbers::e + 0.1 * i; }
  static constexpr double kStiffness = 3.0, kOffset = 1e8 * std::numbers::pi;

 private:
  int n_;
  bool reports_floor_;
  Eigen::SparseMatrix<double> k_;
  Eigen::VectorXd r_;
};

NewtonOptions strict_options() {
  NewtonOptions o;
  o.tol_relative = 1e-15;  // far below the floor (~1e-8 of a residual scale of 1)
  o.tol_absolute = 0.0;
  o.tol_increment = 0.0;  // only the estimated floor can end the iteration
  o.max_iterations = 10;
  return o;
}

TEST(RoundoffFloor, NewtonStopsAtAReportedFloor) {
  OffsetSystem sys(50, true);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(50);
  auto solver = make_linear_solver("auto", true);
  const NewtonReport rep = newton_solve(sys, q, 1.0, strict_options(), *solver);
  ASSERT_TRUE(rep.converged) << rep.failure;
  EXPECT_TRUE(rep.at_roundoff_floor);
  EXPECT_LE(rep.iterations, 2);
  EXPECT_GT(rep.residual_norm, 0.0) << "the test needs a floor above zero";
  for (int i = 0; i < 50; ++i) EXPECT_NEAR(q[i], OffsetSystem::load(i) / OffsetSystem::kStiffness, 1e-7);
}

TEST(RoundoffFloor, WithoutTheFloorTheToleranceCannotBeMet) {
  OffsetSystem sys(50, false);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(50);
  auto solver = make_linear_solver("auto", true);
  const NewtonReport rep = newton_solve(sys, q, 1.0, strict_options(), *solver);
  EXPECT_FALSE(rep.converged);
  EXPECT_FALSE(rep.at_roundoff_floor);
}

TEST(RoundoffFloor, AResidualAboveTheFloorIsNotAccepted) {
  // One iteration only: the first iterate after the update is at the floor, the starting point is not.
  OffsetSystem sys(5, true);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(5);
  auto solver = make_linear_solver("auto", true);
  NewtonOptions o = strict_options();
  o.max_iterations = 0;
  const NewtonReport rep = newton_solve(sys, q, 1.0, o, *solver);
  EXPECT_FALSE(rep.converged);
}

}  // namespace
}  // namespace fibrane::solve
