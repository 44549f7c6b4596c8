#pragma once
// Section-beam interaction potential (SBIP, after Grill, Wall, Meier, arXiv 2208.03149) at ONE point of
// fiber A: A's circular cross section at its axis point x with tangent t_A, against the surrogate of fiber
// B, an infinite straight cylinder along B's tangent t_B at the point x_B of B's axis closest to x. Pure
// function of the axis data; no mesh. The law of the gap is laws/section_cylinder.hpp, which also states
// the small-separation form (S1)-(S2).
//
// Geometry (all evaluated exactly, with derivatives, in second-order forward AD, common/jet.hpp):
//   P = I - t_B t_B^T, D = P (x - x_B), d = |D|, n = D / d                  distance of x from B's axis
//   c = t_A . n, e = (n - c t_A) / sqrt(1 - c^2)       the in-section direction towards B's axis   (S3)
//   v = D - R_A P e, rho = |v|, nu = v / rho             the rim point x - R_A e seen from the axis
//   b = nu . e + G(rho - R_B) / (2 R_A)                 gap slope from the rim into the section,   (S4')
//                                   with the finite-section term of laws/section_cylinder.hpp
//   tau = t_A x e, a = b / (2 R_A) + (1 - (t_B.tau)^2 - (nu.tau)^2) / (2 rho)                       (S5)
//                                   rim curvature and cylinder curvature along the rim, h = g + a x^2 ...
//   g = rho - R_B - (nu . tau)^2 / (4 a)                the gap at the minimum along the rim        (S6)
//   pi = F(g) / (b sqrt(a))                                                                         (S1)
// For parallel fibers (S3)-(S6) give b = 1 + g / (2 R_A), a = b / (2 R_A) + 1 / (2 (R_B + g)); for the
// section of a crossed fiber closest to the other, b = 1 + g / (2 R_A), a = b / (2 R_A).
// Why SBIP and not a section-section law (SSIP, Borkovic et al.): one closest-point projection per
// quadrature point instead of a double integral over both fibers, the same structure as the paper's SBS
// (a section against a surrogate of the other body), and a closed form (S1) for every exponent m > 4.5.
// The closest point x_B = r_B(xi_B) satisfies (x - r_B) . r_B' = 0; its dependence on all DOFs enters
// exactly: xi_B + delta with delta solving the orthogonality condition to second order,
//   O(xi) = (x - r_B(xi)) . r_B'(xi),  delta_1 = -O / O',  delta = -(O + O'' delta_1^2 / 2) / O'.    (S7)
//
// End taper (optional): pi is multiplied by T(u) = u^2 (3 - 2 u) (C1: T(0) = T'(0) = 0, T(1) = 1,
// T'(1) = 0), u = s_end / l_T, s_end the reference arc length from x_B to B's nearer end, l_T the taper
// length; T = 1 for u >= 1. s_end moves with the closest point: its second-order expansion in the (S7)
// correction, s_end(xi_B) + s_end' delta + s_end'' delta^2 / 2, so that the taper's derivatives are exact.
//
// Local variables w (15): x, x_xi (A's axis derivative at the point, any parametrisation), r_B, r_B',
// r_B'' at xi_B; r_B''' enters (S7)'s second-order term as a value. The energy per unit length is pi; the
// caller multiplies by the weight (Gauss weight x REFERENCE arc length of A, the densities being
// reference ones as in the paper's Eq. 4).
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "laws/section_cylinder.hpp"

namespace fibrane::interaction {

// The end taper's data at x_B (see the file comment); length 0: no taper.
struct EndTaper {
  double s = 0, s_xi = 0, s_xixi = 0;  // s_end and its first two derivatives in B's parameter
  double length = 0;                   // l_T
};

struct SectionBeamPoint {
  Eigen::Vector3d x = Eigen::Vector3d::Zero(), x_xi = Eigen::Vector3d::UnitX();  // fiber A
  Eigen::Vector3d r[4] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY(), Eigen::Vector3d::Zero(),
                          Eigen::Vector3d::Zero()};  // fiber B: r_B and its first three xi-derivatives
  EndTaper taper;
};

struct SectionBeamResult {
  bool active = false;  // false: the gap is at or beyond the cut-off (everything below is zero)
  double energy = 0;    // pi per unit length (S1)
  double gap = 0;       // g (S6); d - R_A - R_B if the section is beyond the cut-off by that bound
  double distance = 0;  // d: from x to B's axis
  double cos_angle = 1; // |t_A . t_B|
  double slope = 1, curvature = 0;  // b (S4'), a (S5)
  double taper = 1;                 // the end taper's factor T (1 without a taper)
  Eigen::Matrix<double, 15, 1> gradient = Eigen::Matrix<double, 15, 1>::Zero();
  Eigen::Matrix<double, 15, 15> hessian = Eigen::Matrix<double, 15, 15>::Zero();
};

// pi and its exact gradient and Hessian in the local variables. Throws std::domain_error where the
// small-separation form has no value inside the cut-off: x on B's axis, A's tangent pointing at B's axis
// (1 - c^2 < 1e-12), b or a not positive (the section's rim turned away from B's axis), or, without
// regularization, g <= 0.
SectionBeamResult section_beam(const laws::SectionCylinderLaw& law, const SectionBeamPoint& p);

// Newton's method on (S7) for the parameter of B's axis closest to x, from `xi` within [lo, hi] (B's
// parameter domain), with the axis given by `axis(xi, derivatives)` -> r_B and derivatives (rows of a
// 3 x 4 matrix). Returns false if it does not converge or the stationary point lies outside [lo, hi].
template <class Axis>
bool closest_on_axis(const Eigen::Vector3d& x, const Axis& axis, double lo, double hi, double& xi);

// The kernel mapped to control points: A's basis (rows N, N_xi; nA columns) and current control points,
// B's basis at xi_B (rows N .. N_xixixi; nB columns) and control points. Adds weight * pi to *energy and
// the gradient / Hessian to residual / tangent in the DOF order [A CP_0: x, y, z, phi, ..., B CP_0: x, y,
// z, phi, ...] (sized 4 (nA + nB), or empty to be created zeroed; twist entries stay zero).
SectionBeamResult add_section_beam_point(const laws::SectionCylinderLaw& law,
                                         const Eigen::Matrix<double, 2, Eigen::Dynamic>& basis_a,
                                         const Eigen::Matrix3Xd& x_a,
                                         const Eigen::Matrix<double, 4, Eigen::Dynamic>& basis_b,
                                         const Eigen::Matrix3Xd& x_b, double weight, double* energy,
                                         Eigen::VectorXd* residual, Eigen::MatrixXd* tangent,
                                         const EndTaper& taper = {});

template <class Axis>
bool closest_on_axis(const Eigen::Vector3d& x, const Axis& axis, double lo, double hi, double& xi) {
  for (int it = 0; it < 50; ++it) {
    const Eigen::Matrix<double, 3, 4> r = axis(xi);
    const Eigen::Vector3d gap = x - r.col(0);
    const double g = gap.dot(r.col(1)), dg = gap.dot(r.col(2)) - r.col(1).squaredNorm();
    double step = dg < 0 ? -g / dg : (g > 0 ? 1.0 : -1.0) * 0.1 * (hi - lo);  // away from a maximum
    const double next = std::min(hi, std::max(lo, xi + step));
    step = next - xi;
    xi = next;
    if (std::abs(step) <= 1e-14 * (hi - lo)) {
      const Eigen::Matrix<double, 3, 4> rr = axis(xi);
      const double gg = (x - rr.col(0)).dot(rr.col(1));
      return std::abs(gg) <= 1e-12 * rr.col(1).norm() * ((x - rr.col(0)).norm() + rr.col(1).norm());
    }
  }
  return false;
}

}  // namespace fibrane::interaction
