#pragma once
// Nonlinear Kirchhoff-Love shell with a St. Venant-Kirchhoff (plane stress) material, Sec. 3.1 of the
// paper (Eqs. 8-31) and its linearization (Appendix A). Everything here is a pure function of the basis
// functions at ONE quadrature point and of the element's reference/current control points: no mesh.
#include <Eigen/Dense>

namespace fibrane::shell {

struct ShellSection {
  double young;      // Young's modulus E
  double poisson;    // Poisson's ratio nu
  double thickness;  // h
};

// Rational basis functions at one point of the surface and their parametric derivatives:
// rows 0..5 = R, R_1, R_2, R_11, R_12, R_22; one column per control point of the element.
using BasisDerivs = Eigen::Matrix<double, 6, Eigen::Dynamic>;

// Largest number of element control points the kernel handles (its scratch space lives on the stack).
inline constexpr int kMaxShellNodes = 100;

// Adds the quadrature point's contribution, multiplied by `weight` (Gauss weight times the parent-to-
// parametric Jacobian; the kernel multiplies by the reference area Jacobian J_S itself), to whichever of
// energy / residual / tangent is non-null. DOF order: [x_0, y_0, z_0, x_1, ...] (3 per control point).
// X: reference control points (3 x nen), x: current control points (3 x nen).
// residual = dPi/du (internal virtual work, Eq. 28); tangent = d residual / du (Appendix A).
// `residual` and `tangent` must already have size 3 nen (x 3 nen); they are accumulated into.
// Throws std::invalid_argument on inconsistent sizes or nen > kMaxShellNodes. Does not allocate.
void add_shell_point(const ShellSection& s, const BasisDerivs& R, const Eigen::Matrix3Xd& X,
                     const Eigen::Matrix3Xd& x, double weight, double* energy, Eigen::VectorXd* residual,
                     Eigen::MatrixXd* tangent);

// Strain measures and section forces at a point.
//  E, K:   covariant components E_ab (Eq. 17) and K_ab (Eq. 18), w.r.t. the reference dual basis G^a x G^b.
//  N, M:   contravariant section forces/moments N^ab, M^ab (Eq. 29), w.r.t. the reference basis G_a x G_b;
//          N^ab = d(energy density)/dE_ab, M^ab = d(energy density)/dK_ab.
//  N_local, M_local: the push-forward (J_S/j_S) N^ab g_a x g_b (force / moment per CURRENT length, the
//          thickness-integrated Cauchy stress) in the orthonormal frame e1 = g1/|g1|, e2 = n x e1.
struct SectionForces {
  Eigen::Matrix2d N, M;
  Eigen::Matrix2d N_local, M_local;
  Eigen::Matrix2d E, K;
};
SectionForces section_forces(const ShellSection& s, const BasisDerivs& R, const Eigen::Matrix3Xd& X,
                             const Eigen::Matrix3Xd& x);

}  // namespace fibrane::shell
