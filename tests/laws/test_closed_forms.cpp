// Closed-form laws against direct numerical integration (<= 1e-9 relative on
// d/R in [1.01, 20], cos a in [0, 1], h/R in [0.1, 10]).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "laws/disk_halfspace.hpp"
#include "laws/disk_plate.hpp"
#include "laws/disk_sphere.hpp"
#include "laws/lennard_jones.hpp"
#include "laws/quadrature.hpp"
#include "laws/reference.hpp"

namespace fibrane::laws {
namespace {

// The references are adaptive cubatures to 1e-12 per level; 1e-9 is the acceptance bound and
// leaves two to three digits for the cancellation of the plate difference in the reference itself.
constexpr double kTolerance = 1e-9;
const double kDistances[] = {1.01, 1.1, 1.5, 3.0, 7.0, 20.0};  // d / R
const double kCosines[] = {0.0, 0.3, 0.7, 1.0};

double relative_error(double a, double b) { return std::abs(a - b) / std::abs(b); }

TEST(DiskHalfSpace, ClosedFormsMatchCubatureOnTheGrid) {
  const double radius = 1.3;
  for (double m : {6.0, 12.0, 7.0, 13.0})
    for (double dr : kDistances)
      for (double c : kCosines) {
        const DiskHalfSpace law(m, radius);
        ASSERT_TRUE(law.is_closed_form());
        const double d = dr * radius;
        EXPECT_LT(relative_error(law.jet(d, c).value, reference::disk_halfspace(m, radius, d, c)),
                  kTolerance) << "m=" << m << " d/R=" << dr << " c=" << c;
      }
}

TEST(DiskHalfSpace, Equation55IsTheSixthPowerLaw) {
  const double radius = 0.7, d = 1.2, c = 0.8, pi = std::numbers::pi;
  const double eq55 = pi * pi * radius * radius /
                      (6 * std::pow(d * d - radius * radius * c * c, 1.5));
  EXPECT_NEAR(DiskHalfSpace(6, radius).jet(d, c).value / eq55, 1.0, 1e-14);
}

TEST(DiskHalfSpace, NonIntegerAndSmallExponentsUseQuadratureToTwelveDigits) {
  const double radius = 1.0;
  for (double m : {4.0, 4.5, 5.0, 7.25, 9.9})
    for (double dr : {1.01, 1.5, 20.0})
      for (double c : {0.0, 0.5, 1.0}) {
        const DiskHalfSpace law(m, radius);
        ASSERT_FALSE(law.is_closed_form());
        EXPECT_LT(relative_error(law.jet(dr, c).value, reference::disk_halfspace(m, radius, dr, c)),
                  1e-10) << "m=" << m << " d/R=" << dr << " c=" << c;
      }
}

TEST(DiskHalfSpace, QuadraturePathAgreesWithClosedFormAtIntegerExponent) {
  // 6.0000000001 takes the quadrature path; its law differs from m = 6 by O(1e-10) relative.
  const DiskHalfSpace closed(6, 1.0), numeric(6.0 + 1e-10, 1.0);
  const auto a = closed.jet(1.05, 0.9), b = numeric.jet(1.05, 0.9);
  EXPECT_LT(relative_error(b.value, a.value), 1e-8);
  EXPECT_LT(relative_error(b.dd, a.dd), 1e-8);
  EXPECT_LT(relative_error(b.ss, a.ss), 1e-8);
}

TEST(DiskPlate, ClosedFormsMatchCubatureOnTheGrid) {
  const double radius = 1.0;
  for (double m : {6.0, 12.0})
    for (double h : {0.1, 1.0, 10.0})
      for (double dr : kDistances)
        for (double c : kCosines) {
          const double d = dr * radius + 0.5 * h;  // d/R is the disk-to-surface distance here
          const DiskPlate plate(m, radius, h);
          EXPECT_LT(relative_error(plate.jet(d, c).value,
                                   reference::disk_plate(m, radius, h, d, c)),
                    kTolerance) << "m=" << m << " h=" << h << " d/R=" << dr << " c=" << c;
        }
}

TEST(DiskPlate, StableFormAtLargeDistanceAgreesWithBothSidesOfTheSwitch) {
  // Just beyond the switch the plain difference still holds ~14-15 digits, so the two forms must
  // agree to 1e-12; far away the stable form must still match the reference.
  const double radius = 1.0, h = 0.2, c = 0.6;
  const double d = c * radius + kThicknessQuadratureRatio * 0.5 * h * 1.0001;
  const DiskPlate plate(12, radius, h);
  const DiskHalfSpace half(12, radius);
  const double plain = half.jet(d - 0.1, c).value - half.jet(d + 0.1, c).value;
  EXPECT_LT(relative_error(plate.jet(d, c).value, plain), 1e-12);
  const double far = 500.0;  // (d - cR)/(h/2) ~ 5000: the stable form
  EXPECT_LT(relative_error(plate.jet(far, c).value, reference::disk_plate(12, radius, h, far, c)), 1e-9);
}

TEST(DiskSphere, CorrectedPointSphereLawF1MatchesCubature) {
  for (double t : {1.001, 1.2, 3.0, 30.0})
    EXPECT_LT(relative_error(point_sphere(1.0, t).value, reference::point_sphere(1.0, t)), 1e-10)
        << "t=" << t;
}

TEST(DiskSphere, CorrectedF4MatchesCubatureIncludingLargeDistances) {
  for (double rs : {0.5, 1.0, 10.0})
    for (double gap : {0.01, 0.3, 3.0, 20.0}) {
      const double rd = 1.0, d = rd + rs + gap;
      EXPECT_LT(relative_error(disk_sphere(rd, rs, d).value, reference::disk_sphere(rd, rs, d)),
                kTolerance) << "R_S=" << rs << " g=" << gap;
    }
}

TEST(DiskSphere, PrintedF4DenominatorIsWrong) {
  // As printed, {[d^2 - (R_D+R_S)]^2 [d^2 + (R_D+R_S)]^2}^(3/2); it misses the reference by far.
  const double rd = 1, rs = 2, d = 3.5, pi = std::numbers::pi;
  const double n = std::pow(rs, 6) + (rd * rd - 3 * d * d) * std::pow(rs, 4) +
                   3 * (std::pow(d, 4) - std::pow(rd, 4)) * rs * rs - std::pow(d * d - rd * rd, 3);
  const double printed_denominator =
      std::pow(std::pow(d * d - (rd + rs), 2) * std::pow(d * d + (rd + rs), 2), 1.5);
  const double printed = pi * pi / (3 * rs) * (1 + n / printed_denominator);
  EXPECT_GT(relative_error(printed, reference::disk_sphere(rd, rs, d)), 1e-2);
}

TEST(Reference, EllipticAngularIntegralMatchesDirectQuadrature) {
  for (double ratio : {0.0, 0.3, 0.9, 0.999}) {
    const double a = 2.0, b = ratio * a;
    const double direct = integrate([&](double t) { return std::pow(a - b * std::cos(t), -2.5); },
                                    0.0, std::numbers::pi, 1e-13);
    EXPECT_LT(relative_error(reference::angular_integral_five_halves(a, b), direct), 1e-11);
  }
}

TEST(LennardJones, IsTheWeightedSumOfTheGeometricPlateLaws) {
  const LennardJonesDiskPlate lj{0.3, 0.5, 1.0, 0.4, 2.0, 3.0, 1.5};
  const double d = 1.0, c = 0.7, scale = 1.5 * 2.0 * 3.0 * 4 * 0.3;
  const double expected = scale * (-std::pow(0.5, 6) * DiskPlate(6, 1.0, 0.4).jet(d, c).value +
                                   std::pow(0.5, 12) * DiskPlate(12, 1.0, 0.4).jet(d, c).value);
  EXPECT_LT(relative_error(lj.evaluate(d, c).value, expected), 1e-14);
}

TEST(LennardJones, EquilibriumDistanceIsARootOfTheForce) {
  const LennardJonesDiskPlate lj{1.0, 0.1, 1.0, 0.2};
  for (double c : {1.0, 0.5}) {
    const double d = lj.equilibrium_distance(c);
    const LawValue v = lj.evaluate(d, c);
    // |phi_d| must be at rounding level relative to the curvature times the distance scale.
    EXPECT_LT(std::abs(v.d_d), 1e-10 * std::abs(v.d_dd) * 0.1);
    EXPECT_GT(v.d_dd, 0.0);  // a minimum
    EXPECT_GT(d, c * 1.0 + 0.1);
  }
}

}  // namespace
}  // namespace fibrane::laws
