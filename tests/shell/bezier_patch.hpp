#pragma once
// Test geometry for the shell kernel, independent of src/spline: rational tensor-product Bezier
// (Bernstein) patches, their basis derivatives up to second order, and random shell states.
#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <vector>

#include "shell/kl_shell.hpp"

namespace fibrane::shell::testing {

// Bernstein polynomial B_{i,p}(t) and its first two derivatives; zero outside 0 <= i <= p.
inline double bernstein(int p, int i, double t) {
  if (p < 0 || i < 0 || i > p) return 0.0;
  double binom = 1.0;
  for (int k = 1; k <= i; ++k) binom = binom * (p - i + k) / k;
  return binom * std::pow(t, i) * std::pow(1.0 - t, p - i);
}
inline double bernstein_d1(int p, int i, double t) {
  return p * (bernstein(p - 1, i - 1, t) - bernstein(p - 1, i, t));
}
inline double bernstein_d2(int p, int i, double t) {
  return p * (p - 1) * (bernstein(p - 2, i - 2, t) - 2.0 * bernstein(p - 2, i - 1, t) + bernstein(p - 2, i, t));
}

// Rows R, R_1, R_2, R_11, R_12, R_22 of the rational basis w_A N_A / sum_B w_B N_B of a degree (p, q)
// Bezier patch at (u, v). Column A = i + (p + 1) j. Empty `weights` means a polynomial patch.
inline BasisDerivs bezier_basis(int p, int q, double u, double v, const std::vector<double>& weights = {}) {
  const int nen = (p + 1) * (q + 1);
  BasisDerivs Nw(6, nen);  // weighted polynomial basis w_A N_A and its derivatives
  for (int j = 0; j <= q; ++j)
    for (int i = 0; i <= p; ++i) {
      const int A = i + (p + 1) * j;
      const double w = weights.empty() ? 1.0 : weights[A];
      const double bu = bernstein(p, i, u), du = bernstein_d1(p, i, u), ddu = bernstein_d2(p, i, u);
      const double bv = bernstein(q, j, v), dv = bernstein_d1(q, j, v), ddv = bernstein_d2(q, j, v);
      Nw.col(A) << bu * bv, du * bv, bu * dv, ddu * bv, du * dv, bu * ddv;
      Nw.col(A) *= w;
    }
  // Quotient rule for R = Nw / W, W = sum Nw, up to second derivatives.
  const Eigen::Matrix<double, 6, 1> W = Nw.rowwise().sum();
  BasisDerivs R(6, nen);
  R.row(0) = Nw.row(0) / W[0];
  R.row(1) = (Nw.row(1) - R.row(0) * W[1]) / W[0];
  R.row(2) = (Nw.row(2) - R.row(0) * W[2]) / W[0];
  R.row(3) = (Nw.row(3) - 2.0 * R.row(1) * W[1] - R.row(0) * W[3]) / W[0];
  R.row(4) = (Nw.row(4) - R.row(1) * W[2] - R.row(2) * W[1] - R.row(0) * W[4]) / W[0];
  R.row(5) = (Nw.row(5) - 2.0 * R.row(2) * W[2] - R.row(0) * W[5]) / W[0];
  return R;
}

// A doubly curved reference patch over [0, 2] x [0, 1.5] (control net of a saddle-dome mix) with
// random jitter, so that G_ab is not diagonal and B_ab is not zero.
inline Eigen::Matrix3Xd random_curved_patch(int p, int q, std::mt19937& rng) {
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  Eigen::Matrix3Xd X(3, (p + 1) * (q + 1));
  for (int j = 0; j <= q; ++j)
    for (int i = 0; i <= p; ++i) {
      const double s = double(i) / p, t = double(j) / q;
      X.col(i + (p + 1) * j) << 2.0 * s + 0.3 * t + jitter(rng), 1.5 * t + jitter(rng),
          0.4 * s * s - 0.3 * t * t + 0.2 * s * t + jitter(rng);
    }
  return X;
}

inline std::vector<double> random_weights(int nen, std::mt19937& rng) {
  std::uniform_real_distribution<double> w(0.7, 1.3);
  std::vector<double> out(nen);
  for (double& v : out) v = w(rng);
  return out;
}

// Current state: reference plus a smooth stretch/bend plus random displacements of size `amplitude`.
inline Eigen::Matrix3Xd random_deformation(const Eigen::Matrix3Xd& X, double amplitude, std::mt19937& rng) {
  std::uniform_real_distribution<double> d(-amplitude, amplitude);
  Eigen::Matrix3Xd x = X;
  for (Eigen::Index A = 0; A < X.cols(); ++A) {
    x(0, A) *= 1.05;
    x(2, A) += 0.1 * X(0, A) * X(0, A);
    for (int c = 0; c < 3; ++c) x(c, A) += d(rng);
  }
  return x;
}

inline Eigen::Matrix3d random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  const Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
  return q.normalized().toRotationMatrix();
}

// Energy, residual and tangent of one quadrature point, with freshly zeroed containers.
struct PointResult {
  double energy = 0.0;
  Eigen::VectorXd residual;
  Eigen::MatrixXd tangent;
};
inline PointResult evaluate(const ShellSection& s, const BasisDerivs& R, const Eigen::Matrix3Xd& X,
                            const Eigen::Matrix3Xd& x, double weight = 1.0) {
  PointResult r;
  const Eigen::Index n = 3 * R.cols();
  r.residual.setZero(n);
  r.tangent.setZero(n, n);
  add_shell_point(s, R, X, x, weight, &r.energy, &r.residual, &r.tangent);
  return r;
}

// x with DOF `dof` (= 3 * node + component) shifted by `step`.
inline Eigen::Matrix3Xd shifted(const Eigen::Matrix3Xd& x, Eigen::Index dof, double step) {
  Eigen::Matrix3Xd y = x;
  y(dof % 3, dof / 3) += step;
  return y;
}

}  // namespace fibrane::shell::testing
