// The soft-minimum part of the coupling (interaction/soft_distance.hpp, docs/interaction.md section 7):
// which beam points switch to it, their windows on the shell, the continuity offset at the switch, the
// pattern elements they share, and their evaluation.
#include <algorithm>
#include <limits>

#include "common/overlap_groups.hpp"
#include "common/parallel_errors.hpp"
#include "model/beam_body.hpp"
#include "model/coupling.hpp"
#include "model/ordered_sum.hpp"
#include "model/shell_body.hpp"

namespace fibrane::model {
namespace {

// A soft-minimum window (interaction::soft_window_half_width) is re-centred after a step in which its
// point's closest point moved by more than kRecentre of its half-width; when the soft element changes
// anyway (a switch or such a re-centre), windows whose point moved by more than kRecentreAlong are
// re-centred with it: each change of the element is a new sparsity pattern and symbolic factorisation.
constexpr double kRecentre = 0.25, kRecentreAlong = 0.1;

}  // namespace

interaction::SoftWindow Coupling::soft_window(const Eigen::Vector2d& centre) const {
  const double d_eq = law_->equilibrium_distance(1.0);
  return interaction::make_soft_window(shell_.surface, centre, interaction::soft_window_half_width(soft_width_, d_eq),
                                       interaction::soft_window_cell(soft_width_, d_eq), shell_.mirrors);
}

bool Coupling::update_soft_windows() {
  if (soft_requests_.empty()) return false;
  for (const auto& [i, centre] : soft_requests_) {
    interaction::SoftWindow w = soft_window(centre);
    if (soft_of_[i] < 0) {
      soft_of_[i] = static_cast<int>(soft_.size());
      SoftPoint sp;
      sp.point = i;
      sp.centre = centre;
      sp.window = std::move(w);
      soft_.push_back(std::move(sp));
    } else {
      soft_[soft_of_[i]].centre = centre;
      soft_[soft_of_[i]].window = std::move(w);
    }
  }
  soft_requests_.clear();
  soft_changed_ = true;
  return true;
}

void Coupling::calibrate_soft_points(const Eigen::VectorXd& u, const solve::DofMap& dofs) {
  // A point that has just switched to the soft minimum: its offset makes phi(D + offset) = phi(d) here,
  // with d from the branch it was on (a local projection from its window's centre).
  for (SoftPoint& sp : soft_) {
    if (sp.calibrated) continue;
    const Eigen::Vector3d r = beam_point(sp.point, u, dofs);
    const auto branch = proximity_.project(r, sp.centre, 1.0);
    const auto& qp = quad_[sp.point];
    const Eigen::Matrix3Xd beam_x = beam_.current(beam_.elements[qp.element].control_points, u, dofs).topRows<3>();
    const double D = interaction::soft_distance(beta(), beam_.curve.basis(qp.xi, 0).R.row(0), beam_x, sp.window,
                                                shell_.current(sp.window.control_points, u, dofs), false)
                         .distance;
    sp.offset = branch.where == interaction::ShellProximity::Projection::Where::interior ? branch.distance - D : 0.0;
    sp.calibrated = true;
  }
}

void Coupling::build_soft_elements() {
  // One group per set of points whose windows are joined through shared control points.
  std::vector<const std::vector<int>*> windows;
  for (const SoftPoint& sp : soft_) windows.push_back(&sp.window.control_points);
  const std::vector<int> group_of = overlap_groups(windows);
  const auto groups = group_of.empty() ? 0 : *std::max_element(group_of.begin(), group_of.end()) + 1;
  soft_groups_.assign(static_cast<std::size_t>(groups), {});
  for (std::size_t k = 0; k < soft_.size(); ++k) {
    SoftPoint& sp = soft_[k];
    sp.group = group_of[k];
    const auto& beam_cps = beam_.elements[quad_[sp.point].element].control_points;
    SoftGroup& g = soft_groups_[static_cast<std::size_t>(sp.group)];
    g.beam_cps.insert(g.beam_cps.end(), beam_cps.begin(), beam_cps.end());
    g.shell_cps.insert(g.shell_cps.end(), sp.window.control_points.begin(), sp.window.control_points.end());
  }
  for (SoftGroup& group : soft_groups_)
    for (auto* cps : {&group.beam_cps, &group.shell_cps}) {
      std::sort(cps->begin(), cps->end());
      cps->erase(std::unique(cps->begin(), cps->end()), cps->end());
    }
  auto index = [](const std::vector<int>& sorted, int cp) {
    return static_cast<int>(std::lower_bound(sorted.begin(), sorted.end(), cp) - sorted.begin());
  };
  for (SoftPoint& sp : soft_) {
    const SoftGroup& group = soft_groups_[static_cast<std::size_t>(sp.group)];
    const int beam_size = 4 * static_cast<int>(group.beam_cps.size());
    sp.to_union.clear();
    for (int cp : beam_.elements[quad_[sp.point].element].control_points)
      for (int c = 0; c < 4; ++c) sp.to_union.push_back(4 * index(group.beam_cps, cp) + c);
    for (int cp : sp.window.control_points)
      for (int c = 0; c < 3; ++c) sp.to_union.push_back(beam_size + 3 * index(group.shell_cps, cp) + c);
  }
}

void Coupling::request_soft_switches() {
  if (soft_width_ <= 0) return;
  std::vector<std::pair<int, Eigen::Vector2d>> along;
  for (std::size_t i = 0; i < quad_.size(); ++i) {
    const auto& p = projection_[i];
    if (p.where != interaction::ShellProximity::Projection::Where::interior) continue;
    const Eigen::Vector2d theta(p.u, p.v);
    if (soft_of_[i] < 0) {
      if (p.relative_curvature <= soft_below_) soft_requests_.emplace_back(static_cast<int>(i), theta);
    } else {
      const SoftPoint& sp = soft_[soft_of_[i]];
      const double moved = ((theta - sp.centre).array().abs() / sp.window.half_extent.array()).maxCoeff();
      if (moved > kRecentre) soft_requests_.emplace_back(static_cast<int>(i), theta);
      else if (moved > kRecentreAlong) along.emplace_back(static_cast<int>(i), theta);
    }
  }
  if (!soft_requests_.empty()) soft_requests_.insert(soft_requests_.end(), along.begin(), along.end());
}

// A failed attempt's jumps say where the closest-point model fails, but which points jump depends on how
// far the attempt wandered (its iterates, Newton's stall and iteration limits). So the points that switch
// are those whose relative curvature at the last converged state is below `below_on_failure`: a set that
// depends on that state alone. Only where that set is empty do the points that jumped switch.
void Coupling::request_switches_after_jumps(const std::vector<int>& jumped) {
  bool any = false;
  for (std::size_t i = 0; i < quad_.size(); ++i)
    if (soft_of_[i] < 0 && warm_[i] && converged_curvature_[i] <= soft_below_on_failure_) {
      soft_requests_.emplace_back(static_cast<int>(i), *warm_[i]);
      any = true;
    }
  if (any) return;
  for (int i : jumped)
    if (soft_of_[i] < 0 && warm_[i]) soft_requests_.emplace_back(i, *warm_[i]);
}

std::vector<double> Coupling::event_margins() const {
  if (soft_width_ <= 0) return {};
  std::vector<double> margins(quad_.size(), std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < quad_.size(); ++i)
    if (soft_of_[i] >= 0)
      margins[i] = std::numeric_limits<double>::quiet_NaN();
    else if (projection_[i].where == interaction::ShellProximity::Projection::Where::interior)
      margins[i] = projection_[i].relative_curvature - soft_below_;
  return margins;
}

double Coupling::evaluate_soft_points(const State& state, ElementSink& sink, bool& bad) {
  // Each soft point adds the sub-block of its support to its group's soft element (after the pairs). The
  // points are evaluated in parallel and added in their order afterwards: the sub-blocks overlap, and added
  // from several threads they would need a per-thread copy of the matrix values (solve::SparseAssembler).
  // A distributed run evaluates the points of the soft elements this process owns. Where the sink holds
  // rank-one terms apart (a partial evaluation for a local update), each point's dense term goes there.
  const int first_element = static_cast<int>(pairs_.size());
  std::vector<int> owned;
  for (int k = 0; k < static_cast<int>(soft_.size()); ++k)
    if (sink.owns(first_element + soft_[static_cast<std::size_t>(k)].group)) owned.push_back(k);
  const int n_soft = static_cast<int>(owned.size());
  if (n_soft == 0) return 0.0;
  const Eigen::VectorXd& u = state.u;
  const solve::DofMap& dofs = state.dofs;
  const bool with_tangent = sink.with_tangent();
  const double beta = this->beta();
  std::vector<Eigen::VectorXd> r_of(static_cast<std::size_t>(n_soft));
  std::vector<Eigen::MatrixXd> k_of(static_cast<std::size_t>(n_soft));
  std::vector<std::vector<int>> support_of(static_cast<std::size_t>(n_soft));
  const bool apart = sink.holds_rank_one_apart();
  std::vector<interaction::RankOneTerm> rank_one_of(apart ? static_cast<std::size_t>(n_soft) : 0);
  OrderedSum sum;  // static schedule, ordered sum: the same bits in every run with this thread count
  FirstError error;
#pragma omp parallel reduction(|| : bad)
  {
    double energy = 0;
#pragma omp for schedule(static, 1)
    for (int k = 0; k < n_soft; ++k) error.run([&] {
      const SoftPoint& sp = soft_[static_cast<std::size_t>(owned[static_cast<std::size_t>(k)])];
      const auto& qp = quad_[sp.point];
      const auto qb = beam_.current(beam_.elements[qp.element].control_points, u, dofs);
      const Eigen::Matrix3Xd beam_x = qb.topRows<3>();
      const Eigen::Matrix3Xd window_x = shell_.current(sp.window.control_points, u, dofs);
      const Eigen::RowVectorXd basis = beam_.curve.basis(qp.xi, 0).R.row(0);
      Eigen::VectorXd& r = r_of[static_cast<std::size_t>(k)];
      Eigen::MatrixXd& kt = k_of[static_cast<std::size_t>(k)];
      std::vector<int>& support = support_of[static_cast<std::size_t>(k)];
      try {
        double e = 0;
        Eigen::Vector3d f;
        const double D = interaction::add_soft_rf2_point(*law_, beta, basis, beam_x, sp.window, window_x, sp.offset,
                                                         qp.weight, &e, &r, with_tangent ? &kt : nullptr, &f, &support,
                                                         apart ? &rank_one_of[static_cast<std::size_t>(k)] : nullptr);
        energy += e;
        auto& out = points_[sp.point];
        out.active = true;
        out.soft = true;
        out.distance = D;
        out.energy_density = e / qp.weight;
        out.force = -f;
        out.position = beam_x * basis.transpose();
        for (int& i : support) i = sp.to_union[i];
      } catch (const std::domain_error&) {
        support.clear();
        bad = true;
      }
    });
    sum.set(energy);
  }
  error.rethrow();
  for (int k = 0; k < n_soft; ++k) {
    const auto p = static_cast<std::size_t>(k);
    const int element = first_element + soft_[static_cast<std::size_t>(owned[p])].group;
    if (support_of[p].empty()) continue;
    sink.add(element, support_of[p], r_of[p], with_tangent ? &k_of[p] : nullptr);
    if (apart) sink.add_rank_one(element, support_of[p], rank_one_of[p].coefficient, rank_one_of[p].vector);
  }
  return sum.total();
}

}  // namespace fibrane::model
