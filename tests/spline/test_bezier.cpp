// Bezier extraction: the extracted rational Bezier elements, evaluated here with an independent
// Bernstein basis, reproduce the NURBS points and per-control-point fields at random parameters and at
// element boundaries. Tolerance 1e-13 (absolute, geometry and fields of size O(1)): extraction is a
// chain of convex combinations and both evaluations are sums of at most 25 terms with weights in
// [0.5, 2], so the differences stay within a few dozen ulps.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "spline/bezier.hpp"
#include "spline/shapes.hpp"
#include "test_helpers.hpp"

namespace fibrane::spline {
namespace {

constexpr double kTol = 1e-13;
constexpr double kPi = std::numbers::pi;

// Bernstein polynomials B_k of degree p at t in [0, 1], written out independently of the library.
Eigen::VectorXd bernstein(int p, double t) {
  Eigen::VectorXd b(p + 1);
  for (int k = 0; k <= p; ++k) b[k] = std::tgamma(p + 1.0) / (std::tgamma(k + 1.0) * std::tgamma(p - k + 1.0)) *
                                      std::pow(t, k) * std::pow(1.0 - t, p - k);
  return b;
}

// Rational Bezier interpolation of `bezier` (one column per Bezier point) at (u, v) in the element.
Eigen::VectorXd evaluate(const BezierElement& e, const Eigen::MatrixXd& bezier, double u, double v = 0.0) {
  const Eigen::VectorXd bu = bernstein(e.degree_u, (u - e.u0) / (e.u1 - e.u0));
  const Eigen::VectorXd bv = e.degree_v == 0 ? Eigen::VectorXd::Ones(1) : bernstein(e.degree_v, (v - e.v0) / (e.v1 - e.v0));
  Eigen::VectorXd numerator = Eigen::VectorXd::Zero(bezier.rows());
  double denominator = 0.0;
  for (int l = 0; l <= e.degree_v; ++l)
    for (int k = 0; k <= e.degree_u; ++k) {
      const int b = k + (e.degree_u + 1) * l;
      const double wb = e.weights[b] * bu[k] * bv[l];
      numerator += wb * bezier.col(b);
      denominator += wb;
    }
  return numerator / denominator;
}

Eigen::MatrixXd as_columns(const std::vector<Eigen::Vector3d>& points) {
  Eigen::MatrixXd m(3, points.size());
  for (std::size_t i = 0; i < points.size(); ++i) m.col(i) = points[i];
  return m;
}

// Open knot vector of degree p on [0, 1] with interior knots of every multiplicity 1..p (and a second
// simple knot), so elements of every continuity C^(p-1) .. C^0 meet.
KnotVector mixed_knots(int p) {
  std::vector<double> knots(p + 1, 0.0);
  for (int m = 1; m <= p; ++m) knots.insert(knots.end(), m, m / (p + 2.0) + 0.01 * m * m);
  knots.push_back(0.93);
  knots.insert(knots.end(), p + 1, 1.0);
  return KnotVector(p, knots);
}

Eigen::MatrixXd random_field(std::mt19937& rng, int components, int n) {
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  Eigen::MatrixXd f(components, n);
  for (double& x : f.reshaped()) x = value(rng);
  return f;
}

// Element of `elements` (curve elements, increasing u) that contains u; `last` picks the later one
// at an element boundary.
const BezierElement& element_at(const std::vector<BezierElement>& elements, double u, bool last = false) {
  for (std::size_t e = 0; e < elements.size(); ++e) {
    const auto& el = elements[last ? elements.size() - 1 - e : e];
    if (u >= el.u0 && u <= el.u1) return el;
  }
  throw std::logic_error("no element contains the parameter");
}

// Compares curve points and a field at random parameters and at both sides of every knot.
void check_curve(const NurbsCurve& curve, const Eigen::MatrixXd& field) {
  const auto elements = bezier_elements(curve);
  ASSERT_EQ(static_cast<int>(elements.size()), curve.knots().num_elements());
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> param(curve.knots().front(), curve.knots().back());
  std::vector<double> us = curve.knots().unique_knots();
  for (int s = 0; s < 300; ++s) us.push_back(param(rng));
  const Eigen::MatrixXd points = as_columns(curve.control_points());
  for (const double u : us) {
    const CurveBasis basis = curve.basis(u, 0);
    const Eigen::VectorXd f_nurbs = field.middleCols(basis.first, basis.R.cols()) * basis.R.row(0).transpose();
    for (const bool last : {false, true}) {
      const BezierElement& e = element_at(elements, u, last);
      EXPECT_LE((evaluate(e, e.extract(points), u) - curve.point(u)).norm(), kTol) << "u=" << u;
      EXPECT_LE((evaluate(e, e.extract(field), u) - f_nurbs).norm(), kTol) << "u=" << u;
    }
  }
}

// Compares surface points and a field at random parameters in every element and on its corners.
void check_surface(const NurbsSurface& surface, const Eigen::MatrixXd& field) {
  const auto elements = bezier_elements(surface);
  ASSERT_EQ(elements.size(), surface.elements().size());
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const Eigen::MatrixXd points = as_columns(surface.control_points());
  for (const auto& e : elements) {
    const Eigen::MatrixXd xb = e.extract(points), fb = e.extract(field);
    for (int s = 0; s < 12; ++s) {
      const double a = s < 4 ? s % 2 : unit(rng), b = s < 4 ? s / 2 : unit(rng);  // corners first
      const double u = e.u0 + a * (e.u1 - e.u0), v = e.v0 + b * (e.v1 - e.v0);
      const SurfaceBasis basis = surface.basis_in(e.span_u, e.span_v, u, v);
      Eigen::VectorXd f_nurbs = Eigen::VectorXd::Zero(field.rows());
      for (std::size_t k = 0; k < basis.indices.size(); ++k) f_nurbs += basis.R(0, k) * field.col(basis.indices[k]);
      EXPECT_LE((evaluate(e, xb, u, v) - surface.point(u, v)).norm(), kTol) << "u=" << u << " v=" << v;
      EXPECT_LE((evaluate(e, fb, u, v) - f_nurbs).norm(), kTol) << "u=" << u << " v=" << v;
    }
  }
}

TEST(BezierExtraction, RationalCurvesOfDegree2To4WithKnotsOfEveryMultiplicity) {
  std::mt19937 rng(1);
  for (int p = 2; p <= 4; ++p) {
    SCOPED_TRACE("degree " + std::to_string(p));
    const KnotVector kv = mixed_knots(p);
    const int n = kv.num_basis();
    const NurbsCurve curve(kv, testing::random_points(rng, n), testing::random_weights(rng, n));
    check_curve(curve, random_field(rng, 4, n));
  }
}

TEST(BezierExtraction, RationalSurfacesOfDegrees2To4InEachDirection) {
  std::mt19937 rng(2);
  for (int p = 2; p <= 4; ++p)
    for (int q = 2; q <= 4; ++q) {
      SCOPED_TRACE("degrees " + std::to_string(p) + ", " + std::to_string(q));
      const KnotVector ku = mixed_knots(p), kv = mixed_knots(q);
      const int n = ku.num_basis() * kv.num_basis();
      const NurbsSurface surface(ku, kv, testing::random_points(rng, n), testing::random_weights(rng, n));
      check_surface(surface, random_field(rng, 3, n));
    }
}

TEST(BezierExtraction, CircleArcsStayExactAfterRefinement) {
  const Eigen::Vector3d center(0.5, -1.0, 2.0), e1(0, 1, 0), e2(0, 0, 1);
  std::mt19937 rng(3);
  for (int p = 2; p <= 4; ++p) {
    SCOPED_TRACE("degree " + std::to_string(p));
    NurbsCurve arc = make_arc(center, e1, e2, 1.5, -0.2, 1.4 * kPi);  // two segments, joined C1
    arc.refine(p, p - 2, 5);
    arc.insert_knot(0.37, p);  // a C0 knot inside a segment
    check_curve(arc, random_field(rng, 1, arc.num_control_points()));
    // The Bezier form itself lies on the circle.
    for (const auto& e : bezier_elements(arc)) {
      const Eigen::MatrixXd xb = e.extract(as_columns(arc.control_points()));
      for (int s = 0; s <= 10; ++s)
        EXPECT_NEAR((evaluate(e, xb, e.u0 + (e.u1 - e.u0) * s / 10.0) - center).norm(), 1.5, kTol);
    }
  }
}

TEST(BezierExtraction, SphereAndCylinderPatchesStayExactAfterRefinement) {
  std::mt19937 rng(4);
  NurbsSurface sphere = make_sphere_patch(1.0, 0.1, 2.0, -1.0, 1.2);
  sphere.refine(0, 3, 1, 3);
  sphere.refine(1, 4, 2, 2);
  check_surface(sphere, random_field(rng, 3, sphere.num_control_points()));
  for (const auto& e : bezier_elements(sphere)) {
    const Eigen::MatrixXd xb = e.extract(as_columns(sphere.control_points()));
    EXPECT_NEAR(evaluate(e, xb, 0.5 * (e.u0 + e.u1), 0.3 * e.v0 + 0.7 * e.v1).norm(), 1.0, kTol);
  }
  NurbsSurface cylinder = make_cylinder_patch(0.8, 2.0, -0.5, 2.5);
  cylinder.refine(0, 4, 3, 4);
  cylinder.refine(1, 2, 0, 3);
  check_surface(cylinder, random_field(rng, 2, cylinder.num_control_points()));
}

TEST(BezierExtraction, OperatorIsStochasticAndIdentityForBezierKnots) {
  const KnotVector kv = mixed_knots(4);
  for (const int span : kv.element_spans()) {
    const Eigen::MatrixXd c = bezier_extraction_operator(kv, span);
    EXPECT_GE(c.minCoeff(), 0.0);
    EXPECT_LE((c.colwise().sum().array() - 1.0).abs().maxCoeff(), 1e-15);  // partition of unity
  }
  // Interior knots of multiplicity p: the B-splines are the Bernstein polynomials of each element.
  const KnotVector bezier_knots(3, {0, 0, 0, 0, 0.4, 0.4, 0.4, 1, 1, 1, 1});
  for (const int span : bezier_knots.element_spans())
    EXPECT_LE((bezier_extraction_operator(bezier_knots, span) - Eigen::MatrixXd::Identity(4, 4)).norm(), 1e-15);
  EXPECT_THROW(bezier_extraction_operator(bezier_knots, 4), std::invalid_argument);   // empty span
  EXPECT_THROW(bezier_extraction_operator(bezier_knots, 7), std::invalid_argument);   // out of range
}

// Neighbouring elements agree on their common edge (the spline is continuous), so an output mesh may
// share those Bezier points.
TEST(BezierExtraction, NeighboursShareTheirCommonEdgePoints) {
  std::mt19937 rng(7);
  const KnotVector ku = mixed_knots(3), kv = mixed_knots(2);
  const int n = ku.num_basis() * kv.num_basis();
  const NurbsSurface surface(ku, kv, testing::random_points(rng, n), testing::random_weights(rng, n));
  const auto elements = bezier_elements(surface);
  const int per_row = ku.num_elements();
  const Eigen::MatrixXd points = as_columns(surface.control_points());
  for (std::size_t a = 0; a + 1 < elements.size(); ++a) {
    if ((a + 1) % per_row == 0) continue;  // last of its row
    const auto &left = elements[a], &right = elements[a + 1];
    const Eigen::MatrixXd xl = left.extract(points), xr = right.extract(points);
    for (int l = 0; l <= 2; ++l) {
      EXPECT_NEAR(left.weights[3 + 4 * l], right.weights[4 * l], 1e-14);
      EXPECT_LE((xl.col(3 + 4 * l) - xr.col(4 * l)).norm(), 1e-14);
    }
  }
}

}  // namespace
}  // namespace fibrane::spline
