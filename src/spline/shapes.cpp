#include "spline/shapes.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace fibrane::spline {

namespace {

// Sweeps up to this angle are one rational quadratic segment; its middle weight cos(sweep / 2) falls to
// 0.5 here, and the two-segment C1 form (weights cos^2(sweep / 4) >= 0.5 up to 180 degrees) takes over.
constexpr double kSingleSegmentSweep = 2.0 * std::numbers::pi / 3.0;

// One segment: end points at angle0, angle1, middle point at the mid angle and distance 1/cos(h) with
// weight cos(h), h = sweep / 2: exactly the unit arc.
UnitArc single_segment(double angle0, double angle1) {
  const double h = 0.5 * (angle1 - angle0), m = angle0 + h, w = std::cos(h);
  return {KnotVector(2, {0, 0, 0, 1, 1, 1}),
          {{std::cos(angle0), std::sin(angle0)},
           {std::cos(m) / w, std::sin(m) / w},
           {std::cos(angle1), std::sin(angle1)}},
          {1.0, w, 1.0}};
}

// Two segments of sweep / 2 joined C1 at the simple knot 0.5: control points on the tangents at the ends,
// at angles angle0 + sweep/4 and angle0 + 3 sweep/4 and distance 1/cos(h), both of weight cos^2(h),
// h = sweep / 4. Inserting 0.5 once more gives the middle point of the arc with weight cos^2(h), so each
// half is the one-segment arc of its end weights (w_mid^2 = cos^2(h) w_0 w_1 holds); the homogeneous
// middle point is the mean of its neighbours, so the curve is C1 there. Valid for sweeps below 360 deg.
UnitArc two_segments_c1(double angle0, double angle1) {
  const double q = 0.25 * (angle1 - angle0), c = std::cos(q);
  const double a = angle0 + q, b = angle0 + 3.0 * q;
  return {KnotVector(2, {0, 0, 0, 0.5, 1, 1, 1}),
          {{std::cos(angle0), std::sin(angle0)},
           {std::cos(a) / c, std::sin(a) / c},
           {std::cos(b) / c, std::sin(b) / c},
           {std::cos(angle1), std::sin(angle1)}},
          {1.0, c * c, c * c, 1.0}};
}

// A full circle: four quadratic segments of 90 degrees joined C0 (a closed ring has a seam anyway).
UnitArc full_circle(double angle0, double angle1) {
  const int segments = 4;
  const double step = (angle1 - angle0) / segments;
  const double mid_weight = std::cos(0.5 * step);
  std::vector<double> knots{0.0, 0.0, 0.0};
  UnitArc arc{KnotVector(2, {0, 0, 0, 1, 1, 1}), {}, {}};
  for (int s = 0; s < segments; ++s) {
    const double a = angle0 + s * step;
    const double m = a + 0.5 * step;
    if (s == 0) {
      arc.points.emplace_back(std::cos(a), std::sin(a));
      arc.weights.push_back(1.0);
    }
    arc.points.emplace_back(std::cos(m) / mid_weight, std::sin(m) / mid_weight);
    arc.weights.push_back(mid_weight);
    const double b = (s + 1 == segments) ? angle1 : a + step;
    arc.points.emplace_back(std::cos(b), std::sin(b));
    arc.weights.push_back(1.0);
    if (s + 1 < segments) knots.insert(knots.end(), 2, static_cast<double>(s + 1) / segments);
  }
  knots.insert(knots.end(), 3, 1.0);
  arc.knots = KnotVector(2, std::move(knots));
  return arc;
}

}  // namespace

UnitArc make_unit_arc(double angle0, double angle1) {
  const double sweep = std::abs(angle1 - angle0);
  const double two_pi = 2.0 * std::numbers::pi;
  if (!(sweep > 0.0) || sweep > two_pi * (1.0 + 1e-14))
    throw std::invalid_argument("arc: need 0 < |angle1 - angle0| <= 2 pi");
  if (sweep <= kSingleSegmentSweep * (1.0 + 1e-12)) return single_segment(angle0, angle1);
  if (sweep < two_pi * (1.0 - 1e-12)) return two_segments_c1(angle0, angle1);
  return full_circle(angle0, angle1);
}

NurbsSurface make_rectangle(Eigen::Vector3d origin, Eigen::Vector3d edge_u, Eigen::Vector3d edge_v) {
  const KnotVector linear(1, {0, 0, 1, 1});
  return NurbsSurface(linear, linear, {origin, origin + edge_u, origin + edge_v, origin + edge_u + edge_v});
}

NurbsSurface make_cylinder_patch(double radius, double length, double theta0, double theta1) {
  if (!(radius > 0.0) || !(length > 0.0))
    throw std::invalid_argument("make_cylinder_patch: radius and length must be > 0");
  const UnitArc arc = make_unit_arc(theta0, theta1);
  const int n_u = static_cast<int>(arc.points.size());
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < n_u; ++i) {
      points.emplace_back(j * length, radius * arc.points[i].x(), radius * arc.points[i].y());
      weights.push_back(arc.weights[i]);
    }
  }
  return NurbsSurface(arc.knots, KnotVector(1, {0, 0, 1, 1}), std::move(points), std::move(weights));
}

NurbsSurface make_sphere_patch(double radius, double theta0, double theta1, double phi0, double phi1) {
  if (!(radius > 0.0)) throw std::invalid_argument("make_sphere_patch: radius must be > 0");
  const double half_pi = 0.5 * std::numbers::pi;
  if (!(phi0 >= -half_pi * (1 + 1e-14) && phi1 <= half_pi * (1 + 1e-14) && phi0 < phi1))
    throw std::invalid_argument("make_sphere_patch: need -pi/2 <= phi0 < phi1 <= pi/2");
  // Surface of revolution of the meridian (r, z) = (cos ph, sin ph) about z: with the circle
  // (c_i, s_i; weight a_i) and the meridian (r_j, z_j; weight b_j), P_ij = R (r_j c_i, r_j s_i, z_j)
  // and w_ij = a_i b_j reproduce the separable rational product exactly.
  const UnitArc circle = make_unit_arc(theta0, theta1);
  const UnitArc meridian = make_unit_arc(phi0, phi1);
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;
  for (std::size_t j = 0; j < meridian.points.size(); ++j) {
    const double r = meridian.points[j].x(), z = meridian.points[j].y();
    for (std::size_t i = 0; i < circle.points.size(); ++i) {
      points.push_back(radius * Eigen::Vector3d(r * circle.points[i].x(), r * circle.points[i].y(), z));
      weights.push_back(circle.weights[i] * meridian.weights[j]);
    }
  }
  return NurbsSurface(circle.knots, meridian.knots, std::move(points), std::move(weights));
}

NurbsCurve make_line(Eigen::Vector3d a, Eigen::Vector3d b) {
  return NurbsCurve(KnotVector(1, {0, 0, 1, 1}), {a, b});
}

NurbsCurve make_arc(Eigen::Vector3d center, Eigen::Vector3d e1, Eigen::Vector3d e2, double radius,
                    double angle0, double angle1) {
  if (!(radius > 0.0)) throw std::invalid_argument("make_arc: radius must be > 0");
  const UnitArc arc = make_unit_arc(angle0, angle1);
  std::vector<Eigen::Vector3d> points;
  for (const Eigen::Vector2d& cs : arc.points) points.push_back(center + radius * (cs.x() * e1 + cs.y() * e2));
  return NurbsCurve(arc.knots, std::move(points), arc.weights);
}

}  // namespace fibrane::spline
