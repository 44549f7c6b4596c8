// Section forces and moments (Eq. 28, from the section's material) for output: reference contravariant
// components and their push-forward to a local orthonormal frame of the current configuration.
#include <stdexcept>

#include "shell/kl_shell.hpp"
#include "shell/material.hpp"
#include "shell/surface_metric.hpp"

namespace fibrane::shell {
namespace {

// Voigt (11, 22, 12) -> symmetric 2x2; `shear_factor` undoes the engineering factor 2 of strains.
Eigen::Matrix2d from_voigt(const Eigen::Vector3d& v, double shear_factor) {
  Eigen::Matrix2d m;
  m << v[0], shear_factor * v[2], shear_factor * v[2], v[1];
  return m;
}

}  // namespace

SectionForces section_forces(const ShellSection& s, const BasisDerivs& R, const Eigen::Matrix3Xd& X,
                             const Eigen::Matrix3Xd& x) {
  if (X.cols() != R.cols() || x.cols() != R.cols())
    throw std::invalid_argument("section_forces: basis and control points disagree on the node count");
  if (!s.material) throw std::invalid_argument("section_forces: the section has no material");
  const SurfaceMetric ref = surface_metric(R, X);
  const SurfaceMetric cur = surface_metric(R, x);
  const SectionResponse response = s.material->respond(ref, cur, s.thickness, false);

  SectionForces out;
  out.E = from_voigt(membrane_strain(cur, ref), 0.5);
  out.K = from_voigt(curvature_change(cur, ref), 0.5);
  out.N = from_voigt(response.N, 1.0);
  out.M = from_voigt(response.M, 1.0);

  // Push-forward n = (J_S / j_S) N^ab g_a x g_b, expressed in e1 = g1/|g1|, e2 = n x e1:
  // components T N T^T with T_ia = e_i . g_a.
  const Eigen::Vector3d e1 = cur.g1.normalized();
  const Eigen::Vector3d e2 = cur.normal.cross(e1);
  Eigen::Matrix2d T;
  T << e1.dot(cur.g1), e1.dot(cur.g2), e2.dot(cur.g1), e2.dot(cur.g2);
  const double area_ratio = ref.area_jacobian / cur.area_jacobian;
  out.N_local = area_ratio * T * out.N * T.transpose();
  out.M_local = area_ratio * T * out.M * T.transpose();
  return out;
}

}  // namespace fibrane::shell
