// The coupled, reduced tangent of a beam over a curved shell (pairs crossing element boundaries, clamped
// shell edge) against central differences of the reduced residual, for every formulation. FF uses its
// exact tangent; RF1's tangent is exact for its own (non-variational) residual.
#include <gtest/gtest.h>

#include "case_runner.hpp"
#include "model/coupling.hpp"

namespace fibrane::testing {
namespace {

// Tolerance: truncation ~ h^2 |r'''| ~ 1e-12 relative, round-off ~ 1e-16 |r| / h ~ 1e-8 relative to the
// coupling's entries; 1e-6 has margin and still catches a missing term. Measured: RF2 2.3e-8, RF1 2.2e-8,
// FF 2.3e-7. (Relative to the shell's entries, 1e7 times larger than the coupling's, the check could not
// see a coupling error.)
TEST(CoupledModel, TangentMatchesFiniteDifferencesForEveryFormulation) {
  for (const std::string f : {"RF2", "RF1", "FF"}) {
    const double error = coupling_tangent_error("coupled-tangent-" + f, ", formulation: " + f, 11,
                                                [](model::Model& m, const Eigen::VectorXd& q) {
                                                  m.evaluate(q, 1.0, false);
                                                  int active = 0;
                                                  for (const auto& p : m.interactions_of<model::Coupling>()[0]->points()) active += p.active;
                                                  ASSERT_GT(active, 10) << "the beam must interact with the panel";
                                                });
    EXPECT_LT(error, 1e-6) << f;
  }
}

}  // namespace
}  // namespace fibrane::testing
