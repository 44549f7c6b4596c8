#pragma once
// A Bernoulli-Euler beam body: a refined NURBS axis with a twist field on the same basis (4 DOFs per
// control point: x, y, z, phi), the section, and the per-quadrature-point frame states of the
// smallest-rotation map that are updated after every converged step (Sec. 3.2). It is the contribution
// of the beam's strain energy, and it integrates the loads that act on it.
#include <Eigen/Dense>
#include <string>
#include <vector>

#include "beam/beam.hpp"
#include "model/contribution.hpp"
#include "spline/curve.hpp"
#include "linalg/forward.hpp"

namespace fibrane::model {

struct BeamElement {
  int span;
  double xi0, xi1;
  std::vector<int> control_points;
};

class BeamBody final : public Contribution {
 public:
  spline::NurbsCurve curve;  // reference axis after refinement
  beam::BeamSection section;
  Eigen::Vector3d director = Eigen::Vector3d::Zero();  // a2 hint; zero: rotation-minimising frame
  // The part of the physical beam this model represents: 0.5 for a beam lying in a mirror-symmetry plane
  // of a model that keeps only one side of the plane (its stiffness, its loads and its interactions then
  // count half, exactly as the full problem's energy halves). 1 otherwise.
  double share = 1.0;
  double section_radius = 0.0;  // radius of a circular section (interactions need it); 0: other section
  int block = -1;
  int gauss_points = 0;  // 0 means degree + 1
  double density = 0;    // mass per unit volume (dynamics only)
  std::vector<BeamElement> elements;
  std::vector<std::vector<beam::BeamPointState>> states;  // [element][quadrature point]

  BeamBody(std::string name, spline::NurbsCurve curve, beam::BeamSection section, Eigen::Vector3d director);
  int num_control_points() const { return curve.num_control_points(); }
  int gauss() const { return gauss_points > 0 ? gauss_points : curve.degree() + 1; }
  // Builds the reference triads at every quadrature point (call after gauss_points is final).
  void initialise_states();
  beam::BeamDofs current(const std::vector<int>& cps, const Eigen::VectorXd& u, const solve::DofMap& dofs) const;

  // Contribution: the strain energy (Eq. 46) and its variations (App. B), element by element; accept()
  // updates the frame references incrementally after a converged step.
  std::string name() const override { return name_; }
  std::vector<std::vector<int>> element_dofs(const solve::DofMap& dofs) const override;
  double evaluate(const State& s, ElementSink& sink, Status& status) override;
  void accept(const State& s) override;
  // The frame states of the quadrature points and probes.
  std::vector<double> save_state() const override;
  void restore_state(const std::vector<double>& state) override;

  // Consistent nodal forces (x, y, z per control point, control-point major) of a force per unit
  // reference length along the whole beam.
  Eigen::VectorXd line_load(const Eigen::Vector3d& force) const;

  // Probes: frame states at further points (monitors, output samples), updated with the quadrature
  // points' after every converged step, so that section quantities there are exact, not those of the
  // nearest quadrature point. Returns the probe's index.
  int add_probe(double xi);
  // Probes at the Gauss points of [start of xi's element, xi], for twist_angle(); returns the first index.
  int add_twist_probes(double xi);
  // Probes at the `samples` + 1 sample points of every element (just inside its ends) for output; their
  // first index, or -1 if set_output_samples was not called with this count.
  void set_output_samples(int samples);
  int output_probes(int samples) const { return samples == output_samples_ ? output_first_ : -1; }
  beam::BeamPointOutput probe_output(int probe, const Eigen::VectorXd& u, const solve::DofMap& dofs) const;
  // Rotation vector (axis times angle in [0, pi]) of the section triad (t, a2, a3) in `out` from the
  // probe's reference triad.
  Eigen::Vector3d probe_rotation(int probe, const beam::BeamPointOutput& out) const;
  // Twist of the section at xi relative to the start: the integral of the twist rate over the reference
  // arc length (quadrature points of the elements before xi, twist probes from `first_twist_probe` on).
  double twist_angle(double xi, int first_twist_probe, const Eigen::VectorXd& u, const solve::DofMap& dofs) const;
  // Frame state of an arbitrary parameter (for point moments), consistent with initialise_states().
  beam::BeamPointState state_at(double xi) const;
  int element_of(double xi) const;
  // Reference director a2 at parameter xi (user vector or rotation-minimising frame).
  Eigen::Vector3d reference_director(double xi) const;

 private:
  std::string name_;
  int output_samples_ = -1, output_first_ = -1;
  std::vector<double> probe_xi_;
  std::vector<beam::BeamPointState> probe_states_;
  std::vector<Eigen::Matrix3d> probe_reference_;  // columns T, A2, A3 at creation
  double arc_length_weight(double xi) const { return curve.derivative(xi, 1).norm(); }
  // Rotation-minimising frame sampled densely along the axis (double reflection), for reference_director.
  std::vector<double> rmf_xi_;
  std::vector<Eigen::Vector3d> rmf_a2_;
  void build_rotation_minimising_frame();
};

}  // namespace fibrane::model
