// Derivatives against finite differences, reduced forms at cos a -> 0, and the small-gap limits of
// Eqs. (57) and (58).
#include <gtest/gtest.h>

#include <cmath>

#include "laws/disk_halfspace.hpp"
#include "laws/disk_plate.hpp"
#include "laws/disk_sphere.hpp"
#include "laws/lennard_jones.hpp"

namespace fibrane::laws {
namespace {

// Five-point central difference (fourth order). With step 1e-3 of the local length scale the
// truncation error is ~1e-12 relative and rounding ~1e-13 / 1e-3, so 1e-7 (the acceptance bound)
// is met with margin; a wrong derivative term is off by O(1).
template <class F>
double five_point(F f, double x, double h) {
  return (f(x - 2 * h) - 8 * f(x - h) + 8 * f(x + h) - f(x + 2 * h)) / (12 * h);
}

void expect_close(double analytic, double numeric, double scale, const char* what, double d, double c) {
  EXPECT_LE(std::abs(analytic - numeric), 1e-7 * std::max(std::abs(numeric), scale))
      << what << " at d=" << d << " c=" << c << ": " << analytic << " vs " << numeric;
}

template <class Law>
void check_derivatives(const Law& law, double d, double c, double gap) {
  const LawValue v = law.evaluate(d, c);
  const double hd = 1e-3 * gap, hc = 1e-3 * gap;  // unit disk radius: c moves the edge by hc
  auto at = [&](double dd, double cc) { return law.evaluate(dd, cc); };
  // Scales for derivatives that vanish (e.g. phi_c at c = 0): the natural size |phi|/gap^k.
  const double s0 = std::abs(v.value), sd = s0 / gap, sdd = sd / gap;
  expect_close(v.d_d, five_point([&](double x) { return at(x, c).value; }, d, hd), sd, "phi_d", d, c);
  expect_close(v.d_dd, five_point([&](double x) { return at(x, c).d_d; }, d, hd), sdd, "phi_dd", d, c);
  expect_close(v.d_c, five_point([&](double x) { return at(d, x).value; }, c, hc), sd, "phi_c", d, c);
  expect_close(v.d_cc, five_point([&](double x) { return at(d, x).d_c; }, c, hc), sdd, "phi_cc", d, c);
  expect_close(v.d_dc, five_point([&](double x) { return at(d, x).d_d; }, c, hc), sdd, "phi_dc", d, c);
  expect_close(v.d_dc, five_point([&](double x) { return at(x, c).d_c; }, d, hd), sdd, "phi_cd", d, c);
  if (c > 0) {
    EXPECT_NEAR(v.reduced_c * c, v.d_c, 1e-14 * std::abs(v.d_c) + 1e-300);
    EXPECT_NEAR(v.reduced_dc * c, v.d_dc, 1e-14 * std::abs(v.d_dc) + 1e-300);
  }
}

TEST(Derivatives, DiskHalfSpaceAndPlateMatchFiniteDifferences) {
  for (double m : {6.0, 12.0, 4.5}) {
    const DiskHalfSpace half(m, 1.0);
    const DiskPlate plate(m, 1.0, 0.5);
    for (double dr : {1.05, 2.0, 20.0})
      for (double c : {0.0, 0.4, 1.0}) {
        check_derivatives(half, dr, c, dr - c);
        check_derivatives(plate, dr + 0.25, c, dr - c);
      }
  }
}

TEST(Derivatives, LennardJonesMatchesFiniteDifferencesAcrossTheWell) {
  const LennardJonesDiskPlate lj{1.0, 0.05, 1.0, 0.2, 1.0, 1.0, 2.0};
  const double d_eq = lj.equilibrium_distance(1.0);
  for (double factor : {0.999, 1.0, 1.2, 3.0, 50.0})
    for (double c : {0.0, 0.5, 1.0}) {
      const double contact = c + 0.1;
      const double d = contact + factor * (d_eq - 1.1);
      check_derivatives(lj, d, c, d - contact);
    }
}

TEST(Derivatives, DiskSphereMatchesFiniteDifferences) {
  for (double gap : {0.01, 1.0, 30.0}) {
    const double d = 1.0 + 2.0 + gap;
    auto value = [&](double x) { return disk_sphere(1.0, 2.0, x).value; };
    auto slope = [&](double x) { return disk_sphere(1.0, 2.0, x).d1; };
    const ScalarJet v = disk_sphere(1.0, 2.0, d);
    EXPECT_LE(std::abs(v.d1 - five_point(value, d, 1e-3 * gap)), 1e-7 * std::abs(v.d1));
    EXPECT_LE(std::abs(v.d2 - five_point(slope, d, 1e-3 * gap)), 1e-7 * std::abs(v.d2));
  }
}

TEST(ReducedForms, FiniteAndContinuousAtCosZero) {
  const LennardJonesDiskPlate lj{1.0, 0.05, 1.0, 0.2};
  for (double d : {0.4, 0.6, 3.0}) {
    const LawValue at_zero = lj.evaluate(d, 0.0);
    ASSERT_TRUE(std::isfinite(at_zero.reduced_c) && std::isfinite(at_zero.reduced_dc));
    EXPECT_NE(at_zero.reduced_c, 0.0);  // the limit is phi_cc(0), not zero
    EXPECT_NEAR(at_zero.reduced_c, at_zero.d_cc, 1e-13 * std::abs(at_zero.d_cc));
    // Continuity: the reduced forms are even in c, so they change by O((c R / gap)^2) relative;
    // 100 (c R / gap)^2 bounds the coefficient, 1e-13 the rounding.
    const double gap = d - 0.1;
    for (double c : {1e-3, 1e-6, 1e-9}) {
      const LawValue v = lj.evaluate(d, c);
      const double bound = 100 * (c / gap) * (c / gap) + 1e-13;
      EXPECT_NEAR(v.reduced_c, at_zero.reduced_c, bound * std::abs(at_zero.reduced_c));
      EXPECT_NEAR(v.reduced_dc, at_zero.reduced_dc, bound * std::abs(at_zero.reduced_dc));
    }
  }
}

TEST(SmallGapLimits, Equation57DiskSphereApproachesDiskSphericalShell) {
  // (Pi_DSS - Pi_DS)/Pi_DSS -> 0: the inner surface of the shell stops mattering near contact.
  const double rd = 1.0, rss = 5.0, h = 0.5;
  double previous = 1.0;
  for (double gap : {1e-1, 1e-3, 1e-5}) {
    const double d = rd + rss + 0.5 * h + gap;
    const double shell = disk_spherical_shell(rd, rss, h, d).value;
    const double sphere = disk_sphere(rd, rss + 0.5 * h, d).value;
    const double error = std::abs((shell - sphere) / shell);
    EXPECT_LT(error, previous);
    previous = error;
  }
  EXPECT_LT(previous, 1e-6);
}

TEST(SmallGapLimits, Equation58DiskPlateErrorTendsToTheBound) {
  for (double rss : {2.0, 10.0})
    for (double h : {0.1, 1.0}) {
      const double rd = 1.0, bound = 1 - std::sqrt(1 + 2 * rd / (h + 2 * rss));
      const DiskPlate plate(6, rd, h);
      double previous = 1.0;
      for (double gap : {1e-2, 1e-4, 1e-6}) {
        const double shell = disk_spherical_shell(rd, rss, h, rd + rss + 0.5 * h + gap).value;
        const double flat = plate.jet(rd + 0.5 * h + gap, 1.0).value;
        const double distance = std::abs((shell - flat) / shell - bound);
        EXPECT_LT(distance, previous);
        previous = distance;
      }
      // The approach is O(sqrt(g/R)): at g = 1e-6 R the error is within 1e-2 of Eq. (58).
      EXPECT_LT(previous, 1e-2) << "R_SS=" << rss << " h=" << h;
    }
}

}  // namespace
}  // namespace fibrane::laws
