// Shell kernel against analytical solutions: membrane stretch of a flat plate, bending of a flat strip
// into a cylinder, and section forces as derivatives of the energy density.
#include <gtest/gtest.h>

#include <cmath>

#include "shell/bezier_patch.hpp"

namespace fibrane::shell {
namespace {

using testing::bezier_basis;

// Control points of the affine map (u, v) -> origin + a u + b v on a degree (p, q) Bezier patch: Bernstein
// polynomials reproduce linear functions when the control points sit at the Greville abscissae i/p.
Eigen::Matrix3Xd affine_patch(int p, int q, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  Eigen::Matrix3Xd X(3, (p + 1) * (q + 1));
  for (int j = 0; j <= q; ++j)
    for (int i = 0; i <= p; ++i) X.col(i + (p + 1) * j) = a * (double(i) / p) + b * (double(j) / q);
  return X;
}

TEST(BezierTestHelper, BasisIsPartitionOfUnityWithConsistentDerivatives) {
  std::mt19937 rng(3);
  const auto w = testing::random_weights(12, rng);
  const double u = 0.37, v = 0.61, step = 1e-5;
  const BasisDerivs R = bezier_basis(3, 2, u, v, w);
  const BasisDerivs Ru = (bezier_basis(3, 2, u + step, v, w) - bezier_basis(3, 2, u - step, v, w)) / (2 * step);
  const BasisDerivs Rv = (bezier_basis(3, 2, u, v + step, w) - bezier_basis(3, 2, u, v - step, w)) / (2 * step);
  EXPECT_NEAR(R.row(0).sum(), 1.0, 1e-14);
  // Central differences of O(1) smooth functions with step 1e-5: error ~1e-9, tolerance 1e-7.
  EXPECT_LT((Ru.row(0) - R.row(1)).cwiseAbs().maxCoeff(), 1e-7);
  EXPECT_LT((Rv.row(0) - R.row(2)).cwiseAbs().maxCoeff(), 1e-7);
  EXPECT_LT((Ru.row(1) - R.row(3)).cwiseAbs().maxCoeff(), 1e-7);
  EXPECT_LT((Ru.row(2) - R.row(4)).cwiseAbs().maxCoeff(), 1e-7);
  EXPECT_LT((Rv.row(1) - R.row(4)).cwiseAbs().maxCoeff(), 1e-7);
  EXPECT_LT((Rv.row(2) - R.row(5)).cwiseAbs().maxCoeff(), 1e-7);
}

// Flat plate with a skewed parametrization (G_12 != 0), stretched by lambda1 along x and contracted along
// y so that the Green strain is uniaxial-stress: E_yy = -nu E_xx, hence S_xx = E E_xx, S_yy = S_xy = 0.
// The contravariant section forces must be N^ab = h G^a . S . G^b.
TEST(ShellAnalytic, UniaxialMembraneStretchOfFlatPlate) {
  const double young = 2.0e5, poisson = 0.3;
  const ShellSection s = ShellSection::svk(young, poisson, 0.01);
  const Eigen::Vector3d a(2.0, 0.0, 0.0), b(0.5, 1.5, 0.0);
  const Eigen::Matrix3Xd X = affine_patch(2, 2, a, b);
  const double lambda1 = 1.1, exx = 0.5 * (lambda1 * lambda1 - 1.0);
  const double lambda2 = std::sqrt(1.0 - 2.0 * poisson * exx);  // (lambda2^2 - 1)/2 = -nu exx
  const Eigen::Matrix3d F = Eigen::Vector3d(lambda1, lambda2, 1.0).asDiagonal();
  const Eigen::Matrix3Xd x = F * X;
  const BasisDerivs R = bezier_basis(2, 2, 0.3, 0.7);
  const SectionForces f = section_forces(s, R, X, x);

  Eigen::Matrix<double, 3, 2> G, Gdual;
  G << a, b;
  Gdual = G * (G.transpose() * G).inverse();
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
  S(0, 0) = young * exx;
  const Eigen::Matrix2d expected = s.thickness * Gdual.transpose() * S * Gdual;
  // Only round-off separates the two evaluations; 1e-12 relative to the largest component.
  const double tol = 1e-12 * expected.cwiseAbs().maxCoeff();
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) EXPECT_NEAR(f.N(i, j), expected(i, j), tol) << i << j;
  EXPECT_LT(f.M.cwiseAbs().maxCoeff(), tol);
  // Force per current length: N_xx = h S_xx lambda1 / lambda2 (Cauchy = F S F^T / det F), e1 = x axis.
  EXPECT_NEAR(f.N_local(0, 0), s.thickness * young * exx * lambda1 / lambda2, tol);
  EXPECT_NEAR(f.N_local(1, 1), 0.0, tol);
  EXPECT_NEAR(f.N_local(0, 1), 0.0, tol);
  // Poisson coupling: a pure x stretch (lambda2 = 1) gives S_yy = nu S_xx.
  const Eigen::Matrix3Xd x_plane_strain = Eigen::Vector3d(lambda1, 1.0, 1.0).asDiagonal() * X;
  const SectionForces g = section_forces(s, R, X, x_plane_strain);
  // S_yy = nu S_xx; the push-forward scales xx by lambda1 and yy by 1 / lambda1.
  EXPECT_NEAR(g.N_local(1, 1) * lambda1 * lambda1, poisson * g.N_local(0, 0), 1e-12 * g.N_local(0, 0));
}

// A flat strip (reference) bent into a circular cylinder of radius rho (current) represented exactly by a
// rational quadratic arc in u and a straight generator in v. At the evaluation point the reference is
// scaled so that the metric is unchanged (E = 0), leaving pure bending with curvature 1/rho along the arc:
// the physical bending moment must be m_11 = D / rho, m_22 = nu D / rho, m_12 = 0 with
// D = E h^3 / (12 (1 - nu^2)).
TEST(ShellAnalytic, PureBendingOfFlatStripIntoCylinder) {
  const double young = 2.0e5, poisson = 0.3;
  const ShellSection s = ShellSection::svk(young, poisson, 0.05);
  const double rho = 1.7, half_angle = 0.6, width = 0.8, u0 = 0.3, v0 = 0.55;
  // Arc in the x-z plane around the origin; the cylinder axis is y.
  const Eigen::Vector3d arc[3] = {rho * Eigen::Vector3d(std::sin(-half_angle), 0.0, std::cos(-half_angle)),
                                  rho / std::cos(half_angle) * Eigen::Vector3d(0.0, 0.0, 1.0),
                                  rho * Eigen::Vector3d(std::sin(half_angle), 0.0, std::cos(half_angle))};
  const double arc_weight[3] = {1.0, std::cos(half_angle), 1.0};
  std::vector<double> w(9);
  Eigen::Matrix3Xd x(3, 9), X(3, 9);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      w[i + 3 * j] = arc_weight[i];
      x.col(i + 3 * j) = arc[i] + Eigen::Vector3d(0.0, width * j / 2.0, 0.0);
      X.col(i + 3 * j) = Eigen::Vector3d(i / 2.0, width * j / 2.0, 0.0);
    }
  const BasisDerivs R = bezier_basis(2, 2, u0, v0, w);
  const Eigen::Vector3d g1 = x * R.row(1).transpose(), G1 = X * R.row(1).transpose();
  X.row(0) *= g1.norm() / G1.norm();  // same arc-length rate at u0: E_11 = 0 there
  const Eigen::Vector3d point = x * R.row(0).transpose();
  const Eigen::Vector3d radial(point.x(), 0.0, point.z());
  ASSERT_NEAR(radial.norm(), rho, 1e-12) << "the rational arc must lie on the cylinder";

  const SectionForces f = section_forces(s, R, X, x);
  const double D = young * std::pow(s.thickness, 3) / (12.0 * (1.0 - poisson * poisson));
  // The sign of the curvature follows the normal orientation: b_11 > 0 when n points to the axis.
  const Eigen::Vector3d normal = g1.cross(x * R.row(2).transpose()).normalized();
  const double inward = -normal.dot(radial.normalized());
  ASSERT_NEAR(std::abs(inward), 1.0, 1e-12);
  const double m = D / rho * inward;
  // Exact geometry: only round-off remains; 1e-10 relative covers the rational-basis evaluation.
  const double tol = 1e-10 * std::abs(m);
  EXPECT_LT(f.E.cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_NEAR(f.M_local(0, 0), m, tol);
  EXPECT_NEAR(f.M_local(1, 1), poisson * m, tol);
  EXPECT_NEAR(f.M_local(0, 1), 0.0, tol);
  EXPECT_NEAR(f.M(0, 0) * g1.squaredNorm(), m, tol);  // contravariant M^11 times |G_1|^2 = |g_1|^2
  EXPECT_LT(f.N.cwiseAbs().maxCoeff(), 1e-9 * young * s.thickness);
  // Energy per unit reference area: psi = (1/2)(m_11 kappa_11 + m_22 kappa_22) = D / (2 rho^2), kappa_22 = 0.
  double energy = 0.0;
  add_shell_point(s, R, X, x, 1.0, &energy, nullptr);
  const double area_jacobian = (X * R.row(1).transpose()).cross(X * R.row(2).transpose()).norm();
  EXPECT_NEAR(energy / area_jacobian, 0.5 * D / (rho * rho), 1e-10 * D / (rho * rho));
}

// N^ab and M^ab are the derivatives of the energy density psi with respect to E_ab and K_ab: along any
// path x(t), d psi/dt = N^ab dE_ab/dt + M^ab dK_ab/dt (sum over all four ab), and psi = (N:E + M:K)/2.
TEST(ShellAnalytic, SectionForcesAreEnergyDerivatives) {
  std::mt19937 rng(21);
  const ShellSection s = ShellSection::svk(1000.0, 0.25, 0.6);
  const auto w = testing::random_weights(16, rng);
  const BasisDerivs R = bezier_basis(3, 3, 0.62, 0.28, w);
  const Eigen::Matrix3Xd X = testing::random_curved_patch(3, 3, rng);
  const Eigen::Matrix3Xd x = testing::random_deformation(X, 0.08, rng);
  const double area_jacobian = (X * R.row(1).transpose()).cross(X * R.row(2).transpose()).norm();
  auto density = [&](const Eigen::Matrix3Xd& y) {
    double e = 0.0;
    add_shell_point(s, R, X, y, 1.0, &e, nullptr);
    return e / area_jacobian;
  };
  const SectionForces f = section_forces(s, R, X, x);
  EXPECT_NEAR(density(x), 0.5 * ((f.N.array() * f.E.array()).sum() + (f.M.array() * f.K.array()).sum()),
              1e-12 * density(x));

  std::normal_distribution<double> g(0.0, 1.0);
  const double step = 1e-5;  // central differences: ~1e-10 relative error, see the derivative tests
  for (int trial = 0; trial < 3; ++trial) {
    Eigen::Matrix3Xd dir(3, 16);
    for (Eigen::Index k = 0; k < dir.size(); ++k) dir.data()[k] = g(rng);
    const SectionForces plus = section_forces(s, R, X, x + step * dir);
    const SectionForces minus = section_forces(s, R, X, x - step * dir);
    const Eigen::Matrix2d dE = (plus.E - minus.E) / (2 * step), dK = (plus.K - minus.K) / (2 * step);
    const double dpsi = (density(x + step * dir) - density(x - step * dir)) / (2 * step);
    const double membrane = (f.N.array() * dE.array()).sum(), bending = (f.M.array() * dK.array()).sum();
    EXPECT_NEAR(dpsi, membrane + bending, 1e-7 * (std::abs(membrane) + std::abs(bending)));
    EXPECT_GT(std::abs(bending), 1e-3 * std::abs(membrane)) << "the bending part must be visible";
  }
}

}  // namespace
}  // namespace fibrane::shell
