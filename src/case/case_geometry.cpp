#include "case/case_geometry.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

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

std::pair<double, double> read_range(const io::YamlNode& node, double scale) {
  const auto v = node.as_doubles();
  if (v.size() != 2 || !(v[1] > v[0])) node.fail("[from, to] with to > from");
  return {v[0] * scale, v[1] * scale};
}

spline::KnotVector read_knots(const io::YamlNode& degree, const io::YamlNode& knots) {
  const int p = degree.positive_int();
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

template <class Refine>
void apply_refinement(const std::optional<io::YamlNode>& refine, int dims, Refine&& apply) {
  if (!refine) return;
  const int degree = (*refine)["degree"].positive_int();
  const int continuity = (*refine).get("continuity", degree - 1);
  if (continuity < 0 || continuity >= degree)
    (*refine)["continuity"].fail("an inter-element continuity in [0, degree - 1] = [0, " +
                                 std::to_string(degree - 1) + "]");
  const auto elements = (*refine)["elements"];
  std::vector<int> counts;
  if (dims == 1) {
    counts.push_back(elements.positive_int());
  } else {
    const auto v = elements.as_doubles();
    if (v.size() != 2 || v[0] < 1 || v[1] < 1 || v[0] != std::floor(v[0]) || v[1] != std::floor(v[1]))
      elements.fail("[n_u, n_v], two positive integers");
    counts = {static_cast<int>(v[0]), static_cast<int>(v[1])};
  }
  refine->reject_unknown_keys();
  try {
    for (int d = 0; d < dims; ++d) apply(d, degree, continuity, counts[d]);
  } catch (const std::invalid_argument& e) {
    refine->fail_message(std::string("cannot refine: ") + e.what());
  }
}

}  // namespace

spline::NurbsSurface read_surface(const io::YamlNode& g, const std::optional<io::YamlNode>& refine) {
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
      const auto [a0, a1] = read_range((*c)["angles"], deg);
      c->reject_unknown_keys();
      return spline::make_cylinder_patch(radius, length, a0, a1);
    }
    if (auto s = g.optional("sphere")) {
      const double radius = (*s)["radius"].positive();
      const auto [t0, t1] = read_range((*s)["theta"], deg);
      const auto [p0, p1] = read_range((*s)["phi"], deg);
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
  apply_refinement(refine, 2, [&](int d, int p, int c, int n) { surface.refine(d, p, c, n); });
  return surface;
}

spline::NurbsCurve read_curve(const io::YamlNode& g, const std::optional<io::YamlNode>& refine) {
  auto curve = [&]() -> spline::NurbsCurve {
    if (auto l = g.optional("line")) {
      const Eigen::Vector3d a = (*l)["from"].as_vector3(), b = (*l)["to"].as_vector3();
      if ((b - a).norm() == 0.0) (*l)["to"].fail("an end point different from 'from'");
      l->reject_unknown_keys();
      return spline::make_line(a, b);
    }
    if (auto a = g.optional("arc")) {
      const Eigen::Vector3d c = (*a)["center"].as_vector3();
      const Eigen::Vector3d e1 = (*a)["e1"].as_vector3().normalized();
      Eigen::Vector3d e2 = (*a)["e2"].as_vector3();
      e2 = (e2 - e2.dot(e1) * e1);
      if (e2.norm() < 1e-12) (*a)["e2"].fail("a direction not parallel to e1");
      e2.normalize();
      const double radius = (*a)["radius"].positive();
      const auto [a0, a1] = read_range((*a)["angles"], deg);
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
  apply_refinement(refine, 1, [&](int, int p, int c, int n) { curve.refine(p, c, n); });
  return curve;
}

}  // namespace fibrane::casefile
