#include "model/coupling.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "common/parallel_errors.hpp"
#include "model/beam_body.hpp"
#include "model/ordered_sum.hpp"
#include "model/shell_body.hpp"
#include "linalg/assembler.hpp"
#include "linalg/dof_map.hpp"
#include "spline/quadrature.hpp"
#include "spline/surface_third.hpp"

namespace fibrane::model {

namespace {


// Where two local minima of the distance are within this fraction of each other, a beam point stays on
// its branch (ShellProximity::project): switching at every Newton iterate made Newton cycle at the
// bending example's folded shell under the fiber's end.
constexpr double kBranchMargin = 1e-3;

// A closest point that moves by more than kJump d in one evaluation while its beam point moves less than
// 1/kJumpRatio of that has jumped to another branch (sliding moves it by < 1e-2 d per Newton iteration in
// the examples, with the beam point; in a diverging attempt both move far).
constexpr double kJump = 0.1, kJumpRatio = 10;

// A pattern block reaches this many elements further toward where its point's closest point is moving, once
// it has moved by this share of its element since the last converged step (Coupling::collect_pairs).
constexpr int kDriftPadding = 1;
constexpr double kDriftShare = 1e-3;

std::vector<Eigen::Vector3d> current_points(const ShellBody& s, const Eigen::VectorXd& u, const solve::DofMap& dofs) {
  std::vector<Eigen::Vector3d> x = s.surface.control_points();
  for (int cp = 0; cp < s.num_control_points(); ++cp)
    for (int c = 0; c < 3; ++c) x[cp][c] += u[dofs.dof(s.block, cp, c)];
  return x;
}

}  // namespace

Coupling::Coupling(std::string name, std::shared_ptr<const laws::InteractionLaw> law, interaction::Formulation f,
                   interaction::FfTangent ff_tangent, const BeamBody& b, const ShellBody& s)
    : name_(std::move(name)), beam_(b), shell_(s), law_(std::move(law)), formulation_(f), ff_tangent_(ff_tangent),
      proximity_(s.surface) {
  const auto g = spline::gauss_legendre(b.gauss());
  double s_start = 0;
  for (std::size_t e = 0; e < b.elements.size(); ++e) {
    const auto& el = b.elements[e];
    const double j = 0.5 * (el.xi1 - el.xi0);
    for (std::size_t q = 0; q < g.points.size(); ++q) {
      const double xi = el.xi0 + (g.points[q] + 1.0) * j;
      // Eq. (5) integrates over the reference arc length: weight = Gauss weight x dxi/dxi_parent x J_B
      // (times the beam's share of a symmetric model).
      const double weight = b.share * g.weights[q] * j * b.curve.derivative(xi, 1).norm();
      quad_.push_back({static_cast<int>(e), xi, weight, s_start + spline::arc_length(b.curve, el.xi0, xi)});
    }
    s_start += spline::arc_length(b.curve, el.xi0, el.xi1);
  }
  projection_.resize(quad_.size());
  warm_.assign(quad_.size(), std::nullopt);
  last_ = warm_;
  beam_points_.assign(quad_.size(), Eigen::Vector3d::Zero());
  jump_.assign(quad_.size(), 0.0);
  points_.resize(quad_.size());
  soft_of_.assign(quad_.size(), -1);
  converged_curvature_.assign(quad_.size(), std::numeric_limits<double>::infinity());
}

void Coupling::enable_soft_minimum(double width, double below, double below_on_failure) {
  if (formulation_ != interaction::Formulation::RF2)
    throw std::invalid_argument("Coupling::enable_soft_minimum: RF2 only");
  if (!(below_on_failure >= below)) throw std::invalid_argument("Coupling::enable_soft_minimum: below_on_failure < below");
  soft_width_ = width;
  soft_below_ = below;
  soft_below_on_failure_ = below_on_failure;
}

double Coupling::beta() const { return 1.0 / (soft_width_ * law_->equilibrium_distance(1.0)); }

Eigen::Vector3d Coupling::beam_point(int i, const Eigen::VectorXd& u, const solve::DofMap& dofs) const {
  const auto& qp = quad_[i];
  return beam_.current(beam_.elements[qp.element].control_points, u, dofs).topRows<3>() *
         beam_.curve.basis(qp.xi, 0).R.row(0).transpose();
}

bool Coupling::update(const State& state) {
  const Eigen::VectorXd& u = state.u;
  const solve::DofMap& dofs = state.dofs;
  proximity_.update(current_points(shell_, u, dofs));
  const bool windows_changed = update_soft_windows();
  const int n = static_cast<int>(quad_.size());
  FirstError error;
#pragma omp parallel for schedule(dynamic, 16)
  for (int i = 0; i < n; ++i) error.run([&] {
    const Eigen::Vector3d r = beam_point(i, u, dofs);
    // Warm start from the last evaluation (the branch the point is on), kept unless a point 1e-3 closer
    // exists. After a failed attempt reject() has reset it to the last converged step.
    projection_[i] = proximity_.project(r, last_[i], kBranchMargin);
    const bool inside = projection_[i].where == interaction::ShellProximity::Projection::Where::interior;
    if (last_[i] && soft_of_[i] < 0 && inside) {
      const double moved = (proximity_.at(r, *last_[i]).point - projection_[i].point).norm();
      if (moved > kJump * projection_[i].distance && moved > kJumpRatio * (r - beam_points_[i]).norm())
        jump_[i] = std::max(jump_[i], moved / projection_[i].distance);
    }
    beam_points_[i] = r;
    last_[i] = inside ? std::optional<Eigen::Vector2d>(Eigen::Vector2d(projection_[i].u, projection_[i].v))
                      : std::nullopt;
  });
  error.rethrow();
  calibrate_soft_points(u, dofs);
  if (windows_changed) build_soft_elements();
  return collect_pairs();
}

int Coupling::drift_side(int i, int axis, double width) const {
  const auto k = static_cast<std::size_t>(i);
  if (!warm_[k]) return 0;
  const double moved = (axis == 0 ? projection_[k].u : projection_[k].v) - (*warm_[k])[axis];
  return moved > kDriftShare * width ? 1 : moved < -kDriftShare * width ? -1 : 0;
}

bool Coupling::collect_pairs() {
  // The sparsity pattern holds, for each beam element, the shell elements around the ones its points
  // project onto (a 3 x 3 block), so that points sliding across a shell element edge (a beam lying on an
  // element boundary does that at every iteration) do not force a new pattern and a new symbolic
  // factorisation. The pattern is rebuilt only when a point reaches a shell element outside it; the
  // block then reaches kDriftPadding elements further on each side toward which the point's closest
  // point has moved since the last converged step (by more than kDriftShare of its element), where a
  // fiber drifting over the shell will go next.
  const int n = static_cast<int>(quad_.size());
  const int n_u = shell_.surface.knots(0).num_elements(), n_v = shell_.surface.knots(1).num_elements();
  bool changed = soft_changed_;
  soft_changed_ = false;
  auto paired = [&](int i) {  // evaluated with its closest point (not soft)
    return soft_of_[i] < 0 && projection_[i].where == interaction::ShellProximity::Projection::Where::interior;
  };
  std::vector<int> found;  // the paired points
  for (int i = 0; i < n; ++i)
    if (paired(i)) {
      found.push_back(i);
      const auto key = std::make_pair(quad_[i].element, projection_[i].element);
      if (!std::binary_search(pairs_.begin(), pairs_.end(), key)) changed = true;
    }
  if (changed) {
    auto element_widths = [&](int axis) {  // each element's parameter length along the axis
      const spline::KnotVector& k = shell_.surface.knots(axis);
      std::vector<double> w;
      for (const int span : k.element_spans()) w.push_back(k.knots()[span + 1] - k.knots()[span]);
      return w;
    };
    const std::array<std::vector<double>, 2> width{element_widths(0), element_widths(1)};
    pairs_.clear();
    for (const int i : found) {
      const int eb = quad_[i].element, es = projection_[i].element;
      const int iu = es % n_u, iv = es / n_u;
      const std::array<int, 2> drift{drift_side(i, 0, width[0][iu]), drift_side(i, 1, width[1][iv])};
      auto low = [&](int axis) { return -1 - (drift[axis] < 0 ? kDriftPadding : 0); };
      auto high = [&](int axis) { return 1 + (drift[axis] > 0 ? kDriftPadding : 0); };
      for (int dv = low(1); dv <= high(1); ++dv)
        for (int du = low(0); du <= high(0); ++du)
          if (iu + du >= 0 && iu + du < n_u && iv + dv >= 0 && iv + dv < n_v)
            pairs_.emplace_back(eb, (iv + dv) * n_u + iu + du);
    }
    std::sort(pairs_.begin(), pairs_.end());
    pairs_.erase(std::unique(pairs_.begin(), pairs_.end()), pairs_.end());
  }
  pair_points_.assign(pairs_.size(), {});
  for (int i = 0; i < n; ++i) {
    if (!paired(i)) continue;
    const auto key = std::make_pair(quad_[i].element, projection_[i].element);
    const auto it = std::lower_bound(pairs_.begin(), pairs_.end(), key);
    pair_points_[it - pairs_.begin()].push_back(i);
  }
  return changed;
}

void Coupling::accept(const State& state) {
  for (std::size_t i = 0; i < quad_.size(); ++i)
    converged_curvature_[i] =
        soft_of_[i] < 0 && projection_[i].where == interaction::ShellProximity::Projection::Where::interior
            ? projection_[i].relative_curvature
            : std::numeric_limits<double>::infinity();
  request_soft_switches();
  warm_ = last_;
  std::fill(jump_.begin(), jump_.end(), 0.0);
  failed_jumps_.clear();
  // The points that switch here are calibrated at this converged state, so that the model after the switch
  // depends on the converged steps only (not on the predictor or the solver path of the next step).
  if (!update_soft_windows()) return;
  proximity_.update(current_points(shell_, state.u, state.dofs));
  calibrate_soft_points(state.u, state.dofs);
  build_soft_elements();
}

void Coupling::reject() {
  failed_jumps_.clear();
  std::vector<int> jumped;
  for (std::size_t i = 0; i < quad_.size(); ++i)
    if (jump_[i] > 0) {
      failed_jumps_.emplace_back(quad_[i].xi, jump_[i]);
      jumped.push_back(static_cast<int>(i));
    }
  // The soft minimum exists for this: the retry evaluates such points with it.
  if (soft_width_ > 0 && !jumped.empty()) request_switches_after_jumps(jumped);
  withdraw();
}

void Coupling::withdraw() {
  last_ = warm_;
  std::fill(jump_.begin(), jump_.end(), 0.0);
}

std::string Coupling::failure_hint() const {
  if (failed_jumps_.empty()) return {};
  std::string xi;
  double largest = 0;
  for (std::size_t k = 0; k < failed_jumps_.size(); ++k) {
    if (k < 4) xi += (k ? ", " : "") + fmt::format("{:.4g}", failed_jumps_[k].first);
    largest = std::max(largest, failed_jumps_[k].second);
  }
  if (failed_jumps_.size() > 4) xi += ", ...";
  return fmt::format(
      "In the last attempt the closest points of {} beam point(s) of '{}' (xi = {}) jumped across the shell "
      "(by up to {:.2g} times the distance) while the points barely moved: two shell regions are nearly "
      "equally close there, and the closest-point SBS residual is discontinuous (docs/examples.md, "
      "\"The beam end and the closest-point projection\"){}",
      failed_jumps_.size(), name_, xi, largest,
      soft_width_ > 0 ? ""
                      : ". An RF2 interaction's 'soft_minimum' key evaluates such points with a smooth "
                        "soft-minimum distance (docs/interaction.md, section 7)");
}

std::vector<std::vector<int>> Coupling::element_dofs(const solve::DofMap& dofs) const {
  std::vector<std::vector<int>> out;
  out.reserve(pairs_.size());
  auto append = [&](std::vector<int>& d, const std::vector<int>& beam_cps, const std::vector<int>& shell_cps) {
    for (int cp : beam_cps)
      for (int c = 0; c < 4; ++c) d.push_back(dofs.dof(beam_.block, cp, c));
    for (int cp : shell_cps)
      for (int c = 0; c < 3; ++c) d.push_back(dofs.dof(shell_.block, cp, c));
  };
  for (const auto& [eb, es] : pairs_) {
    std::vector<int> d;
    append(d, beam_.elements[eb].control_points, shell_.element_control_points[es]);
    out.push_back(std::move(d));
  }
  for (const SoftGroup& g : soft_groups_) {
    std::vector<int> d;
    append(d, g.beam_cps, g.shell_cps);
    out.push_back(std::move(d));
  }
  return out;
}

double Coupling::evaluate(const State& state, ElementSink& sink, Status& status) {
  for (std::size_t i = 0; i < quad_.size(); ++i) {
    auto& out = points_[i];
    out = CouplingPoint{};
    out.xi = quad_[i].xi;
    out.s = quad_[i].s;
  }
  bool bad = false;
  double energy = evaluate_pairs(state, sink, bad);
  energy += evaluate_soft_points(state, sink, bad);
  // The model sums the returned energies over the processes; energy_ (output) is the whole coupling's.
  energy_ = energy;
  if (sink.distributed()) share_points(sink, energy_);
  classify_points();
  if (bad)
    status.merge(Status::invalid("a beam point of interaction '" + name_ +
                                 "' lies inside the plate, where the interaction law has no value"));
  return energy;
}

double Coupling::evaluate_pairs(const State& state, ElementSink& sink, bool& bad) {
  const Eigen::VectorXd& u = state.u;
  const solve::DofMap& dofs = state.dofs;
  const bool with_tangent = sink.with_tangent();
  const int n_pairs = static_cast<int>(pairs_.size());
  const bool need_third = formulation_ == interaction::Formulation::FF && ff_tangent_ == interaction::FfTangent::exact;
  OrderedSum sum;  // static schedule, ordered sum: the same bits in every run with this thread count
  FirstError error;
#pragma omp parallel reduction(|| : bad)
  {
    double energy = 0;
    Eigen::VectorXd r;
    Eigen::MatrixXd k;
    interaction::PairPoint p;
    sink.for_each_element(n_pairs, 4, [&](int k_pair) { error.run([&] {
      // A neighbour kept in the pattern only, or a pair another process evaluates.
      if (pair_points_[k_pair].empty() || !sink.owns(k_pair)) return;
      const auto [eb, es] = pairs_[k_pair];
      const auto& bel = beam_.elements[eb];
      const auto& sel = shell_.elements[es];
      const auto qb = beam_.current(bel.control_points, u, dofs);
      p.beam_x = qb.topRows<3>();
      p.shell_x = shell_.current(shell_.element_control_points[es], u, dofs);
      const int n = 4 * static_cast<int>(bel.control_points.size()) + 3 * static_cast<int>(p.shell_x.cols());
      r.setZero(n);
      if (with_tangent) k.setZero(n, n);
      for (int i : pair_points_[k_pair]) {
        const auto& qp = quad_[i];
        const auto& proj = projection_[i];
        p.beam_basis = beam_.curve.basis(qp.xi, 1).R.topRows(2);
        p.shell_basis = shell_.surface.basis_in(sel.span_u, sel.span_v, proj.u, proj.v).R;
        if (need_third) p.shell_basis3 = spline::basis3_in(shell_.surface, sel.span_u, sel.span_v, proj.u, proj.v).R;
        p.weight = qp.weight;
        try {
          double e = 0;
          const auto res = interaction::add_sbs_point(*law_, formulation_, ff_tangent_, p, &e, &r,
                                                      with_tangent ? &k : nullptr);
          energy += e;
          auto& out = points_[i];
          out.active = true;
          out.distance = res.distance;
          out.cos_alpha = res.cos_alpha;
          out.energy_density = e / qp.weight;
          out.force = -res.force;  // the kernel's f (Eq. 73) acts on delta u_B with a plus: the physical force is -f
          out.position = p.beam_x * p.beam_basis.row(0).transpose();
        } catch (const std::domain_error&) {
          bad = true;  // the beam has entered the plate: no potential there; Newton must cut back
        }
      }
      sink.add(k_pair, r, with_tangent ? &k : nullptr);
    }); });
    sum.set(energy);
  }
  error.rethrow();
  return sum.total();
}

void Coupling::share_points(const ElementSink& sink, double& energy) {
  // Each point was evaluated by one process (the owner of its pair or of the soft element) and is zero
  // elsewhere, so the sum over the processes is its value. xi and s are set everywhere and not summed.
  constexpr int kFields = 11;
  std::vector<double> data(points_.size() * kFields + 1);
  for (std::size_t i = 0; i < points_.size(); ++i) {
    const CouplingPoint& p = points_[i];
    double* d = data.data() + i * kFields;
    d[0] = p.active ? 1.0 : 0.0;
    d[1] = p.soft ? 1.0 : 0.0;
    d[2] = p.distance;
    d[3] = p.cos_alpha - 1.0;  // zero where not evaluated (the default is 1)
    d[4] = p.energy_density;
    for (int c = 0; c < 3; ++c) {
      d[5 + c] = p.position[c];
      d[8 + c] = p.force[c];
    }
  }
  data.back() = energy;
  sink.sum(data);
  for (std::size_t i = 0; i < points_.size(); ++i) {
    CouplingPoint& p = points_[i];
    const double* d = data.data() + i * kFields;
    p.active = d[0] > 0.5;
    p.soft = d[1] > 0.5;
    p.distance = d[2];
    p.cos_alpha = d[3] + 1.0;
    p.energy_density = d[4];
    for (int c = 0; c < 3; ++c) {
      p.position[c] = d[5 + c];
      p.force[c] = d[8 + c];
    }
  }
  energy = data.back();
}

void Coupling::classify_points() {
  using Where = interaction::ShellProximity::Projection::Where;
  lost_points_ = 0;
  for (std::size_t i = 0; i < quad_.size(); ++i) {
    auto& p = points_[i];
    if (p.active) {
      p.status = p.soft ? CouplingPoint::Status::soft : CouplingPoint::Status::interior;
      continue;
    }
    // Not evaluated: off the patch, or no projection (a point whose kernel threw makes the state invalid).
    p.status = projection_[i].where == Where::outside ? CouplingPoint::Status::outside : CouplingPoint::Status::failed;
    ++lost_points_;
  }
}

Eigen::Vector3d Coupling::total_force() const {
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < quad_.size(); ++i)
    if (points_[i].active) f += quad_[i].weight * points_[i].force;
  return f;
}

}  // namespace fibrane::model
