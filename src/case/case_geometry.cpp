#include "case/case_geometry.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

#include "case/case_limits.hpp"
#include "spline/shapes.hpp"

namespace fibrane::casefile {

namespace {

constexpr double deg = std::numbers::pi / 180.0;

std::vector<Eigen::Vector3d> read_points(const io::YamlNode& node) {
  if (!node.is_sequence() || node.size() == 0) node.fail("a non-empty list of [x, y, z] points");
  std::vector<Eigen::Vector3d> pts;
  for (std::size_t i = 0; i < node.size(); ++i) pts.push_back(node.at(i).as_vector3());
  return pts;
}

// An angle range [from, to] in degrees, returned in radians: to > from, to - from <= 360, and, where
// `lo` < `hi` are given, both ends inside [lo, hi].
std::pair<double, double> read_range(const io::YamlNode& node, double lo = -INFINITY, double hi = INFINITY) {
  const auto v = node.as_doubles();
  if (v.size() != 2 || !(v[1] > v[0]) || v[1] - v[0] > 360.0)
    node.fail("[from, to] in degrees with from < to <= from + 360");
  if (v[0] < lo || v[1] > hi) node.fail(fmt::format("[from, to] in degrees within [{:g}, {:g}]", lo, hi));
  return {v[0] * deg, v[1] * deg};
}

spline::KnotVector read_knots(const io::YamlNode& degree, const io::YamlNode& knots) {
  const int p = read_degree(degree);
  try {
    return spline::KnotVector(p, knots.as_doubles());
  } catch (const std::invalid_argument& e) {
    knots.fail_message(std::string("invalid knot vector for degree ") + std::to_string(p) + ": " + e.what());
  }
}

std::vector<double> read_weights(const io::YamlNode& g, std::size_t expected) {
  auto w = g.optional("weights");
  if (!w) return {};
  auto values = w->as_doubles();
  if (values.size() != expected)
    w->fail(std::to_string(expected) + " weights (one per control point), got " + std::to_string(values.size()) +
            " values");
  for (double x : values)
    if (!(x > 0)) w->fail("positive weights");
  return values;
}

// Element counts of a refine block: one positive integer per direction, at most kMaxElementsPerDirection.
std::vector<int> read_element_counts(const io::YamlNode& elements, int dims) {
  const std::string expected = fmt::format("{} in [1, {}]", dims == 1 ? "the number of elements, an integer" : "[n_u, n_v], integers",
                                           kMaxElementsPerDirection);
  std::vector<double> v;
  if (dims == 1) {
    v.push_back(elements.as_double());
  } else {
    v = elements.as_doubles();
    if (v.size() != 2) elements.fail(expected);
  }
  std::vector<int> counts;
  for (double x : v) {
    if (!(x >= 1 && x <= kMaxElementsPerDirection) || x != std::floor(x)) elements.fail(expected);
    counts.push_back(static_cast<int>(x));
  }
  return counts;
}

// Control points per direction after refining a direction that has `existing` elements to `degree`,
// `continuity` and `n` uniform elements (an upper bound: the existing knots stay).
double refined_control_points(int existing, int degree, int continuity, int n) {
  return static_cast<double>(n + existing) * (degree - continuity) + continuity + 1;
}

// `size(degree, continuity, counts)` estimates the refined body's size; it is checked against the machine's
// memory together with `others` before `apply` refines.
template <class Size, class Refine>
void apply_refinement(const std::optional<io::YamlNode>& refine, int dims, const ModelSize& others, Size&& size,
                      Refine&& apply) {
  if (!refine) return;
  const int degree = read_degree((*refine)["degree"]);
  const int continuity = (*refine).get("continuity", degree - 1);
  if (continuity < 0 || continuity >= degree)
    (*refine)["continuity"].fail("an inter-element continuity in [0, degree - 1] = [0, " +
                                 std::to_string(degree - 1) + "]");
  const auto elements = (*refine)["elements"];
  const std::vector<int> counts = read_element_counts(elements, dims);
  refine->reject_unknown_keys();
  ModelSize total = others;
  total += size(degree, continuity, counts);
  check_fits(total, elements);
  try {
    for (int d = 0; d < dims; ++d) apply(d, degree, continuity, counts[d]);
  } catch (const std::invalid_argument& e) {
    refine->fail_message(std::string("cannot refine: ") + e.what());
  }
}

}  // namespace

spline::NurbsSurface read_surface(const io::YamlNode& g, const std::optional<io::YamlNode>& refine,
                                  const ModelSize& others) {
  auto surface = [&]() -> spline::NurbsSurface {
    if (auto r = g.optional("rectangle")) {
      const Eigen::Vector3d o = (*r)["origin"].as_vector3();
      const Eigen::Vector3d eu = (*r)["edge_u"].as_vector3(), ev = (*r)["edge_v"].as_vector3();
      if (eu.cross(ev).norm() <= 1e-14 * eu.norm() * ev.norm())
        (*r)["edge_v"].fail("an edge not parallel to edge_u");
      r->reject_unknown_keys();
      return spline::make_rectangle(o, eu, ev);
    }
    if (auto c = g.optional("cylinder")) {
      const double radius = (*c)["radius"].positive(), length = (*c)["length"].positive();
      const auto [a0, a1] = read_range((*c)["angles"]);
      c->reject_unknown_keys();
      return spline::make_cylinder_patch(radius, length, a0, a1);
    }
    if (auto s = g.optional("sphere")) {
      const double radius = (*s)["radius"].positive();
      const auto [t0, t1] = read_range((*s)["theta"]);
      const auto [p0, p1] = read_range((*s)["phi"], -90.0, 90.0);
      s->reject_unknown_keys();
      return spline::make_sphere_patch(radius, t0, t1, p0, p1);
    }
    if (auto n = g.optional("nurbs")) {
      const auto degrees = (*n)["degrees"];
      if (!degrees.is_sequence() || degrees.size() != 2) degrees.fail("[p, q], the degrees in u and v");
      auto ku = read_knots(degrees.at(0), (*n)["knots_u"]);
      auto kv = read_knots(degrees.at(1), (*n)["knots_v"]);
      const auto pts_node = (*n)["control_points"];
      auto pts = read_points(pts_node);
      const std::size_t expected = static_cast<std::size_t>(ku.num_basis()) * kv.num_basis();
      if (pts.size() != expected)
        pts_node.fail(std::to_string(expected) + " control points (" + std::to_string(ku.num_basis()) + " x " +
                      std::to_string(kv.num_basis()) + ", u fastest), got " + std::to_string(pts.size()));
      auto w = read_weights(*n, expected);
      n->reject_unknown_keys();
      return spline::NurbsSurface(std::move(ku), std::move(kv), std::move(pts), std::move(w));
    }
    g.fail("one of 'rectangle', 'cylinder', 'sphere' or 'nurbs'");
  }();
  g.reject_unknown_keys();
  auto size = [&](int p, int c, const std::vector<int>& n) {
    const int e0 = surface.knots(0).num_elements(), e1 = surface.knots(1).num_elements();
    return shell_size(refined_control_points(e0, p, c, n[0]) * refined_control_points(e1, p, c, n[1]),
                      static_cast<double>(n[0] + e0) * (n[1] + e1), p, p, p + 1);
  };
  apply_refinement(refine, 2, others, size, [&](int d, int p, int c, int n) { surface.refine(d, p, c, n); });
  check_surface_metric(surface, g);
  return surface;
}

spline::NurbsCurve read_curve(const io::YamlNode& g, const std::optional<io::YamlNode>& refine,
                              const ModelSize& others) {
  auto curve = [&]() -> spline::NurbsCurve {
    if (auto l = g.optional("line")) {
      const Eigen::Vector3d a = (*l)["from"].as_vector3(), b = (*l)["to"].as_vector3();
      if ((b - a).norm() == 0.0) (*l)["to"].fail("an end point different from 'from'");
      l->reject_unknown_keys();
      return spline::make_line(a, b);
    }
    if (auto a = g.optional("arc")) {
      const Eigen::Vector3d c = (*a)["center"].as_vector3();
      Eigen::Vector3d e1 = (*a)["e1"].as_vector3();
      if (!(e1.norm() > 0)) (*a)["e1"].fail("a non-zero direction");
      e1.normalize();
      Eigen::Vector3d e2 = (*a)["e2"].as_vector3();
      if (!(e2.norm() > 0)) (*a)["e2"].fail("a non-zero direction");
      e2.normalize();
      e2 = (e2 - e2.dot(e1) * e1);
      if (e2.norm() < 1e-9) (*a)["e2"].fail("a direction not parallel to e1");
      e2.normalize();
      const double radius = (*a)["radius"].positive();
      const auto [a0, a1] = read_range((*a)["angles"]);
      a->reject_unknown_keys();
      return spline::make_arc(c, e1, e2, radius, a0, a1);
    }
    if (auto n = g.optional("nurbs")) {
      auto kv = read_knots((*n)["degree"], (*n)["knots"]);
      const auto pts_node = (*n)["control_points"];
      auto pts = read_points(pts_node);
      if (pts.size() != static_cast<std::size_t>(kv.num_basis()))
        pts_node.fail(std::to_string(kv.num_basis()) + " control points, got " + std::to_string(pts.size()));
      auto w = read_weights(*n, pts.size());
      n->reject_unknown_keys();
      return spline::NurbsCurve(std::move(kv), std::move(pts), std::move(w));
    }
    g.fail("one of 'line', 'arc' or 'nurbs'");
  }();
  g.reject_unknown_keys();
  auto size = [&](int p, int c, const std::vector<int>& n) {
    const int e = curve.knots().num_elements();
    return beam_size(refined_control_points(e, p, c, n[0]), n[0] + e, p, p + 1);
  };
  apply_refinement(refine, 1, others, size, [&](int, int p, int c, int n) { curve.refine(p, c, n); });
  check_curve_metric(curve, g);
  return curve;
}

}  // namespace fibrane::casefile
