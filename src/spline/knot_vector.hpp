#pragma once
// Open (clamped) knot vectors for B-splines and NURBS.
//
// Conventions used throughout fibrane::spline:
//  * The parameter domain is [front(), back()] as given by the knots; the shape generators in
//    shapes.hpp always use [0, 1].
//  * Knots are "open": the first and the last knot are repeated exactly degree + 1 times, so a curve
//    interpolates its first and last control points. Interior knots may be repeated up to `degree`
//    times; a knot of multiplicity m gives C^(degree - m) continuity there.
//  * Two knots closer than 1e-12 * (back - front) count as the same knot (multiplicity, element count).
#include <vector>

namespace fibrane::spline {

class KnotVector {
 public:
  // Validates the knots and throws std::invalid_argument with a message naming what is wrong.
  KnotVector(int degree, std::vector<double> knots);

  // [a,...,a (p+1 times), interior grid a + (b-a) k/n each repeated p - continuity times, b,...,b].
  // Requires degree >= 1, n_elements >= 1, 0 <= continuity <= degree - 1, a < b.
  static KnotVector open_uniform(int degree, int n_elements, int continuity, double a = 0.0,
                                 double b = 1.0);

  int degree() const { return degree_; }
  const std::vector<double>& knots() const { return knots_; }
  int num_basis() const { return static_cast<int>(knots_.size()) - degree_ - 1; }

  // Span i with knots[i] <= u < knots[i+1]; u == back() gives the last non-empty span. Parameters a
  // hair outside the domain (|excess| <= 1e-10 (back - front), e.g. round-off of a mapped Gauss point)
  // are clamped; anything further out throws std::out_of_range.
  int find_span(double u) const;

  int num_elements() const;                // number of non-empty knot spans
  std::vector<int> element_spans() const;  // span index of each element, increasing
  double front() const { return knots_.front(); }
  double back() const { return knots_.back(); }
  std::vector<double> unique_knots() const;  // distinct knot values, increasing
  int multiplicity(double u) const;          // 0 if u is not a knot
  double tolerance() const;                  // 1e-12 * (back - front): "same knot" threshold

 private:
  int degree_;
  std::vector<double> knots_;
};

}  // namespace fibrane::spline
