// The section-beam interaction potential (interaction/section_beam.hpp, laws/section_cylinder.hpp):
// energies and forces of two straight fibers, parallel and crossed, against the direct integration of the
// point-pair law over both volumes (cylinder_reference.hpp) and against the Derjaguin limits; the error
// study over the separation; exact derivatives against central differences on curved states.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "cylinder_reference.hpp"
#include "sbip_energies.hpp"
#include "interaction/section_beam.hpp"
#include "laws/disk_halfspace.hpp"
#include "spline/curve.hpp"
#include "spline/knot_vector.hpp"

namespace fibrane::interaction {
namespace {

using laws::SectionCylinderLaw;

// One inverse-power term k r^-m with unit densities; radii ra, rb.
SectionCylinderLaw power_law(double m, double k, double ra, double rb) { return {{{m, k}}, ra, rb}; }

using test::sbip_crossed;
using test::sbip_parallel;

// Derjaguin limits (Israelachvili ch. 13), Hamaker constant A = pi^2 C rho_A rho_B for k = -C.
double derjaguin_crossed(double hamaker, double ra, double rb, double gap) {
  return -hamaker * std::sqrt(ra * rb) / (6 * gap);
}
double derjaguin_parallel(double hamaker, double ra, double rb, double gap) {
  return -hamaker / (12 * std::sqrt(2.0) * std::pow(gap, 1.5)) * std::sqrt(ra * rb / (ra + rb));
}

// (S4'): against a cylinder so wide that it is a half-space, the vdW (m = 6) section law is the paper's
// exact disk-half-space law, Eq. (55), at every gap and tilt of the section.
TEST(SectionBeamVerification, FlatLimitIsTheDiskHalfSpaceLaw) {
  const double ra = 0.4, rb = 1e7;
  const laws::DiskHalfSpace exact(6, ra);
  for (double beta : {0.0, 0.3, 1.0})
    for (double g : {0.01, 0.05, 0.5}) {
      const double c = std::cos(beta);
      SectionBeamPoint p;
      p.x = {0, 0, rb + g + ra * c};
      p.x_xi = {std::cos(beta), 0, std::sin(beta)};
      const double pi = section_beam(power_law(6, 1.0, ra, rb), p).energy;
      EXPECT_NEAR(pi / exact.evaluate(g + ra * c, c).value, 1.0, 1e-6) << "beta " << beta << " g " << g;
    }
}

TEST(SectionBeamReference, QuadratureConvergedAndMatchesDerjaguinAtContact) {
  // The reference itself: more points per panel change it by < 1e-8 (parallel) and 1e-7 (crossed); at
  // g = 1e-4 R it is the Derjaguin limit within 1 % (the next term is O(g / R)).
  const double ra = 1.0, rb = 0.6, gap = 1e-4, hamaker = M_PI * M_PI;
  const double par = test::parallel_cylinders(6, ra, rb, ra + rb + gap, 10);
  EXPECT_NEAR(test::parallel_cylinders(6, ra, rb, ra + rb + gap, 20) / par, 1.0, 1e-8);
  EXPECT_NEAR(-par / derjaguin_parallel(hamaker, ra, rb, gap), 1.0, 1e-2);
  const double cross = test::crossed_cylinders(6, ra, rb, ra + rb + gap, 6);
  EXPECT_NEAR(test::crossed_cylinders(6, ra, rb, ra + rb + gap, 10) / cross, 1.0, 1e-7);
  EXPECT_NEAR(-cross / derjaguin_crossed(hamaker, ra, rb, gap), 1.0, 1e-2);
}

// The error study (as the paper's Sec. 4 does for beam-shell): SBIP against the volume integral over the
// separation g / R = 0.1, 0.01, 0.001 (R = R_A = 1, R_B = 0.6), for the vdW (m = 6) and the steric (m = 12)
// terms; docs/verification.md lists the errors. The reference force is the central difference of the
// reference energy (step 1e-4 g), its energy the mean of the two (error 1e-8 g^2 / h^2 relative).
struct ErrorStudy {
  double energy, force;
};

template <class Sbip, class Reference>
ErrorStudy error_at(double g, const Sbip& sbip, const Reference& reference) {
  const double d = 1.6 + g, h = 1e-4 * g;
  const double ep = reference(d + h), em = reference(d - h);
  const double exact = 0.5 * (ep + em), exact_force = -(ep - em) / (2 * h);
  const double force = -(sbip(d + h) - sbip(d - h)) / (2 * h);
  return {std::abs(sbip(d) / exact - 1), std::abs(force / exact_force - 1)};
}

// Checks the errors fall with g (by > 4x per decade) below `energy_bound` g and 3 g (force), and that SBIP
// meets the Derjaguin limit at g = 1e-4.
template <class Sbip, class Reference>
void study(const char* what, double m, double energy_bound, const Sbip& sbip, const Reference& reference,
           double derjaguin_at_1e4) {
  double previous = 1e300;
  for (double g : {1e-1, 1e-2, 1e-3}) {
    const ErrorStudy e = error_at(g, sbip, reference);
    std::printf("%s m=%g g/R=%g: energy error %.3e, force error %.3e\n", what, m, g, e.energy, e.force);
    EXPECT_LT(e.energy, energy_bound * g) << what << " m = " << m << " g = " << g;
    EXPECT_LT(e.force, 3 * g) << what << " m = " << m << " g = " << g;
    EXPECT_LT(4 * e.energy, previous) << what << " m = " << m << " g = " << g;
    previous = e.energy;
  }
  if (m == 6) {
    EXPECT_NEAR(sbip(1.6 + 1e-4) / derjaguin_at_1e4, 1.0, 5e-3) << what;
  }
}

TEST(SectionBeamVerification, ParallelFibersEnergyAndForce) {
  const double ra = 1.0, rb = 0.6;
  for (double m : {6.0, 12.0}) {
    const SectionCylinderLaw law = power_law(m, -1.0, ra, rb);
    study("parallel", m, 3, [&](double d) { return sbip_parallel(law, d); },
          [&](double d) { return -test::parallel_cylinders(m, ra, rb, d, 10); },
          derjaguin_parallel(M_PI * M_PI, ra, rb, 1e-4));
  }
}

TEST(SectionBeamVerification, CrossedFibersEnergyAndForce) {
  // m = 6: the sections beyond ~R from the crossing see B as a half-space (their potential falls like
  // s^-3 instead of s^-5), so the energy converges more slowly than first order (bound 15 g); the
  // force, dominated by the crossing, first order.
  const double ra = 1.0, rb = 0.6;
  for (double m : {6.0, 12.0}) {
    const SectionCylinderLaw law = power_law(m, -1.0, ra, rb);
    study("crossed", m, m == 6 ? 15 : 3, [&](double d) { return sbip_crossed(law, d, 10); },
          [&](double d) { return -test::crossed_cylinders(m, ra, rb, d, 6); },
          derjaguin_crossed(M_PI * M_PI, ra, rb, 1e-4));
  }
}

// A random curved, non-planar cubic fiber pair near contact: A roughly along x at height `height`, B
// roughly along y; control points perturbed by up to `wiggle`.
struct CurvedPair {
  spline::NurbsCurve a, b;
  double xi_a = 0.43;
};

CurvedPair random_pair(std::mt19937& rng, double height, double wiggle) {
  std::uniform_real_distribution<double> u(-wiggle, wiggle);
  const spline::KnotVector kv(3, {0, 0, 0, 0, 1, 1, 1, 1});
  std::vector<Eigen::Vector3d> pa, pb;
  for (int i = 0; i < 4; ++i) {
    const double s = -1.5 + i;
    pa.emplace_back(s + u(rng), u(rng), height + u(rng) + 0.1 * s * s);
    pb.emplace_back(u(rng), s + u(rng), u(rng) - 0.1 * s * s);
  }
  return {spline::NurbsCurve(kv, pa), spline::NurbsCurve(kv, pb)};
}

// Energy, residual and tangent of one SBIP point of A against B at the DOFs q = [A: 4 x 4, B: 4 x 4]
// (x, y, z, twist per control point, added to the curves' control points); B's closest point is found
// anew for every q.
SectionBeamResult evaluate_pair(const SectionCylinderLaw& law, const CurvedPair& pair, const Eigen::VectorXd& q,
                                double* energy, Eigen::VectorXd* residual, Eigen::MatrixXd* tangent) {
  Eigen::Matrix3Xd xa(3, 4), xb(3, 4);
  for (int j = 0; j < 4; ++j) {
    xa.col(j) = pair.a.control_points()[j] + q.segment<3>(4 * j);
    xb.col(j) = pair.b.control_points()[j] + q.segment<3>(16 + 4 * j);
  }
  const Eigen::MatrixXd ba = pair.a.basis(pair.xi_a, 1).R;
  const Eigen::Vector3d x = xa * ba.row(0).transpose();
  auto axis = [&](double xi) -> Eigen::Matrix<double, 3, 4> {
    return xb * pair.b.basis(xi, 3).R.transpose();
  };
  double xi_b = 0.5;
  EXPECT_TRUE(closest_on_axis(x, axis, 0.0, 1.0, xi_b));
  const Eigen::MatrixXd bb = pair.b.basis(xi_b, 3).R;
  return add_section_beam_point(law, ba, xa, bb, xb, 0.7, energy, residual, tangent);
}

TEST(SectionBeamTangent, CentralDifferencesOnRandomCurvedStates) {
  std::mt19937 rng(20231);
  // A 12-6 law with regularization (some states lie below g_r) and a cut-off with its taper.
  const SectionCylinderLaw law({{6, -1.0}, {12, 1e-4}}, 0.3, 0.25, 2.0, 0.02, 0.6);
  int checked = 0, regularized = 0, tapered = 0;
  double worst_r = 0, worst_k = 0;
  for (int trial = 0; trial < 12; ++trial) {
    const CurvedPair pair = random_pair(rng, 0.22 + 0.045 * trial, 0.1);
    const Eigen::VectorXd q0 = Eigen::VectorXd::Zero(32);
    double e0 = 0;
    Eigen::VectorXd r0;
    Eigen::MatrixXd k0;
    const SectionBeamResult res = evaluate_pair(law, pair, q0, &e0, &r0, &k0);
    if (!res.active) continue;
    ++checked;
    regularized += res.gap < law.regularization_gap();
    tapered += res.gap > 0.3;
    const double h = 1e-6;
    Eigen::VectorXd fd_r = Eigen::VectorXd::Zero(32);
    Eigen::MatrixXd fd_k = Eigen::MatrixXd::Zero(32, 32);
    for (int i = 0; i < 32; ++i) {
      Eigen::VectorXd qp = q0, qm = q0;
      qp[i] += h;
      qm[i] -= h;
      double ep = 0, em = 0;
      Eigen::VectorXd rp, rm;
      evaluate_pair(law, pair, qp, &ep, &rp, nullptr);
      evaluate_pair(law, pair, qm, &em, &rm, nullptr);
      fd_r[i] = (ep - em) / (2 * h);
      if (rp.size() == 0) rp.setZero(32);
      if (rm.size() == 0) rm.setZero(32);
      fd_k.col(i) = (rp - rm) / (2 * h);
    }
    EXPECT_LT((fd_r - r0).norm(), 1e-6 * r0.norm()) << "trial " << trial;
    EXPECT_LT((fd_k - k0).norm(), 1e-6 * k0.norm()) << "trial " << trial;
    worst_r = std::max(worst_r, (fd_r - r0).norm() / r0.norm());
    worst_k = std::max(worst_k, (fd_k - k0).norm() / k0.norm());
    EXPECT_LT((k0 - k0.transpose()).norm(), 1e-12 * k0.norm());
    // Translation invariance: the forces on A and B balance (action = reaction).
    Eigen::Vector3d total = Eigen::Vector3d::Zero();
    for (int j = 0; j < 8; ++j) total += r0.segment<3>(4 * j);
    EXPECT_LT(total.norm(), 1e-10 * r0.norm());
  }
  std::printf("worst relative error: residual %.2e, tangent %.2e\n", worst_r, worst_k);
  EXPECT_GE(checked, 8);
  EXPECT_GE(regularized, 1);
  EXPECT_GE(tapered, 1);
}

}  // namespace
}  // namespace fibrane::interaction
