#include "case/case_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

#include "case/case_limits.hpp"
#include "common/format.hpp"
#include "spline/refinement.hpp"
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

// The pattern of a direction refined to `elements` elements of `degree` and `continuity`: that of a uniform
// open knot vector. Refining a direction of E elements to a grid of n gives at most n + E - 1 elements
// (the grid's and the existing interior knots), which the callers pass; an existing knot whose multiplicity
// after degree elevation exceeds degree - continuity adds functions this count leaves out.
DirectionPattern refined_pattern(int elements, int degree, int continuity) {
  return direction_pattern(spline::KnotVector::open_uniform(degree, elements, continuity));
}

// Largest ratio of the longest to the shortest element of a geometric grading.
constexpr double kMaxGradingSpread = 1e6;

// A direction's grading: `grid` holds the interior parameter values of the graded grid; empty: uniform.
struct Grading {
  std::vector<double> grid;
};

// One direction of a refine block's `grading`: {ratio: r} (element lengths growing by the factor r from
// the start of the parameter domain [a, b] to its end) or {knots: [...]} (the interior knots, increasing,
// inside (a, b)). `count` is the element count of `elements` for this direction: explicit knots must make
// as many elements.
Grading read_grading(const io::YamlNode& node, int count, double a, double b, const std::string& direction) {
  if (!node.is_map()) node.fail("{ratio: r} or {knots: [interior knots]}");
  Grading g;
  if (node.has("ratio") == node.has("knots")) node.fail("one of 'ratio' or 'knots'");
  if (auto r = node.optional("ratio")) {
    const double ratio = r->positive();
    const double spread = std::pow(std::max(ratio, 1.0 / ratio), count - 1);
    if (!(spread <= kMaxGradingSpread))
      r->fail(fmt::format("a ratio whose {} elements{} differ in length by at most a factor {:g} (ratio^{} = {:.3g})",
                          count, direction, kMaxGradingSpread, count - 1, spread));
    if (ratio != 1.0) g.grid = spline::geometric_grid(a, b, count, ratio);
  } else {
    const auto k = node["knots"];
    g.grid = k.as_doubles();
    const double tol = 1e-12 * (b - a);
    for (std::size_t i = 0; i < g.grid.size(); ++i) {
      const double lo = i == 0 ? a : g.grid[i - 1];
      if (!(g.grid[i] > lo + tol && g.grid[i] < b - tol))
        k.fail(fmt::format("increasing interior knots strictly inside the parameter domain ({}, {})", format_number(a),
                           format_number(b)));
    }
    if (static_cast<int>(g.grid.size()) + 1 != count)
      k.fail_message(fmt::format("{} interior knots make {} elements, but 'elements' asks for {}{}: give {} knots or "
                                 "set the element count to {}",
                                 g.grid.size(), g.grid.size() + 1, count, direction, count - 1, g.grid.size() + 1));
  }
  node.reject_unknown_keys();
  return g;
}

// The gradings of a refine block: `grading: {ratio | knots}` for a beam, `grading: {u: {...}, v: {...}}`
// (either optional) for a shell; `domain(d)` is the parameter domain of direction d.
template <class Domain>
std::vector<Grading> read_gradings(const io::YamlNode& refine, const std::vector<int>& counts, Domain&& domain) {
  const int dims = static_cast<int>(counts.size());
  std::vector<Grading> out(dims);
  const auto node = refine.optional("grading");
  if (!node) return out;
  if (dims == 1) {
    const auto [a, b] = domain(0);
    out[0] = read_grading(*node, counts[0], a, b, "");
    return out;
  }
  if (!node->is_map()) node->fail("a map with the keys u and/or v");
  for (int d = 0; d < 2; ++d)
    if (auto dir = node->optional(d == 0 ? "u" : "v")) {
      const auto [a, b] = domain(d);
      out[d] = read_grading(*dir, counts[d], a, b, d == 0 ? " along u" : " along v");
    }
  node->reject_unknown_keys();
  return out;
}

// `size(degree, continuity, counts)` estimates the refined body's size; it is checked against the machine's
// memory together with `others` before `apply(direction, degree, continuity, count, grading)` refines.
template <class Size, class Domain, class Refine>
void apply_refinement(const std::optional<io::YamlNode>& refine, int dims, const ModelSize& others, Size&& size,
                      Domain&& domain, Refine&& apply) {
  if (!refine) return;
  const int degree = read_degree((*refine)["degree"]);
  const int continuity = (*refine).get("continuity", degree - 1);
  if (continuity < 0 || continuity >= degree)
    (*refine)["continuity"].fail("an inter-element continuity in [0, degree - 1] = [0, " +
                                 std::to_string(degree - 1) + "]");
  const auto elements = (*refine)["elements"];
  const std::vector<int> counts = read_element_counts(elements, dims);
  const std::vector<Grading> gradings = read_gradings(*refine, counts, domain);
  refine->reject_unknown_keys();
  ModelSize total = others;
  total += size(degree, continuity, counts);
  check_fits(total, elements);
  try {
    for (int d = 0; d < dims; ++d) apply(d, degree, continuity, counts[d], gradings[d]);
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
    const int e0 = n[0] + surface.knots(0).num_elements() - 1, e1 = n[1] + surface.knots(1).num_elements() - 1;
    return shell_size(refined_pattern(e0, p, c), refined_pattern(e1, p, c), static_cast<double>(e0) * e1,
                      (p + 1) * (p + 1));
  };
  auto domain = [&](int d) { return std::make_pair(surface.knots(d).front(), surface.knots(d).back()); };
  apply_refinement(refine, 2, others, size, domain, [&](int d, int p, int c, int n, const Grading& g) {
    if (g.grid.empty())
      surface.refine(d, p, c, n);
    else
      surface.refine(d, p, c, g.grid);
  });
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
    const int e = n[0] + curve.knots().num_elements() - 1;
    return beam_size(refined_pattern(e, p, c), e, p + 1);
  };
  auto domain = [&](int) { return std::make_pair(curve.knots().front(), curve.knots().back()); };
  apply_refinement(refine, 1, others, size, domain, [&](int, int p, int c, int n, const Grading& g) {
    if (g.grid.empty())
      curve.refine(p, c, n);
    else
      curve.refine(p, c, g.grid);
  });
  check_curve_metric(curve, g);
  return curve;
}

}  // namespace fibrane::casefile
