// The closed-form tangents of the paper, App. D (RF2, Eq. D7) and App. E (RF1, Eq. E6), with the typos
// corrected as listed in docs/interaction.md, assembled in the generalized unknowns
// [u_B, u_B,1, u_S, u_S,1, u_S,2] and mapped to the DOFs, must equal the kernel's tangents (which are
// themselves verified against finite differences in test_sbs_point.cpp). This pins down the typos.
#include <gtest/gtest.h>

#include "laws/lennard_jones.hpp"
#include "pair_fixture.hpp"
#include "test_geometry.hpp"

namespace fibrane::interaction {
namespace {

using Mat3 = Eigen::Matrix3d;
using Vec = Eigen::Vector3d;

struct Geometry {
  Vec n, t, g[2], gbar[2];
  Eigen::Matrix2d Cinv;
  double d, tn, sqrt_a;
};

Geometry geometry(const PairPoint& p) {
  Geometry G;
  const Vec rb = p.beam_x * p.beam_basis.row(0).transpose(), a1 = p.beam_x * p.beam_basis.row(1).transpose();
  const Eigen::Matrix<double, 3, 6> s = p.shell_x * p.shell_basis.transpose();
  const Vec D = rb - s.col(0);
  G.d = D.norm();
  G.n = D / G.d;
  G.sqrt_a = a1.norm();
  G.t = a1 / G.sqrt_a;
  G.tn = G.t.dot(G.n);
  G.g[0] = s.col(1), G.g[1] = s.col(2);
  Eigen::Matrix2d C;  // shifted metric, Eq. (C3): C_ab = g_ab - d b_ab = g_a.g_b - D.g_ab
  C << G.g[0].dot(G.g[0]) - D.dot(s.col(3)), G.g[0].dot(G.g[1]) - D.dot(s.col(4)),
      G.g[0].dot(G.g[1]) - D.dot(s.col(4)), G.g[1].dot(G.g[1]) - D.dot(s.col(5));
  G.Cinv = C.inverse();
  for (int b = 0; b < 2; ++b) G.gbar[b] = G.Cinv(0, b) * G.g[0] + G.Cinv(1, b) * G.g[1];  // Eq. (C4)
  return G;
}

// Generalized unknowns (blocks of 3): 0 u_B, 1 u_B,1, 2 u_S, 3 u_S,1, 4 u_S,2.
using Gen = Eigen::Matrix<double, 15, 15>;
void put(Gen& K, int row, int col, const Mat3& block) { K.block<3, 3>(3 * row, 3 * col) += block; }

// Eq. (D7) with k33 = -phi_d d C^ab (n x n) (the printed k33 lacks phi_d).
Gen rf2_blocks(const Geometry& G, double phi_d, double phi_dd) {
  const Mat3 I = Mat3::Identity(), nn = G.n * G.n.transpose();
  Mat3 k11 = phi_dd * nn + phi_d / G.d * (I - nn);
  for (int a = 0; a < 2; ++a) k11 -= phi_d / G.d * G.g[a] * G.gbar[a].transpose();
  Gen K = Gen::Zero();
  put(K, 0, 0, k11), put(K, 0, 2, -k11), put(K, 2, 0, -k11), put(K, 2, 2, k11);
  for (int b = 0; b < 2; ++b) {
    const Mat3 k13 = -phi_d * G.gbar[b] * G.n.transpose(), k31 = -phi_d * G.n * G.gbar[b].transpose();
    put(K, 0, 3 + b, k13), put(K, 2, 3 + b, -k13);
    put(K, 3 + b, 0, k31), put(K, 3 + b, 2, -k31);
    for (int a = 0; a < 2; ++a) put(K, 3 + a, 3 + b, -phi_d * G.d * G.Cinv(a, b) * nn);
  }
  return K;
}

// Eq. (E6), w_d = -phi^R_{,d cos a} t_n (E2).
Gen rf1_blocks(const Geometry& G, double reduced_dc) {
  const double wd = -reduced_dc * G.tn;
  const Mat3 nn = G.n * G.n.transpose(), nt = G.n * G.t.transpose();
  Mat3 k11 = wd / G.d * (nt - G.tn * nn);
  for (int a = 0; a < 2; ++a) k11 -= wd / G.d * G.t.dot(G.g[a]) * G.n * G.gbar[a].transpose();
  const Mat3 k12 = wd / G.sqrt_a * (nn - G.tn * nt);
  Gen K = Gen::Zero();
  put(K, 0, 0, k11), put(K, 0, 1, k12), put(K, 0, 2, -k11);
  put(K, 2, 0, -k11), put(K, 2, 1, -k12), put(K, 2, 2, k11);
  for (int b = 0; b < 2; ++b) {
    const Mat3 k14 = -wd * G.t.dot(G.gbar[b]) * nn;
    put(K, 0, 3 + b, k14), put(K, 2, 3 + b, -k14);
  }
  return K;
}

// Generalized unknowns from the pair DOFs (beam twist columns stay zero).
Eigen::MatrixXd generalized_map(const PairPoint& p) {
  const int nb = static_cast<int>(p.beam_basis.cols()), ns = static_cast<int>(p.shell_basis.cols());
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(15, 4 * nb + 3 * ns);
  for (int i = 0; i < nb; ++i)
    for (int k = 0; k < 3; ++k) B(k, 4 * i + k) = p.beam_basis(0, i), B(3 + k, 4 * i + k) = p.beam_basis(1, i);
  for (int a = 0; a < ns; ++a)
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) B(6 + 3 * r + k, 4 * nb + 3 * a + k) = p.shell_basis(r, a);
  return B;
}

TEST(AppendixForms, CorrectedD7AndE6EqualTheKernelTangents) {
  laws::LennardJonesDiskPlate law{};
  law.epsilon = 1.0, law.sigma = 0.1, law.disk_radius = 0.3, law.plate_thickness = 0.2;
  const spline::NurbsSurface s = test::sphere();
  for (double tn : {0.0, 0.5, 0.9}) {
    test::PairFixture fx(s, s.control_points(), 0.47, 0.53, 0.1 + 1.3 * 0.3, tn, 17);
    const auto rf2 = fx.evaluate(law, Formulation::RF2, FfTangent::rf1, fx.dofs(), 1.0);
    const auto rf1 = fx.evaluate(law, Formulation::RF1, FfTangent::rf1, fx.dofs(), 1.0);
    const Geometry G = geometry(rf2.pair);
    const Eigen::MatrixXd B = generalized_map(rf2.pair);
    const laws::LawValue at1 = law.evaluate(G.d, 1.0);
    const laws::LawValue atc = law.evaluate(G.d, std::sqrt(1 - G.tn * G.tn));
    const Eigen::MatrixXd k_rf2 = B.transpose() * rf2_blocks(G, at1.d_d, at1.d_dd) * B;
    const Eigen::MatrixXd k_rf1 =
        B.transpose() * (rf2_blocks(G, atc.d_d, atc.d_dd) + rf1_blocks(G, atc.reduced_dc)) * B;
    // Same quantities in a different order of operations: agreement to round-off (1e-10 relative).
    const double scale2 = rf2.tangent.cwiseAbs().maxCoeff(), scale1 = rf1.tangent.cwiseAbs().maxCoeff();
    EXPECT_LE((k_rf2 - rf2.tangent).cwiseAbs().maxCoeff(), 1e-10 * scale2) << "tn " << tn;
    EXPECT_LE((k_rf1 - rf1.tangent).cwiseAbs().maxCoeff(), 1e-10 * scale1) << "tn " << tn;
    // The printed k33 (without phi_d) is measurably different: the typo matters.
    Gen printed = rf2_blocks(G, at1.d_d, at1.d_dd);
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        printed.block<3, 3>(9 + 3 * a, 9 + 3 * b) *= 1.0 / at1.d_d;
    EXPECT_GT((B.transpose() * printed * B - rf2.tangent).cwiseAbs().maxCoeff(), 1e-6 * scale2);
  }
}

}  // namespace
}  // namespace fibrane::interaction
