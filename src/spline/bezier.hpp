#pragma once
// Bezier extraction of NURBS curves and surfaces: every element (non-empty knot span) of a NURBS is a
// rational Bezier curve or tensor-product patch, which is how VTK's Bezier cells (and other viewers)
// draw the exact geometry.
//
// Extraction operator (Borden et al., "Isogeometric finite element data structures based on Bezier
// extraction of NURBS", IJNME 87, 2011). On the element [u0, u1] of span s, the p+1 B-splines that do
// not vanish there are polynomials, so
//     N_{s-p+i}(u) = sum_k C(i, k) B_k(t),   t = (u - u0) / (u1 - u0),   B_k(t) = binom(p,k) t^k (1-t)^(p-k),
// with the (p+1) x (p+1) extraction operator C. Column k of C holds the blossom of N_{s-p+i} at
// (u0 [p-k times], u1 [k times]), computed by de Boor's algorithm with those p arguments; every step is
// a convex combination, so C is exact to a few ulps.
//
// Rational geometry and fields. With local NURBS weights w_i and Bezier weights
//     wb_k = sum_i C(i, k) w_i                                   (wb = C^T w),
// the NURBS basis R_i = w_i N_i / W becomes sum_k C(i, k) w_i B_k / sum_k wb_k B_k. Hence a quantity
// f_i given per control point (a coordinate, a displacement, a twist, any k-vector) and interpolated by
// the rational basis, f(u) = sum_i R_i(u) f_i, equals the rational Bezier interpolation
//     f(u) = sum_k wb_k B_k(t) fb_k / sum_k wb_k B_k(t),   fb_k = sum_i C(i, k) w_i f_i / wb_k,
// i.e. every field is extracted in homogeneous form: weight it, apply C^T, divide by the Bezier weight.
// Control points are just the field f = x. The Bezier weights are > 0 because C >= 0 entrywise and
// every column of C has a positive entry (the B-splines sum to one).
//
// Surfaces are tensor products: C = C_u (x) C_v, applied as C_u^T F C_v to the (p+1) x (q+1) table of
// local values of each component.
#include <Eigen/Dense>
#include <vector>

#include "spline/curve.hpp"
#include "spline/knot_vector.hpp"
#include "spline/surface.hpp"

namespace fibrane::spline {

// Extraction operator C of the element on knot span `span` (kv.knots()[span] < kv.knots()[span+1]):
// N_{span-p+i} = sum_k C(i, k) B_k on that element (see the file comment). Throws
// std::invalid_argument for a span that is out of range or empty.
Eigen::MatrixXd bezier_extraction_operator(const KnotVector& kv, int span);

// One element of a NURBS curve or surface in rational Bezier form. A curve element has degree_v = 0
// (one Bezier point across), so curves and surfaces share the layout. Local NURBS control points are
// numbered a = i + (p+1) j (i along u), as SurfaceBasis::indices; Bezier points b = k + (p+1) l.
struct BezierElement {
  int degree_u = 0, degree_v = 0;
  int span_u = 0, span_v = 0;                // knot spans (span_v = 0 for a curve)
  double u0 = 0, u1 = 0, v0 = 0, v1 = 0;     // parameter box (v0 = v1 = 0 for a curve)
  std::vector<int> nurbs_indices;            // global indices of the local NURBS control points
  std::vector<double> nurbs_weights;         // their weights
  Eigen::MatrixXd extraction_u, extraction_v;  // C_u (p+1)x(p+1), C_v (q+1)x(q+1) (1x1 identity for a curve)
  std::vector<double> weights;               // Bezier weights wb_b

  // Number of Bezier points, (p+1)(q+1).
  int num_points() const { return (degree_u + 1) * (degree_v + 1); }

  // Extracts a per-control-point field. `values` has one column per GLOBAL control point of the NURBS
  // (k rows = components); the result has one column per Bezier point: fb_b of the file comment. The
  // rational Bezier interpolation of the result reproduces sum_i R_i f_i exactly.
  Eigen::MatrixXd extract(const Eigen::Ref<const Eigen::MatrixXd>& values) const;
  // The same for points (e.g. the reference or current control points): the Bezier control points.
  std::vector<Eigen::Vector3d> extract_points(const std::vector<Eigen::Vector3d>& points) const;
};

// The elements of a curve in increasing order of u (as KnotVector::element_spans()).
std::vector<BezierElement> bezier_elements(const NurbsCurve& curve);
// The elements of a surface, u fastest (the order of NurbsSurface::elements()).
std::vector<BezierElement> bezier_elements(const NurbsSurface& surface);

}  // namespace fibrane::spline
