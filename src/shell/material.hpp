#pragma once
// Shell materials: the section response of the Kirchhoff-Love shell (Sec. 3.1.3 of the paper) at one
// point, as a function of the midsurface strains only.
//
// A material sees the Voigt strains (engineering factor 2 on 12, see surface_metric.hpp)
//   e = (E11, E22, 2E12)  membrane strain, Eq. 17,     k = (K11, K22, 2K12)  change of curvature, Eq. 18,
// and returns the energy per unit reference area Psi(e, k) and its derivatives
//   N = dPsi/de = (N^11, N^22, N^12),  M = dPsi/dk = (M^11, M^22, M^12)      (Eqs. 28, 29)
// and, on request, the four 3 x 3 blocks dN/de, dN/dk, dM/de, dM/dk of the second derivative.
//
// Three materials:
//  - SvkMaterial: St. Venant-Kirchhoff with the plane-stress matrix of Eq. 26 integrated analytically
//    through the thickness (Eq. 29): N = h D e, M = h^3/12 D k, no membrane-bending coupling.
//  - NeoHookeanMaterial, IncompressibleNeoHookeanMaterial: a 3-D hyperelastic law evaluated at the
//    equidistant strain E_ab(zeta) = e_ab + zeta k_ab and integrated numerically in zeta over
//    [-h/2, h/2] (Kiendl, Hsu, Wu, Reali 2015, "Isogeometric Kirchhoff-Love shell formulations for general
//    hyperelastic materials", CMAME 291; called [K15] below). Their equations are (T1)-(T3), (I1)-(I3)
//    and (C1)-(C5) in neo_hookean.cpp.
#include <Eigen/Dense>
#include <memory>
#include <vector>

#include "common/registry.hpp"
#include "shell/surface_metric.hpp"

namespace fibrane::shell {

// The section response at one point (all per unit reference area; Voigt order 11, 22, 12).
// `coupled` is false when the cross blocks dN/dk and dM/de vanish identically (then they are not set and
// the kernel skips them); the diagonal blocks are set only when a tangent was asked for.
struct SectionResponse {
  double energy = 0.0;
  Eigen::Vector3d N, M;
  Eigen::Matrix3d dN_de, dN_dk, dM_de, dM_dk;
  bool coupled = false;
};

// A hyperelastic shell material: the section response from the reference and current metrics at a point.
// It reads the `metric`, `inverse_metric` and `curvature` fields of both SurfaceMetrics (strains by
// Eqs. 17, 18); implementations are immutable and thread-safe, and must not allocate in respond().
class ShellMaterial {
 public:
  virtual ~ShellMaterial() = default;
  // Energy, N and M at the point; with `tangent` also the four blocks (the cross blocks when `coupled`).
  virtual SectionResponse respond(const SurfaceMetric& reference, const SurfaceMetric& current, double thickness,
                                  bool tangent) const = 0;
};

// Plane-stress St. Venant-Kirchhoff matrix per unit thickness in Voigt form, Eq. 26 written with the
// reference metric: C^abcd = E/(1-nu^2) [nu G^ab G^cd + (1-nu)/2 (G^ac G^bd + G^ad G^bc)].
Eigen::Matrix3d plane_stress_matrix(double young, double poisson, const Eigen::Matrix2d& inverse_reference_metric);

// St. Venant-Kirchhoff (Eqs. 25, 26, 29): Psi = h/2 e.D.e + h^3/24 k.D.k with D = plane_stress_matrix.
class SvkMaterial final : public ShellMaterial {
 public:
  // young > 0, -1 < poisson < 0.5 (std::invalid_argument otherwise).
  SvkMaterial(double young, double poisson);
  SectionResponse respond(const SurfaceMetric& reference, const SurfaceMetric& current, double thickness,
                          bool tangent) const override;
  double young() const { return young_; }      // E
  double poisson() const { return poisson_; }  // nu

 private:
  double young_, poisson_;
};

// The plane-stress state of a 3-D law at one thickness point, in the reference basis: the in-plane second
// Piola-Kirchhoff stress S^ab = s_metric G^ab + s_inverse C^ab and its condensed tangent
// dS^ab/dE_cd = t_outer C^ab C^cd + t_sym (C^ac C^bd + C^ad C^bc), with C^ab = [C_ab]^-1 the inverse
// in-plane right Cauchy-Green tensor. Both neo-Hookean laws take this form.
struct PlaneStressPoint {
  double energy = 0.0;  // 3-D energy per unit reference volume
  double s_metric = 0.0, s_inverse = 0.0;
  double t_outer = 0.0, t_sym = 0.0;
  double stretch33 = 1.0;  // C33: the squared thickness stretch
};

// A 3-D hyperelastic law with plane stress imposed, integrated through the thickness with Gauss-Legendre
// points in zeta: Psi = int psi(e + zeta k) dzeta, N = int S dzeta, M = int zeta S dzeta, dN/de = int D,
// dN/dk = dM/de = int zeta D, dM/dk = int zeta^2 D (equations (T1)-(T3) in neo_hookean.cpp).
class ThicknessIntegratedMaterial : public ShellMaterial {
 public:
  // (T1)-(T3) summed over the thickness points; `coupled` is always true.
  SectionResponse respond(const SurfaceMetric& reference, const SurfaceMetric& current, double thickness,
                          bool tangent) const final;
  // The plane-stress state for the in-plane right Cauchy-Green tensor C_ab = G_ab + 2 E_ab (covariant,
  // w.r.t. G^a x G^b), the reference metric G_ab and its inverse G^ab; NaN entries if C_ab is not
  // positive definite or the plane-stress condition has no solution.
  virtual PlaneStressPoint plane_stress(const Eigen::Matrix2d& C, const Eigen::Matrix2d& G,
                                        const Eigen::Matrix2d& Ginv) const = 0;
  // Number of Gauss-Legendre points through the thickness.
  int thickness_points() const { return static_cast<int>(points_.size()); }

 protected:
  // `points` >= 1 Gauss-Legendre points through the thickness (std::invalid_argument otherwise).
  explicit ThicknessIntegratedMaterial(int points);

 private:
  std::vector<double> points_, weights_;  // on [-1/2, 1/2], weights summing to 1
};

// Compressible neo-Hookean, psi = mu/2 (I1 - 3) - mu ln J + lambda/2 (ln J)^2 (equation (C1)), with plane
// stress S^33 = 0 solved for C33 by a Newton iteration and the tangent condensed statically (C3)-(C5).
class NeoHookeanMaterial final : public ThicknessIntegratedMaterial {
 public:
  // Lame constants from young > 0, 0 <= poisson < 0.5: mu = E / (2 (1 + nu)),
  // lambda = E nu / ((1 + nu)(1 - 2 nu)) (std::invalid_argument otherwise).
  NeoHookeanMaterial(double young, double poisson, int thickness_points);
  PlaneStressPoint plane_stress(const Eigen::Matrix2d& C, const Eigen::Matrix2d& G,
                                const Eigen::Matrix2d& Ginv) const override;
  double mu() const { return mu_; }          // shear modulus
  double lambda() const { return lambda_; }  // Lame's first constant (3-D)

 private:
  double mu_, lambda_;
};

// Incompressible neo-Hookean, psi = mu/2 (I1 - 3) with J = 1, so C33 = det G_ab / det C_ab analytically
// (equations (I1)-(I3)).
class IncompressibleNeoHookeanMaterial final : public ThicknessIntegratedMaterial {
 public:
  // shear_modulus mu > 0 (std::invalid_argument otherwise).
  IncompressibleNeoHookeanMaterial(double shear_modulus, int thickness_points);
  PlaneStressPoint plane_stress(const Eigen::Matrix2d& C, const Eigen::Matrix2d& G,
                                const Eigen::Matrix2d& Ginv) const override;
  double mu() const { return mu_; }  // shear modulus

 private:
  double mu_;
};

// Gauss points through the thickness of the neo-Hookean materials when the case does not say.
inline constexpr int kDefaultThicknessPoints = 4;

// The materials by name, for case files (docs/case-format.md): svk {young, poisson},
// neo_hookean {young, poisson, thickness_points}, neo_hookean_incompressible {shear_modulus | young,
// thickness_points}. Unknown keys and invalid values are InputErrors located by the Parameters.
const Registry<std::shared_ptr<const ShellMaterial>>& material_registry();

}  // namespace fibrane::shell
