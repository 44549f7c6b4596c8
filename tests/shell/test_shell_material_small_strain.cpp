// The neo-Hookean materials reduce to St. Venant-Kirchhoff (Eq. 26, integrated as Eq. 29) for small
// strains, with mu = E / (2 (1 + nu)) and lambda = E nu / ((1 + nu)(1 - 2 nu)) condensed to plane stress
// (nu = 1/2, E = 3 mu for the incompressible one), membrane (h) and bending (h^3 / 12) parts alike.
//
// Error scaling with the strain size eps (E(zeta) = O(eps) through the thickness): psi = E:C:E/2 + O(eps^3),
// so S = C:E + O(eps^2) and the relative difference of the energy, N, M and dN/de to SVK is O(eps): it halves
// with eps. In pure bending (e = 0, E = zeta k) the O(eps^2) stress term is even in zeta and drops out of
// M = int zeta S dzeta, and the O(eps^3) energy term is odd in zeta, so M and the energy differ by O(eps^2)
// relative: a quarter for half the curvature.
#include <gtest/gtest.h>

#include "shell/material_states.hpp"

namespace fibrane::shell {
namespace {

using testing::strained;

constexpr double kThickness = 0.2;

// A neo-Hookean material with the SVK plane-stress matrix it must reduce to.
struct Pair {
  std::string name;
  std::shared_ptr<const ShellMaterial> material;
  double young, poisson;
};

std::vector<Pair> pairs() {
  return {{"neo_hookean", std::make_shared<const NeoHookeanMaterial>(1000.0, 0.3, 4), 1000.0, 0.3},
          {"neo_hookean_incompressible", std::make_shared<const IncompressibleNeoHookeanMaterial>(200.0, 4), 600.0,
           0.5}};
}

// SVK section response (Eqs. 26, 29) from the plane-stress matrix.
SectionResponse svk(const Pair& p, const SurfaceMetric& ref, const Eigen::Vector3d& e, const Eigen::Vector3d& k) {
  const Eigen::Matrix3d D = plane_stress_matrix(p.young, p.poisson, ref.inverse_metric);
  const double h = kThickness, bending = h * h * h / 12.0;
  SectionResponse r;
  r.N = h * D * e;
  r.M = bending * D * k;
  r.energy = 0.5 * (e.dot(r.N) + k.dot(r.M));
  r.dN_de = h * D;
  r.dM_dk = bending * D;
  return r;
}

double rel(double a, double b) { return std::abs(a - b) / std::abs(b); }
double rel(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

// At zero strain the tangent blocks are SVK's exactly (4 Gauss points integrate zeta^2 exactly) and the
// coupling blocks vanish (symmetric points): only round-off, 1e-12 relative.
TEST(ShellMaterialSmallStrain, TangentAtZeroStrainIsSvk) {
  std::mt19937 rng(41);
  const SurfaceMetric ref = testing::random_reference(rng);
  for (const Pair& p : pairs()) {
    const SectionResponse nh = p.material->respond(ref, ref, kThickness, true);
    const SectionResponse lin = svk(p, ref, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
    EXPECT_LT(rel(nh.dN_de, lin.dN_de), 1e-12) << p.name;
    EXPECT_LT(rel(nh.dM_dk, lin.dM_dk), 1e-12) << p.name;
    EXPECT_LT(nh.dN_dk.cwiseAbs().maxCoeff(), 1e-12 * kThickness * lin.dN_de.cwiseAbs().maxCoeff()) << p.name;
    EXPECT_LT(std::abs(nh.energy), 1e-12 * lin.dN_de.cwiseAbs().maxCoeff()) << p.name;
    EXPECT_LT(nh.N.cwiseAbs().maxCoeff(), 1e-12 * lin.dN_de.cwiseAbs().maxCoeff()) << p.name;
  }
}

// Membrane and bending strains together: every relative difference is O(eps) and halves with eps
// (ratio 2 within 5 %: the next term changes it by O(eps) = 1e-3). The constant is the size of psi''' over
// psi'' along the strain path, O(10) for these materials and this path (the surface strains reach 2 eps;
// measured up to 25 for N); the bound 50 eps only catches a wrong limit, the ratio is the check.
TEST(ShellMaterialSmallStrain, DifferenceToSvkIsFirstOrderInStrain) {
  std::mt19937 rng(42);
  const SurfaceMetric ref = testing::random_reference(rng);
  const Eigen::Vector3d e_dir = testing::random_voigt(1.0, rng);
  const Eigen::Vector3d k_dir = testing::random_voigt(2.0 / kThickness, rng);  // zeta k = O(1) at the faces
  for (const Pair& p : pairs()) {
    double previous[4] = {};
    for (double eps : {1e-3, 5e-4}) {
      const Eigen::Vector3d e = eps * e_dir, k = eps * k_dir;
      const SectionResponse nh = p.material->respond(ref, strained(ref, e, k), kThickness, true);
      const SectionResponse lin = svk(p, ref, e, k);
      const double err[4] = {rel(nh.energy, lin.energy), rel(nh.N, lin.N), rel(nh.M, lin.M),
                             rel(nh.dN_de, lin.dN_de)};
      for (int i = 0; i < 4; ++i) {
        EXPECT_LT(err[i], 50.0 * eps) << p.name << " quantity " << i;
        if (previous[i] > 0) {
          EXPECT_NEAR(previous[i] / err[i], 2.0, 0.1) << p.name << " quantity " << i;
        }
        previous[i] = err[i];
      }
    }
  }
}

// Pure bending: the energy, M and dM/dk differ by O(eps^2) relative (ratio 4 within 5 %; dM/dk =
// int zeta^2 D(zeta k) loses its O(eps) term, odd in zeta, like M), and are below 50 eps^2.
TEST(ShellMaterialSmallStrain, PureBendingDifferenceIsSecondOrder) {
  std::mt19937 rng(43);
  const SurfaceMetric ref = testing::random_reference(rng);
  const Eigen::Vector3d k_dir = testing::random_voigt(2.0 / kThickness, rng);
  for (const Pair& p : pairs()) {
    double previous[3] = {};
    for (double eps : {1e-3, 5e-4}) {
      const Eigen::Vector3d e = Eigen::Vector3d::Zero(), k = eps * k_dir;
      const SectionResponse nh = p.material->respond(ref, strained(ref, e, k), kThickness, true);
      const SectionResponse lin = svk(p, ref, e, k);
      const double err[3] = {rel(nh.energy, lin.energy), rel(nh.M, lin.M), rel(nh.dM_dk, lin.dM_dk)};
      for (int i = 0; i < 3; ++i) {
        EXPECT_LT(err[i], 50.0 * eps * eps) << p.name << " quantity " << i;
        if (previous[i] > 0) {
          EXPECT_NEAR(previous[i] / err[i], 4.0, 0.2) << p.name << " quantity " << i;
        }
        previous[i] = err[i];
      }
    }
  }
}

}  // namespace
}  // namespace fibrane::shell
