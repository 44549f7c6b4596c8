// SBS pair kernel (Eqs. 62-78, App. C-E) against central finite differences on deformed curved shells
// (a random bicubic B-spline patch and a rational sphere patch) with a bent quartic beam close by:
// d = h/2 + (1.05 .. 3) R, t . n from 0 (cos a = 1) to 0.995 (cos a ~ 0.1).
#include <gtest/gtest.h>

#include <functional>
#include <random>

#include "laws/lennard_jones.hpp"
#include "pair_fixture.hpp"
#include "test_geometry.hpp"

namespace fibrane::interaction {
namespace {

laws::LennardJonesDiskPlate test_law() {
  laws::LennardJonesDiskPlate law{};
  law.epsilon = 1.0;
  law.sigma = 0.1;
  law.disk_radius = 0.3;
  law.plate_thickness = 0.2;
  return law;
}

// Central differences: truncation h^2 |f'''| / 6 with |f'''| / |f'| ~ 1 / gap^2, gap >= 0.015 here, and
// round-off eps |f| / h. Relative truncation at h = 1e-6: ~1e-12 / 2e-4 / 6 ~ 1e-9; round-off ~1e-10
// (times the ratio |f| / |f'| gap, O(1)). Both far below the 1e-6 acceptance.
constexpr double kStep = 1e-6;
constexpr double kTol = 1e-6;

Eigen::MatrixXd central_jacobian(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& fun,
                                 const Eigen::VectorXd& q) {
  const Eigen::VectorXd f0 = fun(q);
  Eigen::MatrixXd jac(f0.size(), q.size());
  for (Eigen::Index j = 0; j < q.size(); ++j) {
    Eigen::VectorXd qp = q, qm = q;
    qp[j] += kStep;
    qm[j] -= kStep;
    jac.col(j) = (fun(qp) - fun(qm)) / (2 * kStep);
  }
  return jac;
}

double relative_error(const Eigen::MatrixXd& a, const Eigen::MatrixXd& reference) {
  return (a - reference).cwiseAbs().maxCoeff() / reference.cwiseAbs().maxCoeff();
}

struct Shell {
  const char* name;
  spline::NurbsSurface surface;
  double u0, v0;
};

std::vector<Shell> shells() {
  std::vector<Shell> out;
  out.push_back({"random bicubic", test::random_patch(4, 21), 0.37, 0.62});
  out.push_back({"sphere", test::sphere(), 0.47, 0.53});
  return out;
}

std::vector<Eigen::Vector3d> deformed(const spline::NurbsSurface& s, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> jiggle(-0.04, 0.04);
  std::vector<Eigen::Vector3d> x = s.control_points();
  for (Eigen::Vector3d& p : x) p += Eigen::Vector3d(jiggle(gen), jiggle(gen), jiggle(gen));
  return x;
}

// Runs `check` on every state: 2 shells x 3 distances x 3 angles.
void for_each_state(const std::function<void(test::PairFixture&, const std::string&)>& check) {
  const laws::LennardJonesDiskPlate law = test_law();
  unsigned seed = 1;
  for (const Shell& shell : shells()) {
    for (double k : {1.05, 1.5, 3.0}) {
      for (double tn : {0.0, 0.6, 0.995}) {
        test::PairFixture fx(shell.surface, deformed(shell.surface, seed), shell.u0, shell.v0,
                             0.5 * law.plate_thickness + k * law.disk_radius, tn, seed);
        ++seed;
        check(fx, std::string(shell.name) + " d/R-h/2R=" + std::to_string(k) + " tn=" + std::to_string(tn));
      }
    }
  }
}

void check_tangent(Formulation f, FfTangent ft, bool symmetric) {
  const laws::LennardJonesDiskPlate law = test_law();
  double worst = 0;
  for_each_state([&](test::PairFixture& fx, const std::string& label) {
    const Eigen::VectorXd q = fx.dofs();
    const test::Evaluation ev = fx.evaluate(law, f, ft, q);
    ASSERT_EQ(ev.projection.where, ShellProximity::Projection::Where::interior) << label;
    ASSERT_EQ(ev.projection.element, fx.element()) << label;
    const Eigen::MatrixXd fd =
        central_jacobian([&](const Eigen::VectorXd& x) { return fx.evaluate(law, f, ft, x).residual; }, q);
    const double err = relative_error(ev.tangent, fd);
    worst = std::max(worst, err);
    EXPECT_LE(err, kTol) << label << " cos a = " << ev.result.cos_alpha;
    if (symmetric) {  // symmetric to round-off of the assembled products
      EXPECT_LE(relative_error(ev.tangent, ev.tangent.transpose()), 1e-12) << label;
    }
    for (int i = 0; i < 5; ++i) {  // the potential does not depend on the twist
      EXPECT_EQ(ev.residual[4 * i + 3], 0.0);
      EXPECT_EQ(ev.tangent.row(4 * i + 3).cwiseAbs().maxCoeff(), 0.0);
    }
  });
  std::printf("    worst tangent error %.2e\n", worst);
}

void check_residual_is_gradient(Formulation f) {
  const laws::LennardJonesDiskPlate law = test_law();
  double worst = 0;
  for_each_state([&](test::PairFixture& fx, const std::string& label) {
    const Eigen::VectorXd q = fx.dofs();
    const test::Evaluation ev = fx.evaluate(law, f, FfTangent::rf1, q);
    const Eigen::MatrixXd fd = central_jacobian(
        [&](const Eigen::VectorXd& x) {
          return Eigen::VectorXd::Constant(1, fx.evaluate(law, f, FfTangent::rf1, x).energy);
        },
        q);
    const double err = relative_error(ev.residual.transpose(), fd);
    worst = std::max(worst, err);
    EXPECT_LE(err, kTol) << label;
  });
  std::printf("    worst residual error %.2e\n", worst);
}

TEST(SbsPoint, Rf2TangentIsExactAndSymmetric) { check_tangent(Formulation::RF2, FfTangent::rf1, true); }
TEST(SbsPoint, Rf2ResidualIsEnergyGradient) { check_residual_is_gradient(Formulation::RF2); }
TEST(SbsPoint, Rf1TangentIsExactForItsResidual) { check_tangent(Formulation::RF1, FfTangent::rf1, false); }
TEST(SbsPoint, FfResidualIsEnergyGradient) { check_residual_is_gradient(Formulation::FF); }
TEST(SbsPoint, FfExactTangent) { check_tangent(Formulation::FF, FfTangent::exact, true); }

// The RF1 residual is NOT the gradient of phi(d, cos a) once the beam is tilted: the test above would
// detect a kernel that silently used the FF residual (and vice versa).
TEST(SbsPoint, Rf1DiffersFromFfWhenTilted) {
  const laws::LennardJonesDiskPlate law = test_law();
  const spline::NurbsSurface s = test::random_patch(4, 21);
  test::PairFixture fx(s, deformed(s, 3), 0.37, 0.62, 0.1 + 1.5 * 0.3, 0.6, 3);
  const auto rf1 = fx.evaluate(law, Formulation::RF1, FfTangent::rf1, fx.dofs());
  const auto ff = fx.evaluate(law, Formulation::FF, FfTangent::rf1, fx.dofs());
  EXPECT_GT(relative_error(rf1.residual, ff.residual), 1e-3);
  EXPECT_EQ(relative_error(rf1.tangent, ff.tangent), 0.0);  // FF with the paper's (RF1) tangent
}

}  // namespace
}  // namespace fibrane::interaction
