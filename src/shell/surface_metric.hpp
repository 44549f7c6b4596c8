#pragma once
// Differential geometry of the shell midsurface at one point (Sec. 3.1.1), shared by the point kernel, the
// section-force evaluation and the materials (material.hpp).
//
// Symmetric 2x2 surface tensors are stored in Voigt order (11, 22, 12). Strain-like quantities carry the
// engineering factor 2 on the 12 entry, so that E_ab C^abcd E_cd = e^T D e with D_ij = C^{(i)(j)} and the
// stress-like vector D e holds exactly (N^11, N^22, N^12).
#include <Eigen/Dense>

#include "shell/kl_shell.hpp"

namespace fibrane::shell {

// The first and second fundamental forms of the midsurface at one point, with the base vectors they come
// from; the same struct serves the reference (G_a, G_ab, B_ab, ...) and the current configuration.
struct SurfaceMetric {
  Eigen::Vector3d g1, g2;          // covariant base vectors g_a = r_,a (Eq. 10)
  Eigen::Vector3d g11, g22, g12;   // second parametric derivatives r_,ab
  Eigen::Vector3d normal;          // n = g1 x g2 / |g1 x g2| (Eq. 12)
  double area_jacobian = 0.0;      // j = |g1 x g2| = sqrt(det g_ab) (Eq. 13)
  Eigen::Vector3d metric;          // g_ab in Voigt order (11, 22, 12), no factor 2
  Eigen::Matrix2d inverse_metric;  // g^ab (Eq. 11)
  Eigen::Vector3d dual1, dual2;    // contravariant base vectors g^a = g^ab g_b (Eq. 11)
  Eigen::Vector3d curvature;       // b_ab = n . g_a,b (Eq. 15) in Voigt order, no factor 2
};

// Evaluates the metric of the surface r = sum_A R_A points_A. `points` has one column per basis function.
SurfaceMetric surface_metric(const BasisDerivs& R, const Eigen::Matrix3Xd& points);

// Voigt strain vectors with engineering 12 entries: membrane strain E_ab = (g_ab - G_ab)/2 (Eq. 17) and
// change of curvature K_ab = b_ab - B_ab (Eq. 18).
inline Eigen::Vector3d membrane_strain(const SurfaceMetric& cur, const SurfaceMetric& ref) {
  const Eigen::Vector3d d = cur.metric - ref.metric;
  return {0.5 * d[0], 0.5 * d[1], d[2]};
}
inline Eigen::Vector3d curvature_change(const SurfaceMetric& cur, const SurfaceMetric& ref) {
  const Eigen::Vector3d d = cur.curvature - ref.curvature;
  return {d[0], d[1], 2.0 * d[2]};
}

}  // namespace fibrane::shell
