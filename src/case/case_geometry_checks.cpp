// Checks of a body's reference geometry that the element kernels rely on: a regular parametrisation (no
// collapsed edge, pole or zero-area element of a shell, no zero-speed point of a beam axis), a beam
// director that is not tangent to the axis, a beam section that is thin compared with the beam, and no C0
// interior knot (a hinge) unless the body allows kinks.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "case/case_geometry.hpp"
#include "common/format.hpp"
#include "common/gauss_legendre.hpp"

namespace fibrane::casefile {
namespace {

// Relative size below which a length, area or speed counts as zero.
constexpr double kCollapsed = 1e-10;

// The diagonal of the points' bounding box; 0 when it is at round-off level of their coordinates.
double bounding_diagonal(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d lo = points.front(), hi = points.front();
  double magnitude = 0.0;
  for (const auto& x : points) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
    magnitude = std::max(magnitude, x.cwiseAbs().maxCoeff());
  }
  const double diagonal = (hi - lo).norm();
  return diagonal <= 1e-12 * magnitude ? 0.0 : diagonal;
}

double polygon_length(const std::vector<Eigen::Vector3d>& pts, const std::vector<int>& indices) {
  double length = 0.0;
  for (std::size_t k = 1; k < indices.size(); ++k) length += (pts[indices[k]] - pts[indices[k - 1]]).norm();
  return length;
}

}  // namespace

void check_surface_metric(const spline::NurbsSurface& s, const io::YamlNode& geometry) {
  const auto& pts = s.control_points();
  const double size = bounding_diagonal(pts);
  if (!(size > 0.0) || !std::isfinite(size)) geometry.fail_message("the surface has no extent (all control points coincide)");
  for (const char* edge : {"u0", "u1", "v0", "v1"})
    if (polygon_length(pts, s.edge_indices(edge, 0)) <= kCollapsed * size)
      geometry.fail_message(fmt::format("edge {} of the surface is collapsed to a point (a pole): the surface "
                                        "metric is singular there; leave the pole out of the patch",
                                        edge));
  const double du = s.knots(0).back() - s.knots(0).front(), dv = s.knots(1).back() - s.knots(1).front();
  const double reference = size * size / (du * dv);  // area Jacobian of a regular patch of this size
  const auto gu = gauss_legendre(s.degree(0) + 1), gv = gauss_legendre(s.degree(1) + 1);
  const auto elements = s.elements();
  for (std::size_t e = 0; e < elements.size(); ++e) {
    const auto& el = elements[e];
    for (double a : gu.points)
      for (double b : gv.points) {
        const double u = el.u0 + 0.5 * (a + 1.0) * (el.u1 - el.u0), v = el.v0 + 0.5 * (b + 1.0) * (el.v1 - el.v0);
        const auto basis = s.basis_in(el.span_u, el.span_v, u, v);
        Eigen::Vector3d a1 = Eigen::Vector3d::Zero(), a2 = Eigen::Vector3d::Zero();
        for (std::size_t k = 0; k < basis.indices.size(); ++k) {
          a1 += basis.R(1, static_cast<Eigen::Index>(k)) * pts[basis.indices[k]];
          a2 += basis.R(2, static_cast<Eigen::Index>(k)) * pts[basis.indices[k]];
        }
        const double jacobian = a1.cross(a2).norm();
        if (!(jacobian > kCollapsed * reference))
          geometry.fail_message(fmt::format(
              "the surface metric is singular in element {} (u in [{:g}, {:g}], v in [{:g}, {:g}]): area "
              "Jacobian {:.3g} at (u, v) = ({:g}, {:g}), against {:.3g} for a regular patch of this size "
              "(collapsed or folded control net)",
              e, el.u0, el.u1, el.v0, el.v1, jacobian, u, v, reference));
      }
  }
}

void check_curve_metric(const spline::NurbsCurve& c, const io::YamlNode& geometry) {
  const double size = bounding_diagonal(c.control_points());
  if (!(size > 0.0) || !std::isfinite(size)) geometry.fail_message("the axis has no extent (all control points coincide)");
  const auto& kv = c.knots();
  const double reference = size / (kv.back() - kv.front());
  const auto g = gauss_legendre(c.degree() + 1);
  for (int span : kv.element_spans()) {
    const double x0 = kv.knots()[span], x1 = kv.knots()[span + 1];
    for (double a : g.points) {
      const double xi = x0 + 0.5 * (a + 1.0) * (x1 - x0);
      const double speed = c.derivative(xi, 1).norm();
      if (!(speed > kCollapsed * reference))
        geometry.fail_message(fmt::format("the axis is singular at xi = {:g} (element [{:g}, {:g}]): its tangent "
                                          "vanishes (coinciding control points)",
                                          xi, x0, x1));
    }
  }
}

double curve_length(const spline::NurbsCurve& c) {
  const auto& kv = c.knots();
  const auto g = gauss_legendre(c.degree() + 2);
  double length = 0.0;
  for (int span : kv.element_spans()) {
    const double x0 = kv.knots()[span], x1 = kv.knots()[span + 1];
    for (std::size_t k = 0; k < g.points.size(); ++k)
      length += 0.5 * (x1 - x0) * g.weights[k] * c.derivative(x0 + 0.5 * (g.points[k] + 1.0) * (x1 - x0), 1).norm();
  }
  return length;
}

void check_director(const spline::NurbsCurve& c, const Eigen::Vector3d& director, const io::YamlNode& node) {
  const auto& kv = c.knots();
  const auto g = gauss_legendre(c.degree() + 1);
  const Eigen::Vector3d d = director.normalized();
  for (int span : kv.element_spans()) {
    const double x0 = kv.knots()[span], x1 = kv.knots()[span + 1];
    for (double a : g.points) {
      const double xi = x0 + 0.5 * (a + 1.0) * (x1 - x0);
      const Eigen::Vector3d t = c.derivative(xi, 1).normalized();
      if (d.cross(t).norm() <= 1e-6)
        node.fail_message(fmt::format("the director is parallel to the beam axis at xi = {:g}: it must have a "
                                      "component normal to the axis everywhere",
                                      xi));
    }
  }
}


void check_no_kinks(const std::vector<const spline::KnotVector*>& directions, const io::YamlNode& body,
                    const std::string& kind) {
  const bool shell = kind == "shell";
  if (shell && body.get("allow_kinks", false)) return;
  const auto refine = body.optional("refine");
  // Refined to C0 elements: continuity 0, given or the default of degree 1.
  const bool c0_refine = refine && refine->get("continuity", (*refine)["degree"].as_int() - 1) == 0;
  for (std::size_t d = 0; d < directions.size(); ++d) {
    const spline::KnotVector& kv = *directions[d];
    for (double u : kv.unique_knots()) {
      const int m = kv.multiplicity(u);
      if (u == kv.front() || u == kv.back() || m < kv.degree()) continue;
      const std::string at = shell ? fmt::format("knot line {} = {}", d == 0 ? "u" : "v", format_number(u))
                                   : fmt::format("knot xi = {}", format_number(u));
      const std::string what = shell ? "a crease that the rotation-free Kirchhoff-Love shell treats as a hinge (no "
                                       "bending moment crosses it)"
                                     : "a kink where the bending energy has no stiffness (a hinge: the tangent is "
                                       "singular); a beam needs a C1 axis";
      const std::string fix = c0_refine ? "refine with continuity >= 1 (and degree >= 2)"
                                        : "use a geometry without C0 knots (arcs, cylinders and spheres of less than "
                                          "360 degrees are C1; a 'nurbs' knot repeated 'degree' times is C0)";
      const io::YamlNode where = !c0_refine                 ? body["geometry"]
                                 : refine->has("continuity") ? (*refine)["continuity"]
                                                             : (*refine)["degree"];
      const std::string name = body["name"].as_string();
      if (shell)
        where.fail_message(fmt::format("shell '{}': the surface is only C0 at the interior {} (multiplicity {} = "
                                       "degree {}): {}. Either {}, or, to keep the hinge on purpose, set "
                                       "'allow_kinks: true' on the shell",
                                       name, at, m, kv.degree(), what, fix));
      where.fail_message(fmt::format("beam '{}': the axis is only C0 at the interior {} (multiplicity {} = degree {}): "
                                     "{}: {}",
                                     name, at, m, kv.degree(), what, fix));
    }
  }
}

}  // namespace fibrane::casefile
