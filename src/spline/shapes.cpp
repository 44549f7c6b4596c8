#include "spline/shapes.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace fibrane::spline {

UnitArc make_unit_arc(double angle0, double angle1) {
  const double sweep = angle1 - angle0;
  const double two_pi = 2.0 * std::numbers::pi;
  if (!(std::abs(sweep) > 0.0) || std::abs(sweep) > two_pi * (1.0 + 1e-14))
    throw std::invalid_argument("arc: need 0 < |angle1 - angle0| <= 2 pi");
  // Segments of at most 90 degrees (the slack keeps exactly 90 degrees in one segment).
  const int segments = std::max(1, static_cast<int>(std::ceil(std::abs(sweep) / (0.5 * std::numbers::pi) - 1e-12)));
  const double step = sweep / segments;
  // A rational quadratic Bezier with end points at angles a, a + step, middle point at angle
  // a + step/2 and distance 1/cos(step/2), middle weight cos(step/2), is exactly the unit arc.
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
