// Neo-Hookean shell materials: a 3-D law with plane stress, integrated through the thickness ([K15] in
// material.hpp).
//
// Kinematics at the thickness coordinate zeta in [-h/2, h/2] (Kirchhoff-Love, shifter neglected as in
// Eq. 29): the in-plane Green-Lagrange strain and right Cauchy-Green tensor, w.r.t. G^a x G^b,
//   E_ab(zeta) = e_ab + zeta k_ab,   C_ab = G_ab + 2 E_ab(zeta),   C_a3 = 0,  C33 = lambda_3^2,      (T1)
// (Eq. 24 writes the strain with -zeta; zeta -> -zeta maps the symmetric thickness interval and Gauss rule
// onto themselves, so Psi(e, k) below, and with it every section quantity, is the same.)
// with the reference midsurface metric G_ab and the unit normal as third base vector (G^33 = 1). C^ab is
// the inverse of C_ab, so (C^-1)^ab = C^ab and (C^-1)^33 = 1/C33. Section quantities (Eq. 28):
//   Psi = int psi dzeta,  N = int S dzeta,  M = int zeta S dzeta,                                  (T2)
//   dN/de = int D dzeta,  dN/dk = dM/de = int zeta D dzeta,  dM/dk = int zeta^2 D dzeta,            (T3)
// with S^ab the in-plane stress and D = dS/dE (Voigt) at plane stress, by Gauss-Legendre in zeta. For
// small strains psi = E:C:E/2 with a constant C, so (T2) gives Eq. 29 (h and h^3/12) for >= 2 points.
//
// Incompressible, psi = mu/2 (I1 - 3), I1 = G^ab C_ab + C33, with J = 1 imposed analytically:
//   C33 = det G_ab / det C_ab                                                                       (I1)
//   S^ab = 2 dpsi/dC_ab = mu (G^ab - C33 C^ab)      (using d(det C_ab)/dC_ab = det C_ab C^ab)       (I2)
//   D^abcd = 2 dS^ab/dC_cd = mu C33 (2 C^ab C^cd + C^ac C^bd + C^ad C^bc)                            (I3)
//
// Compressible: psi = mu/2 (I1 - 3) - mu ln J + lambda/2 (ln J)^2,  J^2 = C33 det C_ab / det G_ab.  (C1)
// Chosen because it is the standard neo-Hookean energy whose linearization at C = I is exactly Hooke's law
// with the Lame constants (so the small-strain limit is SVK, Eq. 26), and because its plane-stress
// condition is a scalar equation with a single root that Newton's method always finds (below).
//   S = mu (I - C^-1) + lambda ln J C^-1:  S^ab = mu G^ab + (lambda ln J - mu) C^ab,
//   S^33 = (mu (C33 - 1) + lambda ln J) / C33 = 0.                                                  (C2)
// With t = ln C33, g(t) = mu (e^t - 1) + lambda/2 (t + ln(det C_ab / det G_ab)) is increasing and convex
// (lambda >= 0), so Newton's method converges from any start; we start at the root of its linearization.
// 3-D tangent D = 2 dS/dC = lambda C^-1 x C^-1 + (mu - lambda ln J)(C^-1 (x) C^-1 symmetrized):
//   D^abcd = lambda C^ab C^cd + (mu - lambda ln J)(C^ac C^bd + C^ad C^bc),
//   D^ab33 = lambda C^ab / C33,  D^3333 = (lambda + 2 (mu - lambda ln J)) / C33^2,                    (C3)
// and with C33 following the in-plane strain so that S^33 stays 0 (dS^33 = D^33cd dE_cd + D^3333 dE_33 = 0),
// static condensation gives the plane-stress tangent
//   D^abcd - D^ab33 D^33cd / D^3333 = (lambda - lambda^2 / (lambda + 2 mu - 2 lambda ln J)) C^ab C^cd
//                                     + (mu - lambda ln J)(C^ac C^bd + C^ad C^bc).                   (C4)
// S^ab of (C2) is the derivative of the reduced energy psi(C_ab, C33(C_ab)) since dpsi/dC33 = S^33/2 = 0. (C5)
#include <cmath>
#include <limits>
#include <stdexcept>

#include "common/gauss_legendre.hpp"
#include "shell/material.hpp"

namespace fibrane::shell {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Voigt index -> tensor index pair: 0 -> 11, 1 -> 22, 2 -> 12.
constexpr int kFirst[3] = {0, 1, 0};
constexpr int kSecond[3] = {0, 1, 1};

// G^ab C_ab for symmetric 2x2 tensors.
double contract(const Eigen::Matrix2d& a, const Eigen::Matrix2d& b) {
  return a(0, 0) * b(0, 0) + 2.0 * a(0, 1) * b(0, 1) + a(1, 1) * b(1, 1);
}

PlaneStressPoint not_a_state() {
  PlaneStressPoint p;
  p.energy = p.s_metric = p.s_inverse = p.t_outer = p.t_sym = p.stretch33 = kNaN;
  return p;
}

// Voigt matrix of t_outer C^ab C^cd + t_sym (C^ac C^bd + C^ad C^bc).
Eigen::Matrix3d voigt_tangent(const PlaneStressPoint& p, const Eigen::Matrix2d& Ci) {
  Eigen::Matrix3d D;
  for (int i = 0; i < 3; ++i) {
    const int a = kFirst[i], b = kSecond[i];
    for (int j = i; j < 3; ++j) {
      const int c = kFirst[j], d = kSecond[j];
      D(i, j) = D(j, i) = p.t_outer * Ci(a, b) * Ci(c, d) + p.t_sym * (Ci(a, c) * Ci(b, d) + Ci(a, d) * Ci(b, c));
    }
  }
  return D;
}

}  // namespace

ThicknessIntegratedMaterial::ThicknessIntegratedMaterial(int points) {
  if (points < 1) throw std::invalid_argument("shell material: needs at least one thickness point");
  const QuadratureRule rule = gauss_legendre(points);
  for (int q = 0; q < points; ++q) {
    points_.push_back(0.5 * rule.points[q]);  // zeta / h on [-1/2, 1/2]
    weights_.push_back(0.5 * rule.weights[q]);
  }
}

SectionResponse ThicknessIntegratedMaterial::respond(const SurfaceMetric& ref, const SurfaceMetric& cur, double h,
                                                     bool tangent) const {
  const Eigen::Vector3d e = membrane_strain(cur, ref);  // (E11, E22, 2E12), Eq. 17
  const Eigen::Vector3d k = curvature_change(cur, ref);  // (K11, K22, 2K12), Eq. 18
  Eigen::Matrix2d G;
  G << ref.metric[0], ref.metric[2], ref.metric[2], ref.metric[1];
  const Eigen::Matrix2d& Ginv = ref.inverse_metric;

  SectionResponse r;
  r.coupled = true;
  r.N.setZero();
  r.M.setZero();
  if (tangent) r.dN_de.setZero(), r.dN_dk.setZero(), r.dM_dk.setZero();
  for (std::size_t q = 0; q < points_.size(); ++q) {
    const double zeta = h * points_[q], w = h * weights_[q];
    const Eigen::Vector3d E = e + zeta * k;  // (T1)
    Eigen::Matrix2d C;
    C << G(0, 0) + 2.0 * E[0], G(0, 1) + E[2], G(0, 1) + E[2], G(1, 1) + 2.0 * E[1];
    const Eigen::Matrix2d Cinv = C.inverse();
    const PlaneStressPoint p = plane_stress(C, G, Ginv);
    Eigen::Vector3d S;
    for (int i = 0; i < 3; ++i)
      S[i] = p.s_metric * Ginv(kFirst[i], kSecond[i]) + p.s_inverse * Cinv(kFirst[i], kSecond[i]);
    r.energy += w * p.energy;  // (T2)
    r.N += w * S;
    r.M += (w * zeta) * S;
    if (tangent) {  // (T3)
      const Eigen::Matrix3d D = voigt_tangent(p, Cinv);
      r.dN_de += w * D;
      r.dN_dk += (w * zeta) * D;
      r.dM_dk += (w * zeta * zeta) * D;
    }
  }
  if (tangent) r.dM_de = r.dN_dk.transpose();
  return r;
}

NeoHookeanMaterial::NeoHookeanMaterial(double young, double poisson, int thickness_points)
    : ThicknessIntegratedMaterial(thickness_points) {
  if (!(young > 0.0) || !(poisson >= 0.0 && poisson < 0.5))
    throw std::invalid_argument("NeoHookeanMaterial: needs young > 0 and 0 <= poisson < 0.5");
  mu_ = young / (2.0 * (1.0 + poisson));
  lambda_ = young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson));
}

PlaneStressPoint NeoHookeanMaterial::plane_stress(const Eigen::Matrix2d& C, const Eigen::Matrix2d& G,
                                                  const Eigen::Matrix2d& Ginv) const {
  const double det_ratio = C.determinant() / G.determinant();  // in-plane J^2
  if (!(det_ratio > 0.0)) return not_a_state();
  const double log_det = std::log(det_ratio);
  // Newton's method on g(t) = mu (e^t - 1) + lambda/2 (t + log_det), t = ln C33 (C2); the start is the
  // root of the linearization mu t + lambda/2 (t + log_det).
  double t = -lambda_ * log_det / (2.0 * mu_ + lambda_);
  bool converged = false;
  for (int it = 0; it < 50 && !converged; ++it) {
    const double g = mu_ * std::expm1(t) + 0.5 * lambda_ * (t + log_det);
    const double step = g / (mu_ * std::exp(t) + 0.5 * lambda_);
    t -= step;
    converged = std::abs(step) <= 1e-14 * (1.0 + std::abs(t));
  }
  if (!converged) return not_a_state();
  const double c33 = std::exp(t);
  const double log_j = 0.5 * (t + log_det);
  PlaneStressPoint p;
  p.stretch33 = c33;
  p.energy = 0.5 * mu_ * (contract(Ginv, C) + c33 - 3.0) - mu_ * log_j + 0.5 * lambda_ * log_j * log_j;  // (C1)
  p.s_metric = mu_;                          // (C2)
  p.s_inverse = lambda_ * log_j - mu_;
  const double shear = mu_ - lambda_ * log_j;  // (C3): D^abcd
  const double d33cd = lambda_ / c33;          // D^ab33 = d33cd C^ab
  const double d3333 = (lambda_ + 2.0 * shear) / (c33 * c33);
  p.t_outer = lambda_ - d33cd * d33cd / d3333;  // (C4): static condensation
  p.t_sym = shear;
  return p;
}

IncompressibleNeoHookeanMaterial::IncompressibleNeoHookeanMaterial(double shear_modulus, int thickness_points)
    : ThicknessIntegratedMaterial(thickness_points), mu_(shear_modulus) {
  if (!(shear_modulus > 0.0)) throw std::invalid_argument("IncompressibleNeoHookeanMaterial: needs mu > 0");
}

PlaneStressPoint IncompressibleNeoHookeanMaterial::plane_stress(const Eigen::Matrix2d& C, const Eigen::Matrix2d& G,
                                                                const Eigen::Matrix2d& Ginv) const {
  const double det_c = C.determinant();
  if (!(det_c > 0.0)) return not_a_state();
  PlaneStressPoint p;
  p.stretch33 = G.determinant() / det_c;                     // (I1)
  p.energy = 0.5 * mu_ * (contract(Ginv, C) + p.stretch33 - 3.0);
  p.s_metric = mu_;                                          // (I2)
  p.s_inverse = -mu_ * p.stretch33;
  p.t_outer = 2.0 * mu_ * p.stretch33;                       // (I3)
  p.t_sym = mu_ * p.stretch33;
  return p;
}

}  // namespace fibrane::shell
