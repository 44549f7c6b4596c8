#pragma once
// The SBS coupling of one beam and one shell (Sec. 5): at every beam quadrature point the closest point
// on the current shell is found, and the point kernel of src/interaction adds the disk-surrogate plate
// potential (Eq. 5) to the pair (beam element, shell element) that holds the two points. It is an
// Interaction (model/interaction.hpp): its observables are written in coupling_output.cpp.
#include <Eigen/Dense>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "interaction/closest_point.hpp"
#include "interaction/sbs_point.hpp"
#include "interaction/soft_distance.hpp"
#include "laws/interaction_law.hpp"
#include "model/interaction.hpp"
#include "linalg/forward.hpp"

namespace fibrane::model {

class BeamBody;
class ShellBody;

// What one beam quadrature point sees, for output.
struct CouplingPoint {
  // interior: paired with its closest point on the shell; soft: evaluated with the soft minimum;
  // outside: the closest point lies off the shell patch (the stationary point of the distance is beyond
  // an edge); failed: the closest-point projection did not converge. Outside and failed points are
  // "lost": they carry no interaction, and distance / cos_alpha / position have no meaning for them.
  enum class Status { interior, soft, outside, failed };
  double xi = 0, s = 0;        // beam parameter and reference arc length
  bool active = false;         // interior or soft (the point interacts)
  bool soft = false;           // evaluated with the soft minimum (distance = the soft distance D)
  Status status = Status::outside;
  double distance = 0, cos_alpha = 1, energy_density = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero(), force = Eigen::Vector3d::Zero();  // force per length the shell exerts on the beam
};

class Coupling final : public Interaction {
 public:
  Coupling(std::string name, std::shared_ptr<const laws::InteractionLaw> law, interaction::Formulation f,
           interaction::FfTangent ff_tangent, const BeamBody& b, const ShellBody& s);

  const BeamBody& beam() const { return beam_; }
  const ShellBody& shell() const { return shell_; }
  const laws::InteractionLaw& law() const { return *law_; }
  interaction::Formulation formulation() const { return formulation_; }

  // Contribution. update(): project every beam quadrature point onto the current shell and collect the
  // (beam element, shell element) pairs; true if the pairs' pattern changed. element_dofs(): the pairs'
  // DOF lists (beam element DOFs followed by shell element DOFs), then the soft element if any.
  // evaluate(): every pair's residual (and tangent); a point inside the plate makes the status invalid.
  std::string name() const override { return name_; }
  bool variable() const override { return true; }
  bool update(const State& s) override;
  std::vector<std::vector<int>> element_dofs(const solve::DofMap& dofs) const override;
  double evaluate(const State& s, ElementSink& sink, Status& status) override;
  bool symmetric() const override {
    return formulation_ == interaction::Formulation::RF2 ||
           (formulation_ == interaction::Formulation::FF && ff_tangent_ == interaction::FfTangent::exact);
  }
  // After a converged step: its projections are the ones a failed attempt returns to. Every evaluation
  // starts from the previous evaluation's projections (the branch each point is on).
  void accept(const State& s) override;
  // After a failed attempt (the step is cut back): back to the last converged step's projections.
  void reject() override;
  // After a discarded converged attempt: the same, without switching the points that jumped in it.
  void withdraw() override;
  // With the soft minimum, one event per beam point, its switch: the relative curvature of its closest
  // point at the last evaluation minus `below` (+infinity where it is not interior, NaN once soft). A
  // point switches at the accept() after a converged step where it is <= 0.
  std::vector<double> event_margins() const override;
  // Each switch of a point to the soft minimum changes the equations (points stay switched).
  long model_changes() const override { return soft_points(); }
  // Closest points that jumped in the last failed attempt: moved by more than kJump d in one evaluation
  // while their beam point moved less than a tenth of that (two shell regions nearly equally close: the
  // closest-point SBS residual is discontinuous there). Empty if none; else a sentence for the user.
  std::string failure_hint() const override;
  // The projections' warm starts, the beam points' last positions, the pairs' pattern and the soft-minimum
  // points (their windows are rebuilt from the saved centres) and pending switches (coupling_state.cpp).
  std::vector<double> save_state() const override;
  void restore_state(const std::vector<double>& state) override;

  // Soft minimum (interaction/soft_distance.hpp, RF2 only): a beam point whose converged closest point
  // has relative curvature below `below` is evaluated from then on with the soft distance of Gibbs width
  // `width` (relative to the law's equilibrium distance) over a window of the shell around it, fixed
  // during each step. After a failed attempt in which closest points jumped, the points whose relative
  // curvature at the last converged state is below `below_on_failure` (>= below) switch as well, or, where
  // none is, the points that jumped (request_switches_after_jumps).
  void enable_soft_minimum(double width, double below, double below_on_failure);
  int soft_points() const { return static_cast<int>(soft_.size()); }

  // The (beam element, shell element) pairs of the sparsity pattern, sorted (collect_pairs in coupling.cpp).
  const std::vector<std::pair<int, int>>& pattern_pairs() const { return pairs_; }
  const std::vector<CouplingPoint>& points() const { return points_; }
  // Beam quadrature points of the last evaluation whose closest point is outside the patch or whose
  // projection failed (CouplingPoint::Status): they carry no interaction.
  int lost_points() const { return lost_points_; }
  int quadrature_points() const { return static_cast<int>(quad_.size()); }
  double energy() const { return energy_; }
  Eigen::Vector3d total_force() const;  // integral of the force per length over the beam

  // Interaction (coupling_output.cpp). Quantities: energy, force_x/y/z (total_force) and lost_points.
  // One point series named like the coupling, on the beam: a VTK point cloud of the interacting points
  // (xi, s, distance, cos_alpha, force, force_magnitude, soft_minimum) and a table of every quadrature
  // point (xi, s, active, status, distance, cos_alpha, force_x/y/z, force_magnitude, energy_density,
  // soft_minimum; lost points read nan as distance and cos_alpha, soft points nan as cos_alpha). The run
  // record reports the final energy, force and lost points and the first step with the most lost points,
  // and warns at the first step with lost points; the summary section soft_minimum_points counts the
  // soft points, if any.
  std::pair<std::string, std::string> bodies() const override;
  std::vector<std::string> quantity_names() const override;
  double quantity(std::size_t k) const override;
  std::vector<PointSeries> point_series() const override;
  PointCloud point_cloud(std::size_t series) const override;
  PointTable point_table(std::size_t series) const override;
  std::unique_ptr<RunRecord> run_record() const override;
  std::vector<SummaryField> summary_sections() const override;

 private:
  struct QuadPoint { int element; double xi, weight, s; };
  std::string name_;
  const BeamBody& beam_;
  const ShellBody& shell_;
  std::shared_ptr<const laws::InteractionLaw> law_;
  interaction::Formulation formulation_;
  interaction::FfTangent ff_tangent_;
  interaction::ShellProximity proximity_;
  std::vector<QuadPoint> quad_;  // every beam quadrature point, in beam order
  std::vector<interaction::ShellProximity::Projection> projection_;
  std::vector<std::optional<Eigen::Vector2d>> warm_, last_;
  std::vector<Eigen::Vector3d> beam_points_;  // each point's position at the previous evaluation
  std::vector<double> jump_;                  // how far each closest point jumped in this attempt (0: not)
  std::vector<std::pair<double, double>> failed_jumps_;  // (xi, jump / d) of the last failed attempt
  std::vector<std::pair<int, int>> pairs_;          // (beam element, shell element) in the pattern, sorted
  std::vector<std::vector<int>> pair_points_;       // quadrature points of each pair
  std::vector<CouplingPoint> points_;
  double energy_ = 0;
  int lost_points_ = 0;
  void classify_points();  // sets each point's status and lost_points_ after an evaluation

  struct SoftPoint {
    int point;                      // index into quad_
    Eigen::Vector2d centre;         // the window's centre (parameters)
    interaction::SoftWindow window;
    // d - D at the first evaluation after the switch (d from the branch the point was on), so that the
    // energy is continuous across the switch; kept when the window is re-centred (D changes by < e^-30).
    double offset = 0;
    bool calibrated = false;
    int group = 0;              // its soft element: index into soft_groups_
    std::vector<int> to_union;  // the point's local DOFs (beam CPs x 4, window CPs x 3) in its soft element
  };
  // The control points of one soft element (sorted): its points' beam elements' and windows'.
  struct SoftGroup {
    std::vector<int> beam_cps, shell_cps;
  };
  double beta() const;  // 1 / (width d_eq)
  Eigen::Vector3d beam_point(int i, const Eigen::VectorXd& u, const solve::DofMap& dofs) const;
  bool update_soft_windows();  // switches and re-centres the requested points; false: none requested
  interaction::SoftWindow soft_window(const Eigen::Vector2d& centre) const;  // the window around `centre`
  void calibrate_soft_points(const Eigen::VectorXd& u, const solve::DofMap& dofs);
  bool collect_pairs();  // true if a pair outside the pattern appeared
  // -1, 0 or 1: the side of axis `axis` (0: u, 1: v) toward which point i's closest point has moved since
  // the last converged step, by more than kDriftShare of `width`, its element's parameter length along the
  // axis (collect_pairs).
  int drift_side(int i, int axis, double width) const;
  double evaluate_pairs(const State& s, ElementSink& sink, bool& bad);
  double evaluate_soft_points(const State& s, ElementSink& sink, bool& bad);
  // Distributed: sums the points' output data and `energy` over the processes (collective).
  void share_points(const ElementSink& sink, double& energy);
  // Soft points whose windows share a control point share one pattern element (after the pairs'): the
  // union of their beam elements' and windows' control points (such windows overlap almost entirely), each
  // point adding the sub-block of its support. Points with windows apart (at the two ends of a fiber)
  // have elements apart, so that the pattern does not couple the two windows with each other.
  void build_soft_elements();
  // After a converged step: points to switch to the soft minimum and windows to re-centre.
  void request_soft_switches();
  // After a failed attempt in which the points `jumped` jumped: the points to switch for the retry.
  void request_switches_after_jumps(const std::vector<int>& jumped);
  std::vector<SoftGroup> soft_groups_;
  double soft_width_ = 0, soft_below_ = 0, soft_below_on_failure_ = 0;  // width 0: off
  // Each point's relative curvature at the last converged state (+infinity: not interior, soft, or no
  // state converged yet); saved in checkpoints, since a failed attempt after a restart reads it.
  std::vector<double> converged_curvature_;
  std::vector<SoftPoint> soft_;
  std::vector<int> soft_of_;                                   // per quadrature point: index into soft_, or -1
  std::vector<std::pair<int, Eigen::Vector2d>> soft_requests_;  // (point, centre) to (re)window
  bool soft_changed_ = false;
};

}  // namespace fibrane::model
