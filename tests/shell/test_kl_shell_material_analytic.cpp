// Large-strain membrane states of a flat neo-Hookean sheet against closed-form solutions, evaluated
// through the point kernel on a flat patch under a prescribed homogeneous deformation x = F X,
// F = diag(l1, l2, 1), and through the material for the thickness stretch l3.
//
// Principal stretches l1, l2 (in-plane), l3 = sqrt(C33) (thickness); principal 2nd Piola-Kirchhoff
// stresses S_i; nominal (1st Piola-Kirchhoff) stress P_i = l_i S_i; membrane force per unit reference
// width h P_i; J = l1 l2 l3.
//  Incompressible, psi = mu/2 (l1^2 + l2^2 + l3^2 - 3), J = 1: l3 = 1 / (l1 l2), S_i = mu (1 - l3^2 / l_i^2)
//  (S^ab = mu (G^ab - C33 C^ab) in principal axes).
//   uniaxial (S_2 = 0): l2^2 = l3^2 = 1 / (l1 l2) gives l2 = l3 = l1^(-1/2), P_1 = mu (l1 - l1^-2);
//   equibiaxial (l1 = l2 = l): l3 = l^-2, P = mu (l - l^-5).
//  Compressible, psi = mu/2 (sum l_i^2 - 3) - mu ln J + lambda/2 (ln J)^2: S_i = mu (1 - l_i^-2) + lambda ln J
//  l_i^-2, and S_3 = 0 reads mu (l3^2 - 1) + lambda ln J = 0.
//   uniaxial (S_2 = S_3 = 0): l2 = l3 = s with mu (s^2 - 1) + lambda ln(l1 s^2) = 0;
//   equibiaxial: mu (l3^2 - 1) + lambda ln(l^2 l3) = 0.
// The scalar equations (increasing in s, resp. l3) are solved here by bisection.
//
// Through the kernel, with the reference patch X = a u + b v (area A = |a x b|): energy sum = A h psi;
// the residual's virtual work for the homogeneous virtual field delta u = e_i (e_i . X) is
// sum_A r_A,i X_A,i = A h P_i (Bernstein control points reproduce affine fields).
// All of these are exact for this model (homogeneous membrane state, constant through the thickness;
// 3 x 3 Gauss points integrate the quadratic patch's residual exactly), so the tolerance is round-off,
// 1e-10 relative, far inside the 0.5 % an approximate benchmark would be allowed.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "common/gauss_legendre.hpp"
#include "shell/bezier_patch.hpp"
#include "shell/material.hpp"

namespace fibrane::shell {
namespace {

constexpr double kTolerance = 1e-10;
constexpr double kThickness = 0.05;

// Root of an increasing function on [lo, hi] by bisection (to round-off).
double bisect(const std::function<double(double)>& f, double lo, double hi) {
  for (int i = 0; i < 200 && hi - lo > 1e-16 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (f(mid) < 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

struct Expected {
  double l1, l2, l3;  // stretches
  double psi;         // energy per reference volume
  double P1, P2;      // nominal stresses
};

struct KernelResult {
  double energy = 0.0, work1 = 0.0, work2 = 0.0;  // energy, sum r_A,x X_A,x, sum r_A,y X_A,y
};

// The kernel summed over 3 x 3 Gauss points of a flat biquadratic patch X = a u + b v stretched by F.
KernelResult through_kernel(const ShellSection& s, double l1, double l2) {
  const Eigen::Vector3d a(2.0, 0.0, 0.0), b(0.5, 1.5, 0.0);  // skewed: G_12 != 0
  Eigen::Matrix3Xd X(3, 9);
  for (int j = 0; j <= 2; ++j)
    for (int i = 0; i <= 2; ++i) X.col(i + 3 * j) = a * (i / 2.0) + b * (j / 2.0);
  const Eigen::Matrix3Xd x = Eigen::Vector3d(l1, l2, 1.0).asDiagonal() * X;
  const QuadratureRule g = gauss_legendre(3);
  KernelResult out;
  Eigen::VectorXd r = Eigen::VectorXd::Zero(27);
  for (int qv = 0; qv < 3; ++qv)
    for (int qu = 0; qu < 3; ++qu) {
      const BasisDerivs R = testing::bezier_basis(2, 2, 0.5 * (g.points[qu] + 1), 0.5 * (g.points[qv] + 1));
      add_shell_point(s, R, X, x, 0.25 * g.weights[qu] * g.weights[qv], &out.energy, &r);
    }
  for (int A = 0; A < 9; ++A) {
    out.work1 += r[3 * A] * X(0, A);
    out.work2 += r[3 * A + 1] * X(1, A);
  }
  return out;
}

// Checks the kernel's energy and virtual work and the material's thickness stretch against `e`.
void check(const ThicknessIntegratedMaterial& m, const Expected& e, const std::string& what) {
  const ShellSection s{kThickness, std::shared_ptr<const ShellMaterial>(&m, [](const ShellMaterial*) {})};
  const double area = 3.0, scale = area * kThickness;  // |a x b| = 3
  const KernelResult k = through_kernel(s, e.l1, e.l2);
  EXPECT_NEAR(k.energy, scale * e.psi, kTolerance * scale * e.psi) << what;
  EXPECT_NEAR(k.work1, scale * e.P1, kTolerance * scale * std::abs(e.P1)) << what;
  EXPECT_NEAR(k.work2, scale * e.P2, kTolerance * scale * std::max(std::abs(e.P1), std::abs(e.P2))) << what;
  const Eigen::Matrix2d I = Eigen::Matrix2d::Identity();
  const Eigen::Matrix2d C = Eigen::Vector2d(e.l1 * e.l1, e.l2 * e.l2).asDiagonal();
  EXPECT_NEAR(std::sqrt(m.plane_stress(C, I, I).stretch33), e.l3, kTolerance * e.l3) << what;
}

TEST(ShellMaterialAnalytic, IncompressibleUniaxialAndEquibiaxialStretch) {
  const double mu = 0.4;
  const IncompressibleNeoHookeanMaterial m(mu, 4);
  for (double l : {1.5, 2.0, 3.0}) {
    const double lt = 1.0 / std::sqrt(l);  // uniaxial: l2 = l3 = l^(-1/2)
    check(m, {l, lt, lt, 0.5 * mu * (l * l + 2.0 * lt * lt - 3.0), mu * (l - 1.0 / (l * l)), 0.0},
          "uniaxial " + std::to_string(l));
    const double l3 = 1.0 / (l * l);  // equibiaxial
    const double P = mu * (l - std::pow(l, -5));
    check(m, {l, l, l3, 0.5 * mu * (2.0 * l * l + l3 * l3 - 3.0), P, P}, "equibiaxial " + std::to_string(l));
  }
}

TEST(ShellMaterialAnalytic, CompressibleUniaxialAndEquibiaxialStretch) {
  const double young = 1000.0, nu = 0.3;
  const NeoHookeanMaterial m(young, nu, 4);
  const double mu = young / (2 * (1 + nu)), lambda = young * nu / ((1 + nu) * (1 - 2 * nu));
  auto psi = [&](double l1, double l2, double l3) {
    const double log_j = std::log(l1 * l2 * l3);
    return 0.5 * mu * (l1 * l1 + l2 * l2 + l3 * l3 - 3.0) - mu * log_j + 0.5 * lambda * log_j * log_j;
  };
  auto nominal = [&](double li, double j) { return li * (mu * (1.0 - 1.0 / (li * li)) + lambda * std::log(j) / (li * li)); };
  for (double l : {1.3, 1.8, 2.5}) {
    const double s = bisect([&](double t) { return mu * (t * t - 1.0) + lambda * std::log(l * t * t); }, 0.05, 1.0);
    check(m, {l, s, s, psi(l, s, s), nominal(l, l * s * s), 0.0}, "uniaxial " + std::to_string(l));
    const double l3 = bisect([&](double t) { return mu * (t * t - 1.0) + lambda * std::log(l * l * t); }, 0.01, 1.0);
    const double P = nominal(l, l * l * l3);
    check(m, {l, l, l3, psi(l, l, l3), P, P}, "equibiaxial " + std::to_string(l));
  }
}

}  // namespace
}  // namespace fibrane::shell
