#pragma once
// Fiber-fiber van der Waals and steric interaction between two beams (or a beam and itself) by the
// section-beam interaction potential (interaction/section_beam.hpp, laws/section_cylinder.hpp): at every
// quadrature point of one fiber its section interacts with the surrogate cylinder of the other fiber at
// the closest point of the other's axis, and the potential per unit length is integrated along the fiber.
//
// Two half passes make the energy symmetric in the fibers:
//   Pi = 1/2 int_A pi(A's section | B) dS_A + 1/2 int_B pi(B's section | A) dS_B,
// S the reference arc length (the densities are reference ones, paper Eq. 4). Each pass is differentiated
// exactly, the closest point's motion included (S7), so the residual is the gradient of Pi and the forces on
// the two fibers balance (translation invariance). With one fiber (self-interaction, the fiber folding onto
// itself) there is one pass with the factor 1/2, and the closest point is sought only on elements farther
// than `exclusion` (reference arc length) from the section and sharing no control point with its element.
//
// Pair search: a bounding-volume hierarchy (interaction/box_tree.hpp) over the target fiber's elements
// (boxes of the current control polygons), refitted at every update, gives the candidate elements within
// R_A + R_B + g_c of a section's centre (g_c the law's cut-off; twice the radii when the law has none).
// The closest point is sought by Newton's method in them, nearest box first, skipping elements whose
// box is farther than the best distance found (branch and bound). The pattern of pairs (source element,
// target element) holds the pairs of the points that may interact (gap bound below the cut-off) and the
// pairs with the neighbouring elements of either, and is rebuilt only when such a point's pair is
// missing. A section whose closest point on the other axis is not a stationary point of the distance
// inside the target's elements (beyond a fiber's end, or, for self-interaction, only in the excluded
// neighbourhood) does not interact.
//
// End taper (optional, end_taper > 0): a section's potential is multiplied by the C1 factor of
// interaction/section_beam.hpp over the last end_taper x L_B (reference arc length) of the other fiber's
// ends, so that it fades out smoothly as its closest point approaches the other's end instead of
// stopping where the closest point leaves the fiber.
//
// Contact length: the reference arc length of fiber 0 (the first of the pair) over which the gap to the
// other fiber is below the contact gap g_contact, by the quadrature of the points: L_c = sum of `length`
// over fiber 0's points with a closest point and gap < g_contact (a point counts whole or not at all).
// g_contact defaults to twice the law's equilibrium gap (SectionCylinderLaw::equilibrium_gap).
#include <Eigen/Dense>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "interaction/box_tree.hpp"
#include "interaction/section_beam.hpp"
#include "laws/section_cylinder.hpp"
#include "model/interaction.hpp"

namespace fibrane::model {

class BeamBody;

// What one quadrature point of a fiber sees (its own pass), for output.
struct FiberPoint {
  double xi = 0, s = 0;  // parameter and reference arc length on its fiber
  bool active = false;   // inside the cut-off: it interacts
  bool found = false;    // a closest point on the other fiber was found (gap and distance are meaningful)
  double gap = 0, distance = 0, energy_density = 0;  // g (S6), axis distance, pi (S1) per unit length
  double target_xi = 0;                              // the closest point's parameter on the other fiber
  double weight = 0;  // its quadrature weight: its share of the energy is weight * energy_density
  double length = 0;  // the reference arc length it stands for: Gauss weight x dS/dxi (sum: the fiber's length)
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  // -d pi / d x: the force per unit length on this section from its pass (the half pass's factor 1/2
  // not applied).
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
};

// A model::Interaction between two BeamBody objects (or one with itself); see the file comment. What it
// reports through the Interaction interface is written in beam_beam_output.cpp.
class BeamBeamInteraction final : public Interaction {
 public:
  // `b` may be `a` (self-interaction, needs exclusion > 0). `contact_gap` (> 0) is g_contact of the contact
  // length; NaN: default_contact_gap(law), which is NaN (and so is the contact length) for a law without
  // an equilibrium gap. `end_taper` in [0, 0.5): the taper length as a fraction of the other fiber's
  // reference length (0: none). Throws std::invalid_argument if a fiber has no circular section radius
  // matching the law's, on self-interaction without exclusion, a contact gap that is not positive or an
  // end taper outside [0, 0.5).
  BeamBeamInteraction(std::string name, std::shared_ptr<const laws::SectionCylinderLaw> law, const BeamBody& a,
                      const BeamBody& b, double exclusion = 0,
                      double contact_gap = std::numeric_limits<double>::quiet_NaN(), double end_taper = 0);
  // Twice the law's equilibrium gap (NaN if it has none).
  static double default_contact_gap(const laws::SectionCylinderLaw& law) { return 2 * law.equilibrium_gap(); }

  std::string name() const override { return name_; }
  bool variable() const override { return true; }
  // Refits the element boxes, finds every quadrature point's closest point on the other fiber, and
  // rebuilds the pattern if the pair of a point that may interact is missing from it.
  bool update(const State& s) override;
  // Per pair: fiber 0's element DOFs (x, y, z, twist per control point) followed by fiber 1's.
  std::vector<std::vector<int>> element_dofs(const solve::DofMap& dofs) const override;
  double evaluate(const State& s, ElementSink& sink, Status& status) override;
  void accept(const State& s) override;
  void reject() override;
  // The warm starts (closest-point parameters) of the last converged step and the pair pattern.
  std::vector<double> save_state() const override;
  void restore_state(const std::vector<double>& state) override;

  // Observables of the last evaluation.
  double energy() const { return energy_; }
  // Total force on fiber 0 (a) and 1 (b): minus the sum of the residual over the fiber's translations.
  Eigen::Vector3d force_on(int fiber) const { return force_[fiber]; }
  int interacting_points() const;  // quadrature points inside the cut-off, both passes
  int interacting_pairs() const;   // element pairs with at least one such point
  double minimum_gap() const;      // over the points whose closest point was found (+inf if none)
  double contact_length() const;   // L_c of the file comment
  double contact_gap() const { return contact_gap_; }
  double end_taper() const { return end_taper_; }
  // Per quadrature point of fiber 0 / 1 (fiber 1's is empty for self-interaction).
  const std::vector<FiberPoint>& points(int fiber) const { return points_[fiber]; }
  int pattern_pairs() const { return static_cast<int>(pairs_.size()); }
  bool self() const { return self_; }
  const BeamBody& fiber(int f) const { return *fiber_[f]; }

  // Interaction (beam_beam_output.cpp). Quantities: energy, force_<a>_x/y/z and force_<b>_x/y/z (force_on,
  // <a>, <b> the fibers' names; none for self-interaction), interacting_pairs, interacting_points,
  // minimum_gap, contact_length. One point series per fiber, <name>_<fiber> (<name> for self-interaction), each with a
  // table: the quadrature points with a closest point on the other fiber (VTK), all points (table). The
  // record reports the final quantities and the smallest gap of the run with its step.
  std::pair<std::string, std::string> bodies() const override;
  std::vector<std::string> quantity_names() const override;
  double quantity(std::size_t k) const override;
  std::vector<PointSeries> point_series() const override;
  PointCloud point_cloud(std::size_t series) const override;
  PointTable point_table(std::size_t series) const override;
  std::unique_ptr<RunRecord> run_record() const override;

 private:
  struct Quad {
    int element;
    double xi, weight, s, length;
    Eigen::VectorXd basis;  // shape functions of the element's control points at xi
  };
  struct Pass { int source, target; };  // fiber indices; one pass (0 -> 1) for self-interaction
  std::string name_;
  std::shared_ptr<const laws::SectionCylinderLaw> law_;
  laws::SectionCylinderLaw swapped_;  // the law with the radii exchanged: fiber 1's sections against fiber 0
  const BeamBody* fiber_[2];
  bool self_;
  double exclusion_;
  double contact_gap_;
  double end_taper_;
  std::vector<Pass> passes_;
  std::vector<Quad> quad_[2];
  std::vector<double> element_start_[2];  // reference arc length at each element's start (and the end)
  std::vector<Eigen::Vector3d> cps_[2];   // current control points
  interaction::BoxTree tree_[2];
  std::vector<double> warm_[2], accepted_[2];  // closest-point parameters per point (NaN: none)
  std::vector<int> target_element_[2];         // per point: the target element holding its closest point, or -1
  std::vector<char> in_pair_[2];               // per point: evaluated in a pair (it may be within the cut-off)
  std::vector<std::pair<int, int>> pairs_;     // (element of fiber 0, element of fiber 1), sorted
  std::vector<std::vector<std::pair<int, int>>> pair_points_;  // per pair: (pass, point)
  std::vector<FiberPoint> points_[2];
  double energy_ = 0;
  Eigen::Vector3d force_[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};

  double search_distance() const;
  std::vector<Eigen::AlignedBox3d> element_boxes(int fiber) const;
  bool excluded(int point, int target_element) const;  // self-interaction's neighbourhood
  // The end taper's data at parameter xi of `fiber` (the arc length to its nearer end).
  interaction::EndTaper taper_at(int fiber, double xi) const;
  void project(int pass, int point, std::vector<int>& candidates);
  bool collect_pairs();
  bool keep_pair(int e0, int e1) const;  // a valid pair; self-interaction's excluded ones are not
  // One pair's residual / tangent in its element's DOF order; returns the energy. `any_active`: set if a
  // point of the pair lies inside the cut-off.
  double evaluate_pair(int pair, bool with_tangent, Eigen::VectorXd& r, Eigen::MatrixXd& k, Status& status,
                       bool& any_active);
};

}  // namespace fibrane::model
