#include "model/beam_beam.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "common/error.hpp"
#include "common/parallel_errors.hpp"
#include "interaction/section_beam.hpp"
#include "linalg/dof_map.hpp"
#include "model/beam_body.hpp"
#include "model/ordered_sum.hpp"
#include "model/saved_state.hpp"
#include "spline/quadrature.hpp"

namespace fibrane::model {
namespace {

constexpr double kNone = std::numeric_limits<double>::quiet_NaN();


bool same_radius(double a, double b) { return std::abs(a - b) <= 1e-12 * std::max(a, b); }

}  // namespace

BeamBeamInteraction::BeamBeamInteraction(std::string name, std::shared_ptr<const laws::SectionCylinderLaw> law,
                                         const BeamBody& a, const BeamBody& b, double exclusion,
                                         double contact_gap, double end_taper)
    : name_(std::move(name)), law_(std::move(law)), swapped_(law_->swapped()), fiber_{&a, &b}, self_(&a == &b),
      exclusion_(exclusion), contact_gap_(std::isnan(contact_gap) ? default_contact_gap(*law_) : contact_gap),
      end_taper_(end_taper) {
  if (!same_radius(a.section_radius, law_->radius_a()) || !same_radius(b.section_radius, law_->radius_b()))
    throw std::invalid_argument("beam-beam interaction '" + name_ +
                                "': the law's radii must be the fibers' circular section radii");
  if (self_ && !(exclusion_ > 0))
    throw std::invalid_argument("beam-beam interaction '" + name_ + "': self-interaction needs an exclusion length");
  if (!std::isnan(contact_gap_) && !(contact_gap_ > 0 && std::isfinite(contact_gap_)))
    throw std::invalid_argument("beam-beam interaction '" + name_ + "': the contact gap must be positive and finite");
  if (!(end_taper_ >= 0 && end_taper_ < 0.5))
    throw std::invalid_argument("beam-beam interaction '" + name_ + "': the end taper must be in [0, 0.5)");
  passes_ = self_ ? std::vector<Pass>{{0, 1}} : std::vector<Pass>{{0, 1}, {1, 0}};
  for (int f = 0; f < 2; ++f) {
    const BeamBody& body = *fiber_[f];
    const auto g = spline::gauss_legendre(body.gauss());
    double s = 0;
    element_start_[f].clear();
    for (std::size_t e = 0; e < body.elements.size(); ++e) {
      const auto& el = body.elements[e];
      element_start_[f].push_back(s);
      if (f == 0 || !self_) {
        const double j = 0.5 * (el.xi1 - el.xi0);
        for (std::size_t q = 0; q < g.points.size(); ++q) {
          const double xi = el.xi0 + (g.points[q] + 1.0) * j;
          // The half pass's 1/2 x the fiber's share x Gauss weight x dxi/dparent x reference J (Eq. 4).
          const double length = g.weights[q] * j * body.curve.derivative(xi, 1).norm();
          const double weight = 0.5 * body.share * length;
          const double s_q = s + spline::arc_length(body.curve, el.xi0, xi);
          quad_[f].push_back(
              {static_cast<int>(e), xi, weight, s_q, length, body.curve.basis(xi, 0).R.row(0).transpose()});
        }
      }
      s += spline::arc_length(body.curve, el.xi0, el.xi1);
    }
    element_start_[f].push_back(s);
    warm_[f].assign(quad_[f].size(), kNone);
    accepted_[f] = warm_[f];
    target_element_[f].assign(quad_[f].size(), -1);
    in_pair_[f].assign(quad_[f].size(), 0);
    points_[f].resize(quad_[f].size());
    for (std::size_t i = 0; i < quad_[f].size(); ++i) {
      points_[f][i].xi = quad_[f][i].xi;
      points_[f][i].s = quad_[f][i].s;
      points_[f][i].weight = quad_[f][i].weight;
      points_[f][i].length = quad_[f][i].length;
    }
  }
}

double BeamBeamInteraction::search_distance() const {
  const double radii = law_->radius_a() + law_->radius_b();
  return radii + (std::isfinite(law_->cutoff_gap()) ? law_->cutoff_gap() : radii);
}

std::vector<Eigen::AlignedBox3d> BeamBeamInteraction::element_boxes(int f) const {
  std::vector<Eigen::AlignedBox3d> boxes;
  for (const auto& el : fiber_[f]->elements) {
    Eigen::AlignedBox3d box;
    for (int cp : el.control_points) box.extend(cps_[f][cp]);
    boxes.push_back(box);
  }
  return boxes;
}

interaction::EndTaper BeamBeamInteraction::taper_at(int f, double xi) const {
  if (!(end_taper_ > 0)) return {};
  const BeamBody& body = *fiber_[f];
  const int e = body.element_of(xi);
  const double s = element_start_[f][e] + spline::arc_length(body.curve, body.elements[e].xi0, xi);
  const double length = element_start_[f].back();
  // ds/dxi = |C'| of the reference axis, d2s/dxi2 = C'.C'' / |C'|.
  const Eigen::Vector3d d1 = body.curve.derivative(xi, 1), d2 = body.curve.derivative(xi, 2);
  const double j = d1.norm(), j_xi = d1.dot(d2) / j;
  if (s <= 0.5 * length) return {s, j, j_xi, end_taper_ * length};
  return {length - s, -j, -j_xi, end_taper_ * length};
}

bool BeamBeamInteraction::excluded(int point, int target) const {
  if (!self_) return false;
  const Quad& q = quad_[0][point];
  const auto& own = fiber_[0]->elements[q.element].control_points;
  for (int cp : fiber_[0]->elements[target].control_points)
    if (std::find(own.begin(), own.end(), cp) != own.end()) return true;
  const double lo = element_start_[0][target], hi = element_start_[0][target + 1];
  const double gap = q.s < lo ? lo - q.s : (q.s > hi ? q.s - hi : 0.0);
  return gap < exclusion_;
}

void BeamBeamInteraction::project(int pass, int i, std::vector<int>& candidates) {
  const auto [source, target] = passes_[pass];
  const BeamBody& src = *fiber_[source];
  const BeamBody& tgt = *fiber_[target];
  const Quad& q = quad_[source][i];
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  const auto& cps_of = src.elements[q.element].control_points;
  for (std::size_t j = 0; j < cps_of.size(); ++j) x += q.basis[static_cast<int>(j)] * cps_[source][cps_of[j]];
  FiberPoint& out = points_[source][i];
  out.position = x;
  candidates.clear();
  tree_[target].near_point(x, search_distance(), candidates);
  const auto& cps = cps_[target];
  auto axis = [&](double xi) {
    const auto basis = tgt.curve.basis(xi, 3);
    Eigen::Matrix<double, 3, 4> r = Eigen::Matrix<double, 3, 4>::Zero();
    for (int j = 0; j < basis.R.cols(); ++j)
      for (int k = 0; k < 4; ++k) r.col(k) += basis.R(k, j) * cps[basis.first + j];
    return r;
  };
  // Branch and bound: an element's box holds it, so an element whose box is farther than the best
  // distance found so far cannot hold a closer point (nearest boxes first).
  std::vector<std::pair<double, int>> order;
  for (int e : candidates)
    if (!excluded(i, e)) order.emplace_back(tree_[target].box(e).exteriorDistance(x), e);
  std::sort(order.begin(), order.end());
  double best = std::numeric_limits<double>::infinity(), best_xi = kNone;
  for (const auto& [box_distance, e] : order) {
    if (box_distance >= best) break;
    const auto& el = tgt.elements[e];
    const double warm = warm_[source][i];
    double xi = warm >= el.xi0 && warm <= el.xi1 ? warm : 0.5 * (el.xi0 + el.xi1);
    if (!interaction::closest_on_axis(x, axis, el.xi0, el.xi1, xi)) continue;
    const double d = (x - axis(xi).col(0)).norm();
    if (d < best) {
      best = d;
      best_xi = xi;
    }
  }
  out.found = std::isfinite(best);
  warm_[source][i] = best_xi;
  // The element whose basis curve.basis() uses at xi (the knot-span rule decides at element ends).
  target_element_[source][i] = out.found ? tgt.element_of(best_xi) : -1;
  if (out.found && excluded(i, target_element_[source][i])) {
    out.found = false;
    target_element_[source][i] = -1;
  }
  out.target_xi = out.found ? best_xi : 0.0;
  out.distance = out.found ? best : 0.0;
}

bool BeamBeamInteraction::update(const State& state) {
  for (int f = 0; f < 2; ++f) {
    const BeamBody& body = *fiber_[f];
    cps_[f] = body.curve.control_points();
    for (int cp = 0; cp < body.num_control_points(); ++cp)
      for (int c = 0; c < 3; ++c) cps_[f][cp][c] += state.u[state.dofs.dof(body.block, cp, c)];
    const auto boxes = element_boxes(f);
    if (tree_[f].size() != static_cast<int>(boxes.size())) tree_[f].rebuild(boxes);
    else tree_[f].refit(boxes);
  }
  FirstError error;
  for (int pass = 0; pass < static_cast<int>(passes_.size()); ++pass) {
    const int n = static_cast<int>(quad_[passes_[pass].source].size());
#pragma omp parallel
    {
      std::vector<int> candidates;
#pragma omp for schedule(static)
      for (int i = 0; i < n; ++i) error.run([&] { project(pass, i, candidates); });
    }
  }
  error.rethrow();
  return collect_pairs();
}

double BeamBeamInteraction::evaluate_pair(int pair, bool with_tangent, Eigen::VectorXd& r, Eigen::MatrixXd& k,
                                          Status& status, bool& any_active) {
  const auto [e0, e1] = pairs_[pair];
  const int n0 = static_cast<int>(fiber_[0]->elements[e0].control_points.size());
  const int n1 = static_cast<int>(fiber_[1]->elements[e1].control_points.size());
  const int n = 4 * (n0 + n1);
  r.setZero(n);
  if (with_tangent) k.setZero(n, n);
  double energy = 0;
  Eigen::VectorXd rp;
  Eigen::MatrixXd kp;
  for (const auto& [pass, i] : pair_points_[pair]) {
    const auto [source, target] = passes_[pass];
    const BeamBody& src = *fiber_[source];
    const BeamBody& tgt = *fiber_[target];
    const Quad& q = quad_[source][i];
    FiberPoint& out = points_[source][i];
    const auto& src_cps = src.elements[q.element].control_points;
    const auto& tgt_cps = tgt.elements[target_element_[source][i]].control_points;
    Eigen::Matrix3Xd xs(3, src_cps.size()), xt(3, tgt_cps.size());
    for (std::size_t j = 0; j < src_cps.size(); ++j) xs.col(j) = cps_[source][src_cps[j]];
    for (std::size_t j = 0; j < tgt_cps.size(); ++j) xt.col(j) = cps_[target][tgt_cps[j]];
    const Eigen::Matrix<double, 2, Eigen::Dynamic> bs = src.curve.basis(q.xi, 1).R;
    const Eigen::Matrix<double, 4, Eigen::Dynamic> bt = tgt.curve.basis(out.target_xi, 3).R;
    rp.resize(0);
    kp.resize(0, 0);
    interaction::SectionBeamResult res;
    try {
      res = interaction::add_section_beam_point(source == 0 ? *law_ : swapped_, bs, xs, bt, xt, q.weight, &energy,
                                                &rp, with_tangent ? &kp : nullptr, taper_at(target, out.target_xi));
    } catch (const std::domain_error& e) {
      status.merge(Status::invalid("beam-beam interaction '" + name_ + "': " + e.what()));
      continue;
    }
    out.active = res.active;
    out.gap = res.gap;
    out.energy_density = res.energy;
    out.force = -res.gradient.head<3>();
    if (!res.active) continue;
    any_active = true;
    // Local order [source | target] -> the pair's [fiber 0 | fiber 1].
    const int ns = 4 * static_cast<int>(src_cps.size());
    std::vector<int> map(rp.size());
    for (int j = 0; j < static_cast<int>(map.size()); ++j)
      map[j] = source == 0 ? j : (j < ns ? 4 * n0 + j : j - ns);
    for (int j = 0; j < static_cast<int>(map.size()); ++j) {
      r[map[j]] += rp[j];
      if (with_tangent)
        for (int l = 0; l < static_cast<int>(map.size()); ++l) k(map[j], map[l]) += kp(j, l);
    }
  }
  return energy;
}

double BeamBeamInteraction::evaluate(const State& /*state*/, ElementSink& sink, Status& status) {
  const bool with_tangent = sink.with_tangent();
  const int n_pairs = static_cast<int>(pairs_.size());
  for (int f = 0; f < 2; ++f)
    for (std::size_t i = 0; i < points_[f].size(); ++i) {
      FiberPoint& p = points_[f][i];
      p.active = false;
      p.energy_density = 0;
      p.force.setZero();
      if (in_pair_[f][i]) p.gap = 0;  // set by the pair's owner
    }
  std::vector<Eigen::Matrix<double, 6, 1>> pair_force(pairs_.size(), Eigen::Matrix<double, 6, 1>::Zero());
  std::vector<Status> pair_status(pairs_.size());
  OrderedSum sum;
  FirstError error;
#pragma omp parallel
  {
    double energy = 0;
    Eigen::VectorXd r;
    Eigen::MatrixXd k;
#pragma omp for schedule(static)
    for (int p = 0; p < n_pairs; ++p) error.run([&] {
      if (!sink.owns(p) || pair_points_[p].empty()) return;
      bool active = false;
      energy += evaluate_pair(p, with_tangent, r, k, pair_status[p], active);
      if (!active) return;  // all its points beyond the cut-off: nothing to add
      const int n0 = 4 * static_cast<int>(fiber_[0]->elements[pairs_[p].first].control_points.size());
      for (int j = 0; j < r.size(); j += 4) pair_force[p].segment<3>(j < n0 ? 0 : 3) -= r.segment<3>(j);
      sink.add(p, r, with_tangent ? &k : nullptr);
    });
    sum.set(energy);
  }
  error.rethrow();
  for (const auto& s : pair_status) status.merge(s);
  energy_ = sum.total();
  force_[0].setZero();
  force_[1].setZero();
  for (const auto& f : pair_force) {
    force_[0] += f.head<3>();
    force_[1] += f.tail<3>();
  }
  if (self_) force_[1].setZero();
  if (sink.distributed()) {  // every point and pair was evaluated by one process: sum the output data
    std::vector<double> data{energy_};
    for (int f = 0; f < 2; ++f)
      for (int c = 0; c < 3; ++c) data.push_back(force_[f][c]);
    for (int f = 0; f < 2; ++f)
      for (std::size_t i = 0; i < points_[f].size(); ++i) {
        const FiberPoint& p = points_[f][i];
        if (!in_pair_[f][i]) continue;
        data.push_back(p.active ? 1.0 : 0.0);
        data.push_back(p.energy_density);
        for (int c = 0; c < 3; ++c) data.push_back(p.force[c]);
        data.push_back(p.gap);
      }
    sink.sum(data);
    std::size_t at = 0;
    energy_ = data[at++];
    for (int f = 0; f < 2; ++f)
      for (int c = 0; c < 3; ++c) force_[f][c] = data[at++];
    for (int f = 0; f < 2; ++f)
      for (std::size_t i = 0; i < points_[f].size(); ++i) {
        FiberPoint& p = points_[f][i];
        if (!in_pair_[f][i]) continue;
        p.active = data[at++] > 0.5;
        p.energy_density = data[at++];
        for (int c = 0; c < 3; ++c) p.force[c] = data[at++];
        p.gap = data[at++];
      }
  }
  return sum.total();
}

int BeamBeamInteraction::interacting_points() const {
  int n = 0;
  for (int f = 0; f < 2; ++f)
    for (const auto& p : points_[f]) n += p.active;
  return n;
}

int BeamBeamInteraction::interacting_pairs() const {
  int n = 0;
  for (std::size_t p = 0; p < pairs_.size(); ++p) {
    bool any = false;
    for (const auto& [pass, i] : pair_points_[p]) any = any || points_[passes_[pass].source][i].active;
    n += any;
  }
  return n;
}

double BeamBeamInteraction::minimum_gap() const {
  double g = std::numeric_limits<double>::infinity();
  for (int f = 0; f < 2; ++f)
    for (const auto& p : points_[f])
      if (p.found) g = std::min(g, p.gap);
  return g;
}

double BeamBeamInteraction::contact_length() const {
  if (std::isnan(contact_gap_)) return kNone;
  double length = 0;
  for (const auto& p : points_[0])
    if (p.found && p.gap < contact_gap_) length += p.length;
  return length;
}

void BeamBeamInteraction::accept(const State& /*state*/) {
  accepted_[0] = warm_[0];
  accepted_[1] = warm_[1];
}

void BeamBeamInteraction::reject() {
  warm_[0] = accepted_[0];
  warm_[1] = accepted_[1];
}

std::vector<double> BeamBeamInteraction::save_state() const {
  StateWriter w;
  for (int f = 0; f < 2; ++f) {
    w.add(static_cast<double>(accepted_[f].size()));
    for (double xi : accepted_[f]) w.add(xi);
  }
  w.add(static_cast<double>(pairs_.size()));
  for (const auto& [e0, e1] : pairs_) {
    w.add(static_cast<double>(e0));
    w.add(static_cast<double>(e1));
  }
  return w.take();
}

void BeamBeamInteraction::restore_state(const std::vector<double>& state) {
  StateReader r(state, "interaction '" + name_ + "'");
  for (int f = 0; f < 2; ++f) {
    if (r.next_int() != static_cast<int>(accepted_[f].size()))
      throw InputError("checkpoint: interaction '" + name_ + "' has another number of quadrature points");
    for (double& xi : accepted_[f]) xi = r.next();
    warm_[f] = accepted_[f];
  }
  const int n = r.next_int();
  if (n < 0) throw InputError("checkpoint: interaction '" + name_ + "' has a negative number of pairs");
  std::vector<std::pair<int, int>> pairs(static_cast<std::size_t>(n));
  for (auto& [e0, e1] : pairs) {
    e0 = r.next_int();
    e1 = r.next_int();
    if (e0 < 0 || e1 < 0 || e0 >= static_cast<int>(fiber_[0]->elements.size()) ||
        e1 >= static_cast<int>(fiber_[1]->elements.size()))
      throw InputError("checkpoint: interaction '" + name_ + "' has a pair of elements the fibers do not have");
  }
  r.finish();
  if (!std::is_sorted(pairs.begin(), pairs.end()))
    throw InputError("checkpoint: interaction '" + name_ + "' has unsorted pairs");
  pairs_ = std::move(pairs);
  pair_points_.assign(pairs_.size(), {});
}

}  // namespace fibrane::model
