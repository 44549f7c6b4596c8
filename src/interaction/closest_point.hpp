#pragma once
// Closest-point projection of points (beam quadrature points) onto the CURRENT shell mid-surface,
// paper Eqs. (62)-(64): find theta-hat with (r_B - r_S(theta-hat)) . g_alpha(theta-hat) = 0.
//
// Search: every element's control points bound the element (convex-hull property of NURBS with positive
// weights), so an axis-aligned box of them is a lower bound of the distance to the element. A bounding-
// volume hierarchy over these boxes is traversed best-first (branch and bound); each surviving element is
// sampled on a 3 x 3 grid of parameters, and the best sample starts Newton's method on the orthogonality
// condition (63) in the PATCH parameters (the basis is re-evaluated in whichever element the iterate lies,
// so iterations cross element boundaries freely).
//
// Outside-the-patch policy: Newton is projected onto the closed parameter domain. If the iterate ends on
// the domain boundary with the distance still decreasing outward (the stationary point of (63) lies
// outside the patch), the result is `outside`: point / distance / normal then describe the nearest point
// ON the boundary, but it is NOT an orthogonal projection (n-hat is not the surface normal) and the SBS
// kernel must not be applied (the lead skips such points: no interaction). A stationary point ON the
// boundary (within round-off) is `interior`. A stationary point where the distance is not a minimum
// (C_ab of Eq. C3, the Hessian of |p - r|^2 / 2, has a negative eigenvalue: a point in a mirror plane above
// a groove narrower than the distance) is left along the direction of negative curvature, and Newton goes
// on to the minimum beside it. `failed`: no convergence, or a degenerate stationary point (C_ab singular
// without negative curvature, e.g. a point at the centre of a spherical patch).
#include <Eigen/Dense>
#include <optional>
#include <vector>

#include "spline/surface.hpp"

namespace fibrane::interaction {

class ShellProximity {
 public:
  explicit ShellProximity(const spline::NurbsSurface& reference);

  // Rebuild the element boxes and the hierarchy for the current control points (ordered as the
  // reference surface's). Call once per Newton iteration of the global problem.
  void update(const std::vector<Eigen::Vector3d>& current_control_points);

  struct Projection {
    enum class Where { interior, outside, failed } where = Where::failed;
    int element = -1;               // index into reference.elements()
    double u = 0, v = 0;            // theta-hat
    double distance = 0;            // d = |r_B - r_S(theta-hat)|
    Eigen::Vector3d point, normal;  // r_S(theta-hat) and n-hat = (r_B - r_S)/d (Eq. 64)
    int iterations = 0;             // Newton iterations on Eq. (63)
    // Smallest eigenvalue of C_ab relative to g_ab (Eq. C3) at theta-hat: 1 - d kappa along the direction
    // in which the shell curves most toward the point. Near 0 the shell is bent around the point at a
    // radius close to the distance, and theta-hat is (nearly) not unique.
    double relative_curvature = 1;
  };

  // Global search then Newton; with `start` (e.g. the previous iteration's theta-hat) Newton starts there
  // and the global search only checks that no other element holds a closer point: closer by more than the
  // fraction `keep_margin` of the distance (0: any closer point wins). A margin keeps a point on the
  // branch it is on where two local minima are nearly equally close (a shell folded under a fiber's end),
  // instead of switching at every Newton iterate.
  Projection project(const Eigen::Vector3d& p, const std::optional<Eigen::Vector2d>& start = std::nullopt,
                     double keep_margin = 0.0) const;

  // The shell point at the given parameters, with distance and n-hat = (p - r_S) / d (not a projection:
  // `interior` whatever the parameters; for comparing a previous closest point with the new one).
  Projection at(const Eigen::Vector3d& p, const Eigen::Vector2d& theta) const;

  // The element (index into elements()) whose closed parameter box holds (u, v); the knot-span rule of
  // KnotVector::find_span decides on shared edges.
  int element_at(double u, double v) const;
  const spline::NurbsSurface& surface() const { return surface_; }
  const std::vector<spline::SurfaceElement>& elements() const { return elements_; }
  const std::vector<Eigen::Vector3d>& control_points() const { return points_; }

 private:
  struct Node {
    Eigen::AlignedBox3d box;
    int left = -1, right = -1;  // children (internal node) or -1 (leaf)
    int first = 0, count = 0;   // range in order_ (leaf)
  };
  struct Candidate {
    double squared_distance;
    Eigen::Vector2d theta;
  };
  int build(int first, int count);
  // Best-first traversal: the best 3 x 3 sample over all elements whose box is closer than `bound`
  // (squared). Returns nullopt if no sample beats the bound.
  std::optional<Candidate> global_candidate(const Eigen::Vector3d& p, double bound) const;
  Projection newton(const Eigen::Vector3d& p, Eigen::Vector2d theta) const;

  spline::NurbsSurface surface_;
  std::vector<spline::SurfaceElement> elements_;
  std::vector<std::vector<int>> element_points_;  // control points supporting each element
  // Basis values at the element's 3 x 3 sample parameters (rows), columns as element_points_: the
  // samples of the global search then cost one small product per element.
  std::vector<Eigen::Matrix<double, 9, Eigen::Dynamic>> element_samples_;
  std::vector<int> element_of_span_u_, element_of_span_v_;
  std::vector<Eigen::Vector3d> points_;
  std::vector<Eigen::AlignedBox3d> boxes_;
  std::vector<int> order_;
  std::vector<Node> nodes_;
  double length_scale_ = 1;  // diagonal of the control-point box
};

}  // namespace fibrane::interaction
