#pragma once
// Nonlinear Kirchhoff-Love shell, Sec. 3.1 of the paper (Eqs. 8-31) and its linearization (Appendix A),
// with the material behind ShellMaterial (material.hpp; St. Venant-Kirchhoff, Eq. 26, or neo-Hookean).
// Everything here is a pure function of the basis functions at ONE quadrature point and of the element's
// reference/current control points: no mesh.
#include <Eigen/Dense>
#include <memory>
#include <vector>

namespace fibrane::shell {

class ShellMaterial;

// The shell's cross-section: thickness h and the material that turns strains into section forces.
struct ShellSection {
  double thickness = 0.0;                         // h
  std::shared_ptr<const ShellMaterial> material;  // never null in a section the kernel is given

  // St. Venant-Kirchhoff section (Eq. 26): Young's modulus E, Poisson's ratio nu, thickness h.
  static ShellSection svk(double young, double poisson, double thickness);
};

// Rational basis functions at one point of the surface and their parametric derivatives:
// rows 0..5 = R, R_1, R_2, R_11, R_12, R_22; one column per control point of the element.
using BasisDerivs = Eigen::Matrix<double, 6, Eigen::Dynamic>;

// Largest number of element control points the kernel handles (its scratch space lives on the stack).
inline constexpr int kMaxShellNodes = 100;

// The tangent of one element, summed over its quadrature points. Entry (3A + i, 3B + j) of the upper node
// blocks (B >= A) is stored at row(A, i, j)[B]: contiguous in the column node B, so that the kernel's loop
// over B vectorises (the 3 x 3 block-at-a-time form spent ~50 cycles per node pair, mostly scalar).
// add_to() adds the blocks and their transposes into an ordinary 3 nen x 3 nen matrix once per element.
class ElementTangent {
 public:
  // Zeroes the accumulator for an element with `nen` control points; allocates only when it grows.
  void reset(int nen);
  int nodes() const { return nen_; }
  double* row(int A, int i, int j) { return data_.data() + static_cast<std::size_t>(9 * A + 3 * i + j) * nen_; }
  const double* row(int A, int i, int j) const {
    return data_.data() + static_cast<std::size_t>(9 * A + 3 * i + j) * nen_;
  }
  // k += the accumulated tangent (both triangles); k must be 3 nen x 3 nen.
  void add_to(Eigen::MatrixXd& k) const;

 private:
  int nen_ = 0;
  std::vector<double> data_;
};

// Adds the quadrature point's contribution, multiplied by `weight` (Gauss weight times the parent-to-
// parametric Jacobian; the kernel multiplies by the reference area Jacobian J_S itself), to whichever of
// energy / residual / tangent is non-null. DOF order: [x_0, y_0, z_0, x_1, ...] (3 per control point).
// X: reference control points (3 x nen), x: current control points (3 x nen).
// residual = dPi/du (internal virtual work, Eq. 28); tangent = d residual / du (Appendix A).
// `residual` and `tangent` must already have size 3 nen (x 3 nen); they are accumulated into.
// Throws std::invalid_argument on inconsistent sizes, nen > kMaxShellNodes or a section without material.
// Does not allocate (the material must not either: see ShellMaterial).
// The element loop's form: `tangent` accumulates until ElementTangent::add_to (reset to nen before).
void add_shell_point(const ShellSection& s, const BasisDerivs& R, const Eigen::Matrix3Xd& X,
                     const Eigen::Matrix3Xd& x, double weight, double* energy, Eigen::VectorXd* residual,
                     ElementTangent* tangent);
// Energy and residual only.
inline void add_shell_point(const ShellSection& s, const BasisDerivs& R, const Eigen::Matrix3Xd& X,
                            const Eigen::Matrix3Xd& x, double weight, double* energy, Eigen::VectorXd* residual) {
  add_shell_point(s, R, X, x, weight, energy, residual, static_cast<ElementTangent*>(nullptr));
}
// The same for a single point into a matrix (tests, tools): allocates a scratch ElementTangent.
void add_shell_point(const ShellSection& s, const BasisDerivs& R, const Eigen::Matrix3Xd& X,
                     const Eigen::Matrix3Xd& x, double weight, double* energy, Eigen::VectorXd* residual,
                     Eigen::MatrixXd* tangent);

// Strain measures and section forces at a point.
//  E, K:   covariant components E_ab (Eq. 17) and K_ab (Eq. 18), w.r.t. the reference dual basis G^a x G^b.
//  N, M:   contravariant section forces/moments N^ab, M^ab (Eq. 28; Eq. 29 for SVK), w.r.t. the reference basis G_a x G_b;
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
