// The unsymmetric tangent of the full membrane (bending-full.yaml: the fiber at 30 degrees, whose end
// moments make the load stiffness unsymmetric) at more than 100 k unknowns: "auto" (the symmetric part and a
// low-rank correction) and the LU factorise it and solve to a relative residual of 1e-10.
#include <gtest/gtest.h>

#include <random>

#include "case_runner.hpp"
#include "linalg/direct_solvers.hpp"
#include "linalg/linear_solver.hpp"

namespace fibrane::testing {
namespace {

TEST(UnsymmetricSolve, FullMembraneTangentAbove100kUnknowns) {
  // 61 x 61 quartic C1 shell elements (185^2 control points, 102 675 DOFs) and 244 beam elements, whose
  // end control point is 3 x 244 + 1 = 733.
  const std::string text = example_text("bending-full.yaml", {{"elements: [40, 40]", "elements: [61, 61]"},
                                                              {"elements: 160", "elements: 244"},
                                                              {"control_point: 481, component: x", "control_point: 733, component: x"},
                                                              {"control_point: 481, component: y", "control_point: 733, component: y"}});
  const auto dir = fresh_directory("unsymmetric-solve");
  std::ofstream(dir / "case.yaml") << text;
  auto c = casefile::read_case((dir / "case.yaml").string());
  auto& m = *c.model;
  ASSERT_GE(m.size(), 100000);
  ASSERT_FALSE(m.symmetric());
  // A deformed state at t = 0.5 (moments at half their final value): small random displacements.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1e-3, 1e-3);
  Eigen::VectorXd q(m.size());
  for (int i = 0; i < q.size(); ++i) q[i] = u(rng);
  m.evaluate(q, 0.5, true);
  const Eigen::SparseMatrix<double>& k = m.tangent();
  const Eigen::SparseMatrix<double> kt = k.transpose();
  const double asymmetry = (k - kt).norm() / k.norm();
  EXPECT_GT(asymmetry, 1e-12) << "the tangent is symmetric: the test would not exercise the LU path";
  // A right-hand side as Newton meets them, the forces K x_true of a displacement field: a backward-stable
  // solve leaves a relative residual of ~eps times the element growth (measured 1e-15 here), and a wrong or
  // failed factorisation O(1). (For a random b, |x| is set by the smallest singular values and the relative
  // residual becomes eps times the condition number, ~1e-7 here, whatever the solver.)
  Eigen::VectorXd x_true(m.size());
  for (int i = 0; i < x_true.size(); ++i) x_true[i] = u(rng);
  const Eigen::VectorXd b = k * x_true;
  // "auto": the end moments' skew part lives on 13 rows (the fiber ends' control points), so the symmetric
  // part is factorised (indefinite at this random state: MUMPS's LDL^T) with the rank-13 correction; an LU
  // of the whole matrix where asked for.
  const std::string lu = solve::mumps_available() ? "mumps-lu" : "umfpack64";
  for (const std::string kind : {"auto", lu.c_str()}) {
    auto solver = solve::make_linear_solver(kind, m.symmetric());
    solver->analyze(k);
    ASSERT_TRUE(solver->factorize(k)) << solver->failure_detail();
    EXPECT_EQ(solver->name(), kind == "auto" ? "symmetric-part(auto(" + std::string(solve::mumps_available() ? "mumps" : "umfpack64") +
                                                   "))+rank-13"
                                             : lu);
    const Eigen::VectorXd x = solver->solve(b);
    EXPECT_LT((k * x - b).norm() / b.norm(), 1e-10) << kind;
  }
}

}  // namespace
}  // namespace fibrane::testing
