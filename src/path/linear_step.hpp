#pragma once
// The linearised problem: one Newton update from the start state at the full load t_end (a linear
// analysis when the start is the undeformed state). The residual after the update is checked: a singular
// or ill-posed system (free rigid-body modes) does not pass as a solution.
#include "path/continuation.hpp"

namespace fibrane::solve {

class LinearStep final : public ContinuationMethod {
 public:
  // `tolerance`: largest |r| after the update relative to max(|r_0|, residual_scale()); a linear system
  // solved by a direct method leaves round-off only (1e-10 and below), a singular one does not.
  LinearStep(double t_start, double t_end, double tolerance = 1e-6);
  std::string name() const override { return "linear"; }
  ContinuationResult run(NonlinearSystem& sys, Eigen::VectorXd& q, LinearSolver& solver,
                         const StepCallback& on_step) override;

 private:
  double t_start_, t_end_, tolerance_;
};

}  // namespace fibrane::solve
