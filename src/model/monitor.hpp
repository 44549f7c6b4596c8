#pragma once
// Monitors: named scalar outputs of a run (one history.csv column each, summary.json's final values).
// Each kind is one class; the case file picks them by `type` (docs/case-format.md, "monitors").
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Dense>

namespace fibrane::model {

class Model;
class BeamBody;

class Monitor {
 public:
  explicit Monitor(std::string name) : name_(std::move(name)) {}
  virtual ~Monitor() = default;
  const std::string& name() const { return name_; }
  // The value at the model's last evaluation.
  virtual double value(const Model& m) const = 0;

 private:
  std::string name_;
};

// A linear functional of the displacement (a displacement or position at a point: the basis weights of
// the point's control points) or of the full residual. At constrained DOFs the residual
// r = f_int - f_ext is the force the support exerts on the body; a reaction monitor sums it over a set of
// DOFs closed under the constraints (ConstraintSet::linked_dofs), so that a clamp's tied row or a
// symmetry plane's tied neighbours count with the support they belong to.
class LinearMonitor final : public Monitor {
 public:
  enum class Source { displacement, residual };
  LinearMonitor(std::string name, Source source, std::vector<std::pair<int, double>> weights, double offset = 0.0)
      : Monitor(std::move(name)), source_(source), weights_(std::move(weights)), offset_(offset) {}
  double value(const Model& m) const override;

 private:
  Source source_;
  std::vector<std::pair<int, double>> weights_;  // (DOF, coefficient)
  double offset_;
};

// The resultant of the configuration-independent external loads in one direction: sum of f(t) F over
// the nodal loads' DOFs of that component (of one body, or of all), i.e. the load a load factor
// represents. Moments are not forces and do not count. With the reactions it closes the balance of
// forces: sum of all reactions + applied load = 0 in every direction.
class AppliedLoadMonitor final : public Monitor {
 public:
  // `dofs`: the DOFs of the chosen component (and body) that the loads may act on, sorted.
  AppliedLoadMonitor(std::string name, std::vector<int> dofs) : Monitor(std::move(name)), dofs_(std::move(dofs)) {}
  double value(const Model& m) const override;

 private:
  std::vector<int> dofs_;
};

// A quantity of a beam's cross-section at a point (BeamBody probes: exact at the point, frames updated
// like the quadrature points'): the rotation of the section triad from its reference (as a rotation
// vector, one component or its projection on an axis), a director component, the axial force, a section
// moment, or the twist angle of the section relative to the beam's start (the integral of the twist rate,
// which, unlike the twist DOF, does not depend on the load path).
class BeamPointMonitor final : public Monitor {
 public:
  enum class Quantity { rotation, tangent, director2, director3, axial_force, torque, bending2, bending3, twist_angle };
  // `axis`: the component's unit vector (rotation, directors), unused for scalars. `probe`: the beam's
  // probe at the point (BeamBody::add_probe); for twist_angle the first of its twist probes.
  BeamPointMonitor(std::string name, const BeamBody& beam, Quantity q, double xi, int probe, Eigen::Vector3d axis)
      : Monitor(std::move(name)), beam_(beam), quantity_(q), xi_(xi), probe_(probe), axis_(std::move(axis)) {}
  double value(const Model& m) const override;

 private:
  const BeamBody& beam_;
  Quantity quantity_;
  double xi_;
  int probe_;
  Eigen::Vector3d axis_;
};

}  // namespace fibrane::model
