#include "path/linear_step.hpp"

#include <algorithm>
#include <cmath>

#include "common/format.hpp"

namespace fibrane::solve {

LinearStep::LinearStep(double t_start, double t_end, double tolerance)
    : t_start_(t_start), t_end_(t_end), tolerance_(tolerance) {}

ContinuationResult LinearStep::run(NonlinearSystem& sys, Eigen::VectorXd& q, LinearSolver& solver,
                                   const StepCallback& on_step) {
  ContinuationResult res;
  res.t_reached = t_start_;
  sys.evaluate(q, t_end_, true);
  const double initial = sys.residual().norm();
  const double scale = std::max(initial, sys.residual_scale());
  solver.analyze(sys.tangent());
  if (!solver.factorize(sys.tangent())) {
    res.message = "the linear system is singular (" + solver.name() + " failed): the constraints leave a "
                  "rigid-body mode free, or a body has no stiffness";
    return res;
  }
  const Eigen::VectorXd dq = solver.solve(-sys.residual());
  if (!dq.allFinite()) {
    res.message = "the linear solve gave a non-finite update: the system is singular";
    return res;
  }
  // The linear system's own residual |K dq + r|: a direct solve leaves round-off; a singular system (a
  // zero pivot perturbed to a tiny one) leaves one of the size of the loads, or a huge one.
  const double linear_residual = (sys.tangent_times(dq) + sys.residual()).norm();
  res.total_iterations = 1;
  if (!(linear_residual <= tolerance_ * scale)) {
    res.message = "the linear solve left |K dq + r| = " + format_number(linear_residual) + " at the load level " +
                  format_number(scale) + ": the system is singular or ill-conditioned (a free rigid-body mode?)";
    return res;
  }
  q += dq;
  sys.evaluate(q, t_end_, false);
  const double after = sys.residual().norm();
  sys.accept(q, t_end_);
  res.steps = 1;
  res.t_reached = t_end_;
  StepReport report;
  report.step = 1;
  report.t = t_end_;
  report.dt = t_end_ - t_start_;
  report.iterations = 1;
  report.residual_norm = after;
  report.negative_eigenvalues = solver.negative_eigenvalues();
  if (on_step && !on_step(report, q)) {
    res.outcome = Outcome::stopped;
    res.message = "stopped by the step callback after the linear step";
    return res;
  }
  res.outcome = Outcome::reached_end;
  res.message = "linear analysis";
  return res;
}

}  // namespace fibrane::solve
