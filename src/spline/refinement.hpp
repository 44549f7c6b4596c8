#pragma once
// Knot insertion and degree elevation of B-spline curves with homogeneous control points
// (w x, w y, w z, w). A NURBS curve is the projection of such a polynomial B-spline curve in 4D, so
// refining in homogeneous coordinates refines the NURBS geometry exactly. Surfaces apply these row by
// row (tensor product).
#include <Eigen/Dense>
#include <utility>
#include <vector>

#include "spline/knot_vector.hpp"

namespace fibrane::spline {

using HomogeneousPoints = std::vector<Eigen::Vector4d>;

struct HomogeneousCurve {
  KnotVector knots;
  HomogeneousPoints points;  // knots.num_basis() of them
};

// (w x, w y, w z, w) <-> (x, y, z), w.
HomogeneousPoints to_homogeneous(const std::vector<Eigen::Vector3d>& points,
                                 const std::vector<double>& weights);
void from_homogeneous(const HomogeneousPoints& hom, std::vector<Eigen::Vector3d>& points,
                      std::vector<double>& weights);

// Boehm's algorithm, applied `times` times. u must lie strictly inside the domain; a u within the knot
// tolerance of an existing knot is snapped onto it. Throws std::invalid_argument if the resulting
// multiplicity would exceed the degree.
HomogeneousCurve insert_knot(const HomogeneousCurve& curve, double u, int times = 1);

// Inserts all `values` at once (Piegl & Tiller's A5.4, RefineKnotVectCurve): O(n + r p) for r values on
// n control points, where inserting them one by one costs O(r n). The values may come in any order and
// repeat (a value twice is inserted twice); each must lie strictly inside the domain, and one within the
// knot tolerance of an existing knot is snapped onto it. Equals repeated insert_knot to round-off. Throws
// std::invalid_argument for a value outside the domain or a resulting multiplicity above the degree.
HomogeneousCurve insert_knots(const HomogeneousCurve& curve, const std::vector<double>& values);

// The insertions (value, times) of uniform_insertions or grid_insertions as the list of values insert_knots
// takes: each value repeated `times`.
std::vector<double> expand_insertions(const std::vector<std::pair<double, int>>& insertions);

// Raises the degree by `by` (>= 0). Every distinct knot gains `by` in multiplicity, so the continuity
// at each knot is preserved. Method: the elevated spline space contains the curve, so its control
// points are the unique interpolant of the curve at the Greville abscissae of the new knot vector
// (Schoenberg-Whitney holds there); the collocation system is small, banded and well conditioned.
HomogeneousCurve elevate_degree(const HomogeneousCurve& curve, int by = 1);

// Knot insertions (value, times) for uniform h-refinement of a spline of degree `degree` on the knots
// `kv` (already of that degree): each grid value a + (b-a) k / n_elements, k = 1..n-1, is brought to
// multiplicity degree - continuity, counting the multiplicity it already has and never lowering it.
std::vector<std::pair<double, int>> uniform_insertions(const KnotVector& kv, int continuity,
                                                       int n_elements);

// Knot insertions for h-refinement on an arbitrary grid: each value of `grid` (strictly inside kv's domain,
// increasing) is brought to multiplicity degree - continuity, counting the multiplicity it already has
// and never lowering it.
std::vector<std::pair<double, int>> grid_insertions(const KnotVector& kv, int continuity,
                                                    const std::vector<double>& grid);

// The n_elements - 1 interior values a + (b - a) (r^k - 1) / (r^n - 1), k = 1..n-1, of a geometric grid on
// [a, b]: element k has the length h_0 r^k (r > 1: elements grow toward b; r < 1: toward a; r = 1:
// uniform, a + (b - a) k / n). Throws std::invalid_argument unless r > 0, n >= 1 and a < b.
std::vector<double> geometric_grid(double a, double b, int n_elements, double ratio);

// Checks shared by NurbsCurve::refine and NurbsSurface::refine; throws std::invalid_argument.
void check_refine_request(int current_degree, int degree, int continuity, int n_elements);

}  // namespace fibrane::spline
