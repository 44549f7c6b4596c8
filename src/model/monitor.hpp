#pragma once
// Monitors: named scalar outputs of a run, one history.csv column each.
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Dense>

namespace fibrane::model {

// A linear functional of the displacement (a displacement or position at a point) or of the full residual
// (a reaction: at constrained DOFs the residual r = f_int - f_ext is the force the support exerts).
struct Monitor {
  enum class Source { displacement, reaction };
  std::string name;
  Source source = Source::displacement;
  std::vector<std::pair<int, double>> weights;  // (DOF, coefficient)
  double offset = 0.0;
  double value(const Eigen::VectorXd& u, const Eigen::VectorXd& full_residual) const {
    const Eigen::VectorXd& v = source == Source::displacement ? u : full_residual;
    double s = offset;
    for (const auto& [dof, w] : weights) s += w * v[dof];
    return s;
  }
};

}  // namespace fibrane::model
