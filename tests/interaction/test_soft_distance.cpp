// Soft-minimum distance (interaction/soft_distance): exact on a flat plate (with and without a mirror
// plane), the curvature bias of its Laplace asymptotics on a cylinder, and its gradient / Hessian and the
// RF2 residual / tangent built on it against central differences on a deformed doubly curved patch.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

#include "laws/lennard_jones.hpp"
#include "interaction/soft_distance.hpp"
#include "pair_fixture.hpp"
#include "spline/shapes.hpp"
#include "test_geometry.hpp"

namespace fibrane::interaction {
namespace {

// One beam point from a quartic Bezier element at xi = 0.4, translated so that it sits at `point`.
struct BeamPoint {
  Eigen::RowVectorXd basis;
  Eigen::Matrix3Xd x;
};
BeamPoint beam_at(const Eigen::Vector3d& point, unsigned seed) {
  BeamPoint b;
  b.basis = test::bernstein4(0.4).row(0);
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> bend(-0.05, 0.05);
  b.x.resize(3, 5);
  for (int i = 0; i < 5; ++i)
    b.x.col(i) = Eigen::Vector3d(0.3 * (i - 1.6), 0.1 * i, 0) + Eigen::Vector3d(bend(gen), bend(gen), bend(gen));
  const Eigen::Vector3d at = b.x * b.basis.transpose();
  b.x.colwise() += point - at;
  return b;
}

Eigen::Matrix3Xd window_points(const spline::NurbsSurface& s, const SoftWindow& w) {
  Eigen::Matrix3Xd x(3, w.control_points.size());
  for (std::size_t a = 0; a < w.control_points.size(); ++a) x.col(a) = s.control_points()[w.control_points[a]];
  return x;
}

spline::NurbsSurface plate(Eigen::Vector3d origin, Eigen::Vector3d edge_u, Eigen::Vector3d edge_v, int n) {
  spline::NurbsSurface s = spline::make_rectangle(origin, edge_u, edge_v);
  s.refine(0, 4, 1, n);
  s.refine(1, 4, 1, n);
  return s;
}

constexpr double kWidth = 5e-4;  // the bending example's choice

// The window is its box's cells, whatever the element size: on a plate of 2 x 2 elements (3 wide, against a
// box of half-width 0.3 around an off-centre point) its samples' weights sum to the area of the cells that
// meet the box, between the box's (0.6)^2 and (0.6 + 2 cells)^2; whole elements would give 9 or more.
TEST(SoftDistance, WindowIsTheCellsThatMeetItsBox) {
  const spline::NurbsSurface s = plate({0, 0, 0}, {6, 0, 0}, {0, 6, 0}, 2);
  const double half_width = 0.3, cell = 0.05;
  const SoftWindow w = make_soft_window(s, {3.2 / 6, 2.2 / 6}, half_width, cell, {});
  double area = 0;
  for (double weight : w.weight) area += weight;
  EXPECT_GE(area, std::pow(2 * half_width, 2) - 1e-12);
  EXPECT_LE(area, std::pow(2 * half_width + 2 * cell, 2) + 1e-12);
  EXPECT_EQ(w.element_begin.size(), 3u);  // the box crosses the elements' boundary x = 3 only
}

// A flat plate is the law's own geometry: D = d, for the example's width and the largest allowed. The
// window (soft_window_half_width: 0.41 d at 5e-4, 0.87 d at 5e-3) truncates the integrand at
// exp(-(sqrt(1 + h^2) - 1) / width) = exp(-163) and exp(-63), and the 3 x 3 Gauss rule on cells of half
// the integrand's width (soft_window_cell) is accurate to ~1e-12 relative in I, i.e. 1e-12 / beta ~ 1e-15
// in D. Tolerance 1e-11 d.
TEST(SoftDistance, EqualsTheDistanceOfAFlatPlate) {
  const double d = 0.7;
  const spline::NurbsSurface s = plate({-3, -3, 0}, {6, 0, 0}, {0, 6, 0}, 12);
  const BeamPoint b = beam_at({0.31, -0.42, d}, 1);
  for (const double width : {kWidth, 5e-3}) {
    const double beta = 1.0 / (width * d);
    const SoftWindow w = make_soft_window(s, {(0.31 + 3) / 6, (-0.42 + 3) / 6}, soft_window_half_width(width, d),
                                          soft_window_cell(width, d), {});
    const SoftDistance D = soft_distance(beta, b.basis, b.x, w, window_points(s, w), false);
    EXPECT_NEAR(D.distance, d, 1e-11 * d) << width;
    EXPECT_NEAR(D.nearest, d, 1e-3 * d) << width;  // a sample lies within a cell of the foot point
    EXPECT_LT((D.direction - Eigen::Vector3d::UnitZ()).norm(), 1e-10) << width;
  }
}

// The half plate x >= 0 with its mirror image across x = 0 is the whole plate: D = d for a point in the
// mirror plane; without the image only half of the neighbourhood is there, and D = d + ln 2 / beta to
// first order (1 % tolerance on that offset: its next term is O(width)).
TEST(SoftDistance, CountsTheMirrorImageOfASymmetryPlane) {
  const double d = 0.7;
  const spline::NurbsSurface s = plate({0, -3, 0}, {3, 0, 0}, {0, 6, 0}, 8);
  const BeamPoint b = beam_at({0.0, 0.2, d}, 2);
  const double beta = 1.0 / (kWidth * d);
  const Eigen::Vector2d centre(0.0, (0.2 + 3) / 6);
  const double half_width = soft_window_half_width(kWidth, d), cell = soft_window_cell(kWidth, d);
  const SoftWindow mirrored = make_soft_window(s, centre, half_width, cell, {MirrorPlane{0, 0.0}});
  ASSERT_EQ(mirrored.images.size(), 2u);
  EXPECT_NEAR(soft_distance(beta, b.basis, b.x, mirrored, window_points(s, mirrored), false).distance, d, 1e-11 * d);
  const SoftWindow half = make_soft_window(s, centre, half_width, cell, {});
  const double offset = soft_distance(beta, b.basis, b.x, half, window_points(s, half), false).distance - d;
  EXPECT_NEAR(offset, std::log(2.0) / beta, 0.01 * std::log(2.0) / beta);
}

// Inside a cylinder of radius 2 at distance d from the wall the shell curves toward the point,
// lambda = 1 - d / 2 across and 1 along: D - d = (width d / 2) ln(lambda) (1 + O(width)). Tolerance 2 %
// of the offset at width 1e-3 (the O(width) terms are a few times width relative).
TEST(SoftDistance, IsBelowTheDistanceWhereTheShellCurvesTowardThePoint) {
  const spline::NurbsSurface s = test::cylinder();  // axis x, R = 2, th in [0.3, 1.5], x in [0, 4]
  const double R = 2.0, d = 0.5, theta = 0.9, width = 1e-3;
  const BeamPoint b = beam_at({2.0, (R - d) * std::cos(theta), (R - d) * std::sin(theta)}, 3);
  const auto foot = ShellProximity(s).project(b.x * b.basis.transpose());
  ASSERT_EQ(foot.where, ShellProximity::Projection::Where::interior);
  ASSERT_NEAR(foot.distance, d, 1e-12);
  EXPECT_NEAR(foot.relative_curvature, 1 - d / R, 1e-10);  // Projection::relative_curvature, the switch criterion
  const double beta = 1.0 / (width * d);
  const SoftWindow w = make_soft_window(s, {foot.u, foot.v}, 0.5 * d, 0.5 * d * std::sqrt(width), {});
  const SoftDistance D = soft_distance(beta, b.basis, b.x, w, window_points(s, w), false);
  const double expected = 0.5 * width * d * std::log(1 - d / R);
  EXPECT_NEAR(D.distance - d, expected, 0.02 * std::abs(expected));
}

// Central differences of D (and of the RF2 energy / residual built on it) on a deformed random bicubic
// patch, with the point 0.5 above it, width 0.05 (so that the Gibbs weights spread over many samples
// and the covariance terms of the Hessian matter). Step 1e-6: truncation ~ h^2 beta^2 ~ 1e-12 / (width
// d)^2 ~ 2e-9 relative, round-off ~ 1e-16 / 1e-6 * beta ~ 1e-9; tolerance 1e-6.
TEST(SoftDistance, GradientAndHessianMatchCentralDifferences) {
  const spline::NurbsSurface s = test::random_patch(4, 7);
  std::mt19937 gen(11);
  std::uniform_real_distribution<double> move(-0.05, 0.05);
  std::vector<Eigen::Vector3d> cur = s.control_points();
  for (auto& p : cur) p += Eigen::Vector3d(move(gen), move(gen), move(gen));
  const spline::NurbsSurface deformed(s.knots(0), s.knots(1), cur, s.weights());
  const Eigen::Vector3d foot = deformed.point(0.45, 0.55);
  const BeamPoint b = beam_at(foot + 0.5 * test::unit_normal(deformed, 0.45, 0.55), 5);
  const double width = 0.05, beta = 1.0 / (width * 0.5);
  const SoftWindow w = make_soft_window(s, {0.45, 0.55}, 0.6, 0.1, {MirrorPlane{0, -0.3}});
  const int nb = 5, nw = static_cast<int>(w.control_points.size()), n = 4 * nb + 3 * nw;
  Eigen::VectorXd q(n);
  for (int i = 0; i < nb; ++i) q.segment<4>(4 * i) << b.x.col(i), 0.0;
  for (int a = 0; a < nw; ++a) q.segment<3>(4 * nb + 3 * a) = cur[w.control_points[a]];
  auto split = [&](const Eigen::VectorXd& z, Eigen::Matrix3Xd& bx, Eigen::Matrix3Xd& wx) {
    bx.resize(3, nb);
    wx.resize(3, nw);
    for (int i = 0; i < nb; ++i) bx.col(i) = z.segment<3>(4 * i);
    for (int a = 0; a < nw; ++a) wx.col(a) = z.segment<3>(4 * nb + 3 * a);
  };
  auto distance = [&](const Eigen::VectorXd& z, bool hessian) {
    Eigen::Matrix3Xd bx, wx;
    split(z, bx, wx);
    return soft_distance(beta, b.basis, bx, w, wx, hessian);
  };
  const SoftDistance D = distance(q, true);
  ASSERT_GT(D.distance, 0.3);
  Eigen::VectorXd fd_grad(n);
  Eigen::MatrixXd fd_hess(n, n);
  const double h = 1e-6;
  for (int j = 0; j < n; ++j) {
    Eigen::VectorXd qp = q, qm = q;
    qp[j] += h;
    qm[j] -= h;
    const SoftDistance Dp = distance(qp, false), Dm = distance(qm, false);
    fd_grad[j] = (Dp.distance - Dm.distance) / (2 * h);
    fd_hess.col(j) = (Dp.gradient - Dm.gradient) / (2 * h);
  }
  EXPECT_LT((D.gradient - fd_grad).cwiseAbs().maxCoeff() / fd_grad.cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_LT((D.hessian - fd_hess).cwiseAbs().maxCoeff() / fd_hess.cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_LT((D.hessian - D.hessian.transpose()).cwiseAbs().maxCoeff(), 1e-12 * D.hessian.cwiseAbs().maxCoeff());

  // RF2 on it: residual = gradient of the energy, tangent = Jacobian of the residual.
  laws::LennardJonesDiskPlate law{};
  law.epsilon = 1.0;
  law.sigma = 0.1;
  law.disk_radius = 0.2;
  law.plate_thickness = 0.1;
  auto rf2 = [&](const Eigen::VectorXd& z, double* e, Eigen::VectorXd* r, Eigen::MatrixXd* k) {
    Eigen::Matrix3Xd bx, wx;
    split(z, bx, wx);
    add_soft_rf2_point(law, beta, b.basis, bx, w, wx, 0.01, 0.3, e, r, k);
  };
  double e0 = 0;
  Eigen::VectorXd r0;
  Eigen::MatrixXd k0;
  rf2(q, &e0, &r0, &k0);
  Eigen::VectorXd fd_r(n);
  Eigen::MatrixXd fd_k(n, n);
  for (int j = 0; j < n; ++j) {
    Eigen::VectorXd qp = q, qm = q;
    qp[j] += h;
    qm[j] -= h;
    double ep = 0, em = 0;
    Eigen::VectorXd rp, rm;
    rf2(qp, &ep, &rp, nullptr);
    rf2(qm, &em, &rm, nullptr);
    fd_r[j] = (ep - em) / (2 * h);
    fd_k.col(j) = (rp - rm) / (2 * h);
  }
  EXPECT_LT((r0 - fd_r).cwiseAbs().maxCoeff() / fd_r.cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_LT((k0 - fd_k).cwiseAbs().maxCoeff() / fd_k.cwiseAbs().maxCoeff(), 1e-6);
}

}  // namespace
}  // namespace fibrane::interaction
