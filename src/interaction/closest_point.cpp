#include "interaction/closest_point.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

namespace fibrane::interaction {
namespace {

// Position, tangent vectors g_a and their derivatives g_ab at one parameter point.
struct SurfaceJet {
  Eigen::Vector3d r, g1, g2, g11, g12, g22;
};

SurfaceJet evaluate(const spline::NurbsSurface& s, const std::vector<Eigen::Vector3d>& x, double u,
                    double v) {
  // Per thread: the projections run in the interaction's parallel loops.
  thread_local spline::SurfaceBasis b;
  thread_local Eigen::MatrixXd nu, nv;
  s.basis(u, v, b, nu, nv);
  SurfaceJet j{};
  j.r.setZero(), j.g1.setZero(), j.g2.setZero(), j.g11.setZero(), j.g12.setZero(), j.g22.setZero();
  for (std::size_t a = 0; a < b.indices.size(); ++a) {
    const Eigen::Vector3d& xa = x[b.indices[a]];
    j.r += b.R(0, a) * xa;
    j.g1 += b.R(1, a) * xa;
    j.g2 += b.R(2, a) * xa;
    j.g11 += b.R(3, a) * xa;
    j.g12 += b.R(4, a) * xa;
    j.g22 += b.R(5, a) * xa;
  }
  return j;
}

// Sample k of the 3 x 3 grid (corners, edge midpoints, centre) of an element's parameter box.
std::pair<double, double> sample_parameters(const spline::SurfaceElement& e, int k) {
  return {e.u0 + 0.5 * (k % 3) * (e.u1 - e.u0), e.v0 + 0.5 * (k / 3) * (e.v1 - e.v0)};
}

constexpr int kMaxIterations = 60;
constexpr int kMaxEscapes = 4;

// C_ab = g_a . g_b - D . g_ab (Eq. C3) for D = p - r: the Hessian of f = |p - r|^2 / 2 in theta.
Eigen::Matrix2d distance_hessian(const Eigen::Vector3d& D, const SurfaceJet& s) {
  Eigen::Matrix2d C;
  C << s.g1.dot(s.g1) - D.dot(s.g11), s.g1.dot(s.g2) - D.dot(s.g12), s.g1.dot(s.g2) - D.dot(s.g12),
      s.g2.dot(s.g2) - D.dot(s.g22);
  return C;
}

double f_of(const Eigen::Vector3d& p, const SurfaceJet& s) { return 0.5 * (p - s.r).squaredNorm(); }

// Eigenvalues of C_ab relative to the metric g_ab (C e = lambda g e, e g-normalised: |e^a g_a| = 1):
// lambda = 1 - d kappa along the principal directions for a point at distance d on the side of curvature
// kappa, so lambda <= 0 means the point sits at or beyond a centre of curvature.
Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix2d> relative_curvature(const SurfaceJet& s,
                                                                            const Eigen::Matrix2d& C) {
  Eigen::Matrix2d G;
  G << s.g1.dot(s.g1), s.g1.dot(s.g2), s.g1.dot(s.g2), s.g2.dot(s.g2);
  return Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix2d>(C, G);
}

// From a stationary point theta of f = |p - r|^2 / 2 where the Hessian C_ab has the negative eigenvalue
// lambda (eigenvector e), a step along +-e lowers f by ~ |lambda| s^2 / 2 for a surface step of length s.
// The sign keeps the step inside the parameter box (a saddle on the mirror edge u = 0 escapes to u > 0);
// the length starts at the distance |p - r| (the scale on which a groove's minimum lies) and is halved
// until f falls below f0 (any decrease: a threshold would make the choice between the saddle and the
// minimum beside it depend on the warm start). nullopt: no decrease (the saddle is flat to round-off).
std::optional<Eigen::Vector2d> escape_saddle(const spline::NurbsSurface& surface,
                                             const std::vector<Eigen::Vector3d>& x, const Eigen::Vector3d& p,
                                             const Eigen::Vector2d& theta, Eigen::Vector2d e,
                                             const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, double f0) {
  auto blocked = [&](const Eigen::Vector2d& d) {
    int n = 0;
    for (int a = 0; a < 2; ++a) n += (theta[a] <= lo[a] && d[a] < 0) || (theta[a] >= hi[a] && d[a] > 0);
    return n;
  };
  if (blocked(-e) < blocked(e)) e = -e;
  const double distance = std::sqrt(2 * f0);
  for (double length = distance; length > 1e-8 * distance; length *= 0.5) {
    const Eigen::Vector2d next = (theta + length * e).cwiseMax(lo).cwiseMin(hi);
    const spline::SurfaceBasis b = surface.basis(next[0], next[1]);
    Eigen::Vector3d r = Eigen::Vector3d::Zero();
    for (std::size_t a = 0; a < b.indices.size(); ++a) r += b.R(0, a) * x[b.indices[a]];
    if (0.5 * (p - r).squaredNorm() < f0) return next;
  }
  return std::nullopt;
}

// Backtracking along a Newton step: the first of theta + step / 2^k (k < 40, clipped to the parameter box)
// where f does not exceed f0 beyond round-off (slack: an absolute allowance); its surface jet in `trial`.
Eigen::Vector2d backtrack(const spline::NurbsSurface& surface, const std::vector<Eigen::Vector3d>& x,
                          const Eigen::Vector3d& p, const Eigen::Vector2d& theta, const Eigen::Vector2d& step,
                          const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, double f0, double slack,
                          SurfaceJet& trial) {
  double scale = 1.0;
  Eigen::Vector2d next;
  for (int k = 0; k < 40; ++k, scale *= 0.5) {
    next = (theta + scale * step).cwiseMax(lo).cwiseMin(hi);
    trial = evaluate(surface, x, next[0], next[1]);
    if (f_of(p, trial) <= f0 * (1 + 1e-14) + slack) break;
  }
  return next;
}

constexpr int kLeafSize = 4;

// Newton matrix C where it is positive definite. Else C with its eigenvalues (relative to the metric
// g_ab) replaced by their absolute values, floored: still a descent direction, but one that keeps
// Newton's rate along the directions of positive curvature, so the iterate quickly reaches the
// stationary point from which escape_saddle leaves along the negative one.
Eigen::Matrix2d newton_matrix(const SurfaceJet& s, const Eigen::Matrix2d& C) {
  Eigen::Matrix2d M = C;
  if (!(M.determinant() > 0 && M(0, 0) > 0)) {
    Eigen::Matrix2d G;
    G << s.g1.dot(s.g1), s.g1.dot(s.g2), s.g1.dot(s.g2), s.g2.dot(s.g2);
    const auto eig = relative_curvature(s, C);
    if (eig.info() == Eigen::Success) {
      const Eigen::Matrix2d GE = G * eig.eigenvectors();  // C = G E Lambda E^T G with E^T G E = 1
      M = GE * eig.eigenvalues().cwiseAbs().cwiseMax(1e-2).asDiagonal() * GE.transpose();
    } else {
      M = G + 1e-14 * G.trace() * Eigen::Matrix2d::Identity();
    }
  }
  return M;
}

// The Newton step M^-1 h in the parameters whose bounds are not active (active ones stay put).
Eigen::Vector2d projected_newton_step(const Eigen::Matrix2d& M, const Eigen::Vector2d& h, const bool active[2]) {
  Eigen::Vector2d step = Eigen::Vector2d::Zero();
  if (active[0] && active[1]) return step;
  if (active[0]) {
    step[1] = h[1] / M(1, 1);
  } else if (active[1]) {
    step[0] = h[0] / M(0, 0);
  } else {
    step = M.ldlt().solve(h);
  }
  return step;
}

// The closest point's parameters, position, distance, normal and relative curvature, for the point p whose
// projection ended at theta (surface values s there).
void describe_closest_point(ShellProximity::Projection& out, const Eigen::Vector3d& p, const Eigen::Vector2d& theta,
                            const SurfaceJet& s) {
  out.u = theta[0];
  out.v = theta[1];
  out.point = s.r;
  const Eigen::Vector3d D = p - s.r;
  if (const auto eig = relative_curvature(s, distance_hessian(D, s)); eig.info() == Eigen::Success)
    out.relative_curvature = eig.eigenvalues()[0];
  out.distance = D.norm();
  out.normal = out.distance > 0 ? Eigen::Vector3d(D / out.distance) : Eigen::Vector3d::Zero();
}

}  // namespace

ShellProximity::ShellProximity(const spline::NurbsSurface& reference)
    : surface_(reference), elements_(reference.elements()) {
  const int p = surface_.degree(0), q = surface_.degree(1);
  element_points_.reserve(elements_.size());
  const auto spans_u = surface_.knots(0).element_spans();
  const auto spans_v = surface_.knots(1).element_spans();
  element_of_span_u_.assign(surface_.knots(0).knots().size(), -1);
  element_of_span_v_.assign(surface_.knots(1).knots().size(), -1);
  for (std::size_t i = 0; i < spans_u.size(); ++i) element_of_span_u_[spans_u[i]] = static_cast<int>(i);
  for (std::size_t j = 0; j < spans_v.size(); ++j)
    element_of_span_v_[spans_v[j]] = static_cast<int>(j * spans_u.size());
  for (const spline::SurfaceElement& e : elements_) {
    std::vector<int> ids;
    for (int j = e.span_v - q; j <= e.span_v; ++j)
      for (int i = e.span_u - p; i <= e.span_u; ++i) ids.push_back(surface_.index(i, j));
    Eigen::Matrix<double, 9, Eigen::Dynamic> samples(9, static_cast<int>(ids.size()));
    for (int k = 0; k < 9; ++k) {
      const auto [u, v] = sample_parameters(e, k);
      samples.row(k) = surface_.basis_in(e.span_u, e.span_v, u, v).R.row(0);
    }
    element_points_.push_back(std::move(ids));
    element_samples_.push_back(std::move(samples));
  }
  update(reference.control_points());
}

int ShellProximity::element_at(double u, double v) const {
  return element_of_span_u_[surface_.knots(0).find_span(u)] +
         element_of_span_v_[surface_.knots(1).find_span(v)];
}

void ShellProximity::update(const std::vector<Eigen::Vector3d>& current_control_points) {
  if (static_cast<int>(current_control_points.size()) != surface_.num_control_points())
    throw std::invalid_argument("ShellProximity::update: control point count does not match the surface");
  points_ = current_control_points;
  boxes_.assign(elements_.size(), Eigen::AlignedBox3d());
  Eigen::AlignedBox3d all;
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    for (int id : element_points_[e]) boxes_[e].extend(points_[id]);
    all.extend(boxes_[e]);
  }
  length_scale_ = std::max(all.diagonal().norm(), std::numeric_limits<double>::min());
  order_.resize(elements_.size());
  for (std::size_t e = 0; e < order_.size(); ++e) order_[e] = static_cast<int>(e);
  nodes_.clear();
  nodes_.reserve(2 * elements_.size());
  build(0, static_cast<int>(order_.size()));
}

// Median split of the element boxes along the longest extent of their centres.
int ShellProximity::build(int first, int count) {
  const int id = static_cast<int>(nodes_.size());
  nodes_.push_back(Node{});
  Eigen::AlignedBox3d box, centres;
  for (int k = first; k < first + count; ++k) {
    box.extend(boxes_[order_[k]]);
    centres.extend(boxes_[order_[k]].center());
  }
  nodes_[id].box = box;
  nodes_[id].first = first;
  nodes_[id].count = count;
  if (count <= kLeafSize) return id;
  int axis = 0;
  centres.diagonal().maxCoeff(&axis);
  const int half = count / 2;
  std::nth_element(order_.begin() + first, order_.begin() + first + half, order_.begin() + first + count,
                   [&](int a, int b) { return boxes_[a].center()[axis] < boxes_[b].center()[axis]; });
  const int left = build(first, half);
  const int right = build(first + half, count - half);
  nodes_[id].left = left;
  nodes_[id].right = right;
  return id;
}

std::optional<ShellProximity::Candidate> ShellProximity::global_candidate(const Eigen::Vector3d& p,
                                                                           double bound) const {
  using Entry = std::pair<double, int>;  // (squared box distance, node)
  // A min-heap of the boxes to visit, in storage kept per thread (the searches run in parallel loops).
  thread_local std::vector<Entry> queue;
  queue.clear();
  auto push = [](const Entry& entry) {
    queue.push_back(entry);
    std::push_heap(queue.begin(), queue.end(), std::greater<>());
  };
  push({nodes_[0].box.squaredExteriorDistance(p), 0});
  std::optional<Candidate> best;
  while (!queue.empty()) {
    std::pop_heap(queue.begin(), queue.end(), std::greater<>());
    const auto [box_distance, id] = queue.back();
    queue.pop_back();
    if (box_distance >= bound) break;  // every remaining box is farther than the best sample
    const Node& node = nodes_[id];
    if (node.left >= 0) {
      push({nodes_[node.left].box.squaredExteriorDistance(p), node.left});
      push({nodes_[node.right].box.squaredExteriorDistance(p), node.right});
      continue;
    }
    for (int k = node.first; k < node.first + node.count; ++k) {
      const int e = order_[k];
      if (boxes_[e].squaredExteriorDistance(p) >= bound) continue;
      const std::vector<int>& ids = element_points_[e];
      const auto& samples = element_samples_[e];
      for (int sample = 0; sample < 9; ++sample) {
        Eigen::Vector3d r = Eigen::Vector3d::Zero();
        for (std::size_t a = 0; a < ids.size(); ++a) r += samples(sample, static_cast<int>(a)) * points_[ids[a]];
        const double f = (p - r).squaredNorm();
        if (f < bound) {
          bound = f;
          const auto [u, v] = sample_parameters(elements_[e], sample);
          best = Candidate{f, Eigen::Vector2d(u, v)};
        }
      }
    }
  }
  return best;
}

// Projected Newton on h_a = (p - r) . g_a = 0 (Eq. 63), dh_a/dtheta^b = -C_ab (Eq. C3), with the
// parameter box as bound constraints and backtracking on f = |p - r|^2 / 2 (grad f = -h).
ShellProximity::Projection ShellProximity::newton(const Eigen::Vector3d& p, Eigen::Vector2d theta) const {
  const Eigen::Vector2d lo(surface_.knots(0).front(), surface_.knots(1).front());
  const Eigen::Vector2d hi(surface_.knots(0).back(), surface_.knots(1).back());
  const Eigen::Vector2d span = hi - lo;
  if (!theta.allFinite()) return Projection{};
  theta = theta.cwiseMax(lo).cwiseMin(hi);
  Projection out;
  SurfaceJet s = evaluate(surface_, points_, theta[0], theta[1]);
  bool converged = false, outward = false;
  int escapes = 0;
  for (int it = 0; it <= kMaxIterations; ++it) {
    const Eigen::Vector3d D = p - s.r;
    const Eigen::Vector2d h(D.dot(s.g1), D.dot(s.g2));
    const Eigen::Matrix2d C = distance_hessian(D, s);
    // Round-off floor of h_a: |g_a| times the accuracy of D (relative to the patch size).
    const Eigen::Vector2d tol(1e-13 * s.g1.norm() * (D.norm() + length_scale_),
                              1e-13 * s.g2.norm() * (D.norm() + length_scale_));
    // Active bounds: on the boundary with the distance decreasing outward (-h_a points out).
    bool active[2];
    for (int a = 0; a < 2; ++a)
      active[a] = (theta[a] <= lo[a] && h[a] < -tol[a]) || (theta[a] >= hi[a] && h[a] > tol[a]);
    const bool stationary = (active[0] || std::abs(h[0]) <= tol[0]) && (active[1] || std::abs(h[1]) <= tol[1]);
    out.iterations = it;
    if (stationary) {
      converged = true;
      outward = active[0] || active[1];
      out.where = outward ? Projection::Where::outside : Projection::Where::interior;
      if (!outward && !(C.determinant() > 0 && C(0, 0) > 0)) {
        const auto eig = relative_curvature(s, C);
        if (eig.info() != Eigen::Success) {
          out.where = Projection::Where::failed;
          break;
        }
        if (eig.eigenvalues()[0] < -1e-8 && escapes < kMaxEscapes) {
          // A saddle or maximum of the distance, e.g. a beam point in a mirror plane above a groove whose
          // curvature radius across the plane is below the distance: the gradient vanishes there, so Newton
          // cannot leave it; step along the direction of negative curvature (C_ab is f's Hessian, Eq. C3).
          const auto next = escape_saddle(surface_, points_, p, theta, eig.eigenvectors().col(0), lo, hi, f_of(p, s));
          if (next) {
            ++escapes;
            converged = false;
            theta = *next;
            s = evaluate(surface_, points_, theta[0], theta[1]);
            continue;
          }
        }
        // No descent found along it: a minimum to round-off, at a centre of curvature in one direction (e.g. a
        // groove on a mirror edge with radius = distance, where symmetry pins the projection in that
        // direction). Kept: the distance and normal are right. Flat in BOTH directions (the centre of a
        // sphere) theta-hat is arbitrary: failed.
        if (eig.eigenvalues()[1] <= 1e-8) out.where = Projection::Where::failed;
      }
      break;
    }
    if (it == kMaxIterations) break;
    const Eigen::Vector2d step = projected_newton_step(newton_matrix(s, C), h, active);
    if (!step.allFinite()) break;  // overflow: not converged
    SurfaceJet trial;
    const Eigen::Vector2d next = backtrack(surface_, points_, p, theta, step, lo, hi, f_of(p, s),
                                           1e-30 * length_scale_, trial);
    if (((next - theta).array().abs() <= 1e-15 * span.array()).all()) {
      // No further progress possible: accept if h is at the round-off level.
      theta = next;
      s = trial;
      out.iterations = it + 1;
      const Eigen::Vector3d Dn = p - s.r;
      converged = std::abs(Dn.dot(s.g1)) <= 1e3 * tol[0] && std::abs(Dn.dot(s.g2)) <= 1e3 * tol[1];
      out.where = converged ? Projection::Where::interior : Projection::Where::failed;
      break;
    }
    theta = next;
    s = trial;
  }
  // Overflow (a point or a shell at ~1e154 and beyond, where squared distances are infinite) gives a
  // non-finite parameter: no projection.
  if (!theta.allFinite() || !s.r.allFinite()) return Projection{};
  out.element = element_at(theta[0], theta[1]);
  describe_closest_point(out, p, theta, s);
  if (!converged) out.where = Projection::Where::failed;
  return out;
}

ShellProximity::Projection ShellProximity::at(const Eigen::Vector3d& p, const Eigen::Vector2d& theta) const {
  Projection out;
  const SurfaceJet s = evaluate(surface_, points_, theta[0], theta[1]);
  out.where = Projection::Where::interior;
  out.u = theta[0];
  out.v = theta[1];
  out.element = element_at(theta[0], theta[1]);
  out.point = s.r;
  out.distance = (p - s.r).norm();
  out.normal = out.distance > 0 ? Eigen::Vector3d((p - s.r) / out.distance) : Eigen::Vector3d::Zero();
  return out;
}

ShellProximity::Projection ShellProximity::project(const Eigen::Vector3d& p,
                                                   const std::optional<Eigen::Vector2d>& start,
                                                   double keep_margin) const {
  if (!p.allFinite()) return Projection{};
  if (start) {
    Projection warm = newton(p, *start);
    if (warm.where == Projection::Where::failed) return project(p);
    // Any element that might hold a clearly closer point? (Box bound, then samples.)
    const double closer = warm.distance * (1.0 - std::max(keep_margin, 1e-8));
    const std::optional<Candidate> other = global_candidate(p, closer * closer);
    if (!other) return warm;
    Projection cold = newton(p, other->theta);
    cold.iterations += warm.iterations;
    return (cold.where != Projection::Where::failed && cold.distance < closer) ? cold : warm;
  }
  const std::optional<Candidate> best = global_candidate(p, std::numeric_limits<double>::infinity());
  if (!best) return Projection{};
  return newton(p, best->theta);
}

}  // namespace fibrane::interaction
