// Global consistency of the SBS kernel: a straight beam over a flat plate against the disk-plate law,
// Newton settling at the law's equilibrium, the FF residual integrated along a path of configurations
// against the change of energy, and the third surface derivatives used by the exact FF tangent.
#include <gtest/gtest.h>

#include <cmath>

#include "laws/lennard_jones.hpp"
#include "pair_fixture.hpp"
#include "spline/quadrature.hpp"
#include "spline/shapes.hpp"
#include "spline/surface_third.hpp"
#include "test_geometry.hpp"

namespace fibrane::interaction {
namespace {

laws::LennardJonesDiskPlate law() {
  laws::LennardJonesDiskPlate l{};
  l.epsilon = 2.0;
  l.sigma = 0.05;
  l.disk_radius = 0.5;
  l.plate_thickness = 0.5;
  return l;
}

// Straight beam from (-1, 0.3, z) to (1, 0.3, z) over the plate z = 0 (x, y in [-3,3] x [-2,2], quadratic
// 4 x 4 elements), two quartic Bezier elements with 5 Gauss points each, summed over all points.
struct PlateSum {
  double energy = 0, d_beam_z = 0, dd_beam_z = 0;  // energy, its z-derivative (rigid lift) and tangent
};

PlateSum plate_sum(const laws::LennardJonesDiskPlate& l, Formulation f, double z) {
  spline::NurbsSurface plate = spline::make_rectangle({-3, -2, 0}, {6, 0, 0}, {0, 4, 0});
  plate.refine(0, 2, 1, 4);
  plate.refine(1, 2, 1, 4);
  ShellProximity prox(plate);
  const spline::QuadratureRule gauss = spline::gauss_legendre(5);
  PlateSum sum;
  for (int e = 0; e < 2; ++e) {
    Eigen::Matrix3Xd beam(3, 5);
    for (int i = 0; i < 5; ++i) beam.col(i) = Eigen::Vector3d(-1.0 + e + i / 4.0, 0.3, z);
    for (std::size_t g = 0; g < gauss.points.size(); ++g) {
      const double xi = 0.5 * (1 + gauss.points[g]);
      PairPoint pp;
      pp.beam_basis = test::bernstein4(xi);
      pp.beam_x = beam;
      const auto proj = prox.project(beam * pp.beam_basis.row(0).transpose());
      const auto& el = prox.elements()[proj.element];
      const spline::SurfaceBasis sb = plate.basis_in(el.span_u, el.span_v, proj.u, proj.v);
      pp.shell_basis = sb.R;
      pp.shell_x.resize(3, sb.indices.size());
      for (std::size_t a = 0; a < sb.indices.size(); ++a) pp.shell_x.col(a) = plate.control_points()[sb.indices[a]];
      pp.weight = gauss.weights[g] * 0.5 * 1.0;  // parent Jacobian 1/2, reference J_B = element length 1
      Eigen::VectorXd r;
      Eigen::MatrixXd k;
      add_sbs_point(l, f, FfTangent::rf1, pp, &sum.energy, &r, &k);
      for (int i = 0; i < 5; ++i) {
        sum.d_beam_z += r[4 * i + 2];
        for (int j = 0; j < 5; ++j) sum.dd_beam_z += k(4 * i + 2, 4 * j + 2);
      }
    }
  }
  return sum;
}

TEST(SbsConsistency, StraightBeamOverFlatPlateIsLengthTimesTheLaw) {
  const laws::LennardJonesDiskPlate l = law();
  for (Formulation f : {Formulation::RF2, Formulation::RF1, Formulation::FF}) {
    for (double z : {0.76, 0.8, 1.2}) {
      const PlateSum s = plate_sum(l, f, z);
      const laws::LawValue phi = l.evaluate(z, 1.0);
      // Constant integrand: the Gauss sum is exact; only round-off of 10 terms remains (~1e-15).
      EXPECT_NEAR(s.energy, 2.0 * phi.value, 1e-12 * std::abs(2.0 * phi.value));
      EXPECT_NEAR(s.d_beam_z, 2.0 * phi.d_d, 1e-12 * std::abs(2.0 * phi.d_d));
      EXPECT_NEAR(s.dd_beam_z, 2.0 * phi.d_dd, 1e-10 * std::abs(2.0 * phi.d_dd));
    }
  }
}

TEST(SbsConsistency, RigidBeamSettlesAtTheEquilibriumDistanceQuadratically) {
  const laws::LennardJonesDiskPlate l = law();
  const double target = l.equilibrium_distance(1.0);
  // Start 2% of sigma above the equilibrium gap, inside Newton's basin (the law's inflection point
  // lies ~0.1 sigma beyond the equilibrium).
  double z = target + 0.02 * l.sigma, previous_error = std::abs(z - target) / target, first_ratio = 0;
  int iterations = 0;
  // Quadratic convergence: e_{k+1} / e_k^2 tends to the constant |phi_ddd / 2 phi_dd| z (measured ~146);
  // the ratio must stay within a factor 2 of its first value while e is above round-off.
  for (; iterations < 30 && std::abs(z - target) > 1e-13 * target; ++iterations) {
    const PlateSum s = plate_sum(l, Formulation::RF2, z);
    z -= s.d_beam_z / s.dd_beam_z;
    const double error = std::abs(z - target) / target;
    if (error > 1e-12) {
      const double ratio = error / (previous_error * previous_error);
      if (first_ratio == 0) first_ratio = ratio;
      EXPECT_NEAR(ratio, first_ratio, 0.5 * first_ratio) << "iteration " << iterations;
    }
    previous_error = error;
  }
  EXPECT_LE(std::abs(z - target), 1e-8 * target);
  EXPECT_LT(iterations, 12);
}

// Along q(tau) = q0 + sin(pi tau / 2) A + tau^2 B, tau in [0,1], the trapezoidal sum of the FF residual
// dotted with the increments must reproduce E(1) - E(0). The trapezoid error is ~ dtau^2 / 12 |g'(1) -
// g'(0)| with g = r . q'; measured with 400 steps it is 1.1e-8 relative, with 1000 steps ~1.7e-9, and the Richardson
// estimate (I_1000 - I_500) / 3 agrees with the actual error: what remains is quadrature error, not a
// residual that differs from the energy gradient.
TEST(SbsConsistency, FfResidualIntegratesToTheEnergyChange) {
  laws::LennardJonesDiskPlate l{};
  l.epsilon = 1.0, l.sigma = 0.1, l.disk_radius = 0.3, l.plate_thickness = 0.2;
  const spline::NurbsSurface s = test::random_patch(4, 21);
  test::PairFixture fx(s, s.control_points(), 0.37, 0.62, 0.1 + 1.5 * 0.3, 0.6, 8);
  const Eigen::VectorXd q0 = fx.dofs();
  std::mt19937 gen(4);
  std::uniform_real_distribution<double> r(-0.01, 0.01);
  Eigen::VectorXd A(q0.size()), B(q0.size());
  for (Eigen::Index i = 0; i < q0.size(); ++i) A[i] = (i % 4 == 3 && i < 20) ? 0 : r(gen), B[i] = r(gen);
  auto q = [&](double tau) { return Eigen::VectorXd(q0 + std::sin(M_PI * tau / 2) * A + tau * tau * B); };
  auto integral = [&](int steps) {
    double sum = 0;
    Eigen::VectorXd prev = fx.evaluate(l, Formulation::FF, FfTangent::rf1, q(0)).residual;
    for (int k = 1; k <= steps; ++k) {
      const Eigen::VectorXd next = fx.evaluate(l, Formulation::FF, FfTangent::rf1, q(double(k) / steps)).residual;
      sum += 0.5 * (prev + next).dot(q(double(k) / steps) - q(double(k - 1) / steps));
      prev = next;
    }
    return sum;
  };
  const double change = fx.evaluate(l, Formulation::FF, FfTangent::rf1, q(1)).energy -
                        fx.evaluate(l, Formulation::FF, FfTangent::rf1, q(0)).energy;
  const double i1000 = integral(1000), i500 = integral(500);
  const double error = std::abs(i1000 - change) / std::abs(change);
  std::printf("    relative error %.2e, Richardson estimate %.2e, energy change %.4e\n", error,
              std::abs(i1000 - i500) / 3 / std::abs(change), change);
  EXPECT_LE(error, 1e-8);
  EXPECT_NEAR(error, std::abs(i1000 - i500) / 3 / std::abs(change), 0.2 * error);  // pure O(dtau^2)
  EXPECT_GT(std::abs(change), 1e-3 * std::abs(fx.evaluate(l, Formulation::FF, FfTangent::rf1, q(0)).energy));
}

// Third derivatives of the rational basis against central differences of the second ones (rational
// sphere patch, refined): step 1e-5, truncation ~1e-10 relative, round-off ~1e-11.
TEST(SurfaceThird, MatchesDifferencesOfSecondDerivatives) {
  const spline::NurbsSurface s = test::sphere();
  const double h = 1e-5;
  for (auto [u, v] : {std::pair{0.31, 0.47}, {0.05, 0.93}, {0.77, 0.12}}) {
    const int su = s.knots(0).find_span(u), sv = s.knots(1).find_span(v);
    const spline::SurfaceBasis3 b3 = spline::basis3_in(s, su, sv, u, v);
    const Eigen::MatrixXd du = (s.basis_in(su, sv, u + h, v).R - s.basis_in(su, sv, u - h, v).R) / (2 * h);
    const Eigen::MatrixXd dv = (s.basis_in(su, sv, u, v + h).R - s.basis_in(su, sv, u, v - h).R) / (2 * h);
    const double scale = b3.R.cwiseAbs().maxCoeff();
    EXPECT_LE((b3.R.row(0) - du.row(3)).cwiseAbs().maxCoeff(), 1e-7 * scale);  // R_uuu
    EXPECT_LE((b3.R.row(1) - du.row(4)).cwiseAbs().maxCoeff(), 1e-7 * scale);  // R_uuv
    EXPECT_LE((b3.R.row(1) - dv.row(3)).cwiseAbs().maxCoeff(), 1e-7 * scale);
    EXPECT_LE((b3.R.row(2) - du.row(5)).cwiseAbs().maxCoeff(), 1e-7 * scale);  // R_uvv
    EXPECT_LE((b3.R.row(3) - dv.row(5)).cwiseAbs().maxCoeff(), 1e-7 * scale);  // R_vvv
    EXPECT_EQ(b3.indices, s.basis_in(su, sv, u, v).indices);
    EXPECT_NEAR(b3.R.sum(), 0.0, 1e-9 * scale);  // partition of unity: derivatives sum to zero
  }
}

}  // namespace
}  // namespace fibrane::interaction
