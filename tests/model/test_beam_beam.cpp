// BeamBeamInteraction (model/beam_beam.hpp) in a model: the assembled residual and tangent of two curved
// beams and of a fiber folded onto itself against central differences, the energy's gradient, the balance
// of the forces on the two fibers, and the observables.
#include <gtest/gtest.h>

#include <limits>
#include <memory>
#include <random>

#include "case_runner.hpp"
#include "common/error.hpp"
#include "model/beam_beam.hpp"
#include "model/beam_body.hpp"
#include "model/model.hpp"
#include "spline/curve.hpp"
#include "spline/knot_vector.hpp"

namespace fibrane::testing {
namespace {

// A cubic beam through `points` (control points of an open uniform B-spline), refined to `elements`.
model::BeamBody make_fiber(const std::string& name, const std::vector<Eigen::Vector3d>& points, double radius,
                           int elements) {
  const int n = static_cast<int>(points.size());
  std::vector<double> knots(4, 0.0);
  for (int i = 1; i < n - 3; ++i) knots.push_back(static_cast<double>(i) / (n - 3));
  knots.insert(knots.end(), 4, 1.0);
  spline::NurbsCurve curve(spline::KnotVector(3, knots), points);
  curve.refine(3, 2, elements);
  // A soft section (E = 1e-3): the interaction dominates the tangent, so an error in it cannot hide.
  model::BeamBody body(name, curve, beam::BeamSection::circular(1e-3, 0.3, radius), Eigen::Vector3d::Zero());
  body.section_radius = radius;
  return body;
}

double total_energy(const model::Model& m) { return m.strain_energy() + m.energy(model::EnergyKind::interaction); }

// Checks residual = dE/dq and tangent = dr/dq at a random state near q = 0; returns the interaction.
void check_derivatives(model::Model& m, unsigned seed, double amplitude) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  Eigen::VectorXd q(m.size());
  for (int i = 0; i < q.size(); ++i) q[i] = u(rng);
  m.evaluate(q, 1.0, true);
  ASSERT_TRUE(m.invalid_state().empty()) << m.invalid_state();
  const Eigen::VectorXd r = m.residual();
  const Eigen::MatrixXd k = Eigen::MatrixXd(m.tangent());
  // Central differences, h = 1e-6: truncation ~1e-12, round-off ~1e-10 relative.
  const Eigen::MatrixXd kfd = finite_difference_tangent(m, q, 1.0, 1e-6);
  EXPECT_LT((k - kfd).cwiseAbs().maxCoeff(), 1e-6 * k.cwiseAbs().maxCoeff());
  Eigen::VectorXd dir(q.size());
  for (int i = 0; i < q.size(); ++i) dir[i] = u(rng);
  const double h = 1e-6;
  m.evaluate(q + h * dir, 1.0, false);
  const double ep = total_energy(m);
  m.evaluate(q - h * dir, 1.0, false);
  const double em = total_energy(m);
  EXPECT_NEAR((ep - em) / (2 * h), r.dot(dir), 1e-6 * r.norm() * dir.norm());
  m.evaluate(q, 1.0, true);
}

std::shared_ptr<laws::SectionCylinderLaw> law_for(double ra, double rb) {
  // 12-6 point pairs, regularized below g = 0.01, cut off at g = 0.5.
  return std::make_shared<laws::SectionCylinderLaw>(std::vector<laws::InversePowerTerm>{{6, -1.0}, {12, 1e-12}}, ra,
                                                    rb, 1.0, 0.01, 0.5);
}

TEST(BeamBeamInteraction, TwoCurvedBeamsTangentAndForces) {
  model::Model m;
  auto& a = m.add_beam(make_fiber("a", {{-1.5, -0.1, 0.42}, {-0.5, 0.2, 0.30}, {0.5, -0.2, 0.36}, {1.5, 0.1, 0.5}},
                                  0.2, 4));
  auto& b = m.add_beam(make_fiber("b", {{0.1, -1.5, -0.1}, {-0.2, -0.5, 0.0}, {0.2, 0.5, 0.05}, {0.0, 1.5, -0.2}},
                                  0.15, 4));
  auto& bb = dynamic_cast<model::BeamBeamInteraction&>(
      m.add_contribution(std::make_unique<model::BeamBeamInteraction>("ab", law_for(0.2, 0.15), a, b)));
  m.finalize();
  check_derivatives(m, 3, 0.02);
  EXPECT_GT(bb.interacting_points(), 4);
  EXPECT_GT(bb.interacting_pairs(), 1);
  EXPECT_LT(bb.minimum_gap(), 0.2);
  EXPECT_GT(bb.minimum_gap(), 0.0);
  EXPECT_LT(bb.energy(), 0.0);  // attraction dominates at these gaps
  // Action = reaction: the forces on the two fibers balance; fiber a is pulled down towards b.
  EXPECT_LT((bb.force_on(0) + bb.force_on(1)).norm(), 1e-10 * bb.force_on(0).norm());
  EXPECT_LT(bb.force_on(0).z(), 0.0);
  // Both passes report points along their fiber.
  int active[2] = {0, 0};
  for (int f = 0; f < 2; ++f)
    for (const auto& p : bb.points(f)) active[f] += p.active;
  EXPECT_GT(active[0], 0);
  EXPECT_GT(active[1], 0);
}

// The warm starts survive a restart: a model restored from the saved state evaluates to the same bits.
TEST(BeamBeamInteraction, SavedStateRestoresTheSameEvaluation) {
  auto build = [](model::Model& m) -> model::BeamBeamInteraction& {
    auto& a = m.add_beam(make_fiber("a", {{-1.5, 0, 0.45}, {-0.5, 0.1, 0.36}, {0.5, -0.1, 0.36}, {1.5, 0, 0.45}},
                                    0.2, 3));
    auto& b = m.add_beam(make_fiber("b", {{0, -1.5, 0}, {0.1, -0.5, 0}, {-0.1, 0.5, 0}, {0, 1.5, 0}}, 0.15, 3));
    auto& bb = dynamic_cast<model::BeamBeamInteraction&>(
        m.add_contribution(std::make_unique<model::BeamBeamInteraction>("ab", law_for(0.2, 0.15), a, b)));
    m.finalize();
    return bb;
  };
  model::Model first, second;
  auto& bb1 = build(first);
  auto& bb2 = build(second);
  Eigen::VectorXd q = Eigen::VectorXd::Constant(first.size(), 0.003);
  first.evaluate(q, 1.0, true);
  first.accept(q, 1.0);
  EXPECT_FALSE(bb1.save_state().empty());
  second.restore_state(first.save_state());  // rebuilds the pattern from the restored pairs
  q *= 2;
  first.evaluate(q, 1.0, true);
  second.evaluate(q, 1.0, true);
  EXPECT_EQ(bb1.energy(), bb2.energy());
  EXPECT_GT(bb1.interacting_points(), 0);
  EXPECT_EQ((first.residual() - second.residual()).norm(), 0.0);
  EXPECT_THROW(bb2.restore_state(std::vector<double>(3, 0.0)), InputError);
}

// End taper: fiber b ends 0.05 past the crossing, inside the taper (10 % of b's length 1.55), so the
// sections of a near the crossing fade with their closest point's distance to b's end. The tangent and the
// energy's gradient, through the taper's dependence on the moving closest point, against central
// differences; the taper lowers the energy's magnitude; far from the end the taper changes nothing.
TEST(BeamBeamInteraction, EndTaperTangentAndFading) {
  auto build = [](model::Model& m, double taper, double end_y) -> model::BeamBeamInteraction& {
    auto& a = m.add_beam(make_fiber(
        "a", {{-1.5, 0.05, 0.40}, {-0.5, -0.05, 0.37}, {0.5, 0.05, 0.37}, {1.5, -0.05, 0.40}}, 0.2, 6));
    auto& b = m.add_beam(make_fiber(
        "b", {{0.05, -1.5, 0.0}, {-0.05, -1.0, 0.02}, {0.05, -0.5, -0.02}, {0.0, end_y, 0.0}}, 0.15, 6));
    auto interaction = std::make_unique<model::BeamBeamInteraction>(
        "ab", law_for(0.2, 0.15), a, b, 0.0, std::numeric_limits<double>::quiet_NaN(), taper);
    auto& bb = dynamic_cast<model::BeamBeamInteraction&>(m.add_contribution(std::move(interaction)));
    m.finalize();
    return bb;
  };
  model::Model tapered;
  auto& bb = build(tapered, 0.1, 0.05);
  EXPECT_EQ(bb.end_taper(), 0.1);
  check_derivatives(tapered, 7, 0.01);
  EXPECT_GT(bb.interacting_points(), 4);
  EXPECT_LT((bb.force_on(0) + bb.force_on(1)).norm(), 1e-10 * bb.force_on(0).norm());
  model::Model plain, far_tapered, far_plain;
  auto& bp = build(plain, 0.0, 0.05);
  auto& bf = build(far_tapered, 0.1, 1.5);
  auto& bfp = build(far_plain, 0.0, 1.5);
  for (model::Model* m : {&tapered, &plain, &far_tapered, &far_plain})
    m->evaluate(Eigen::VectorXd::Zero(m->size()), 1.0, false);
  EXPECT_LT(bb.energy(), 0.0);
  EXPECT_GT(bb.energy(), 0.9 * bp.energy());  // faded: a smaller magnitude
  // b's end 1.5 from the crossing (length 3.0, taper length 0.3): a's sections do not reach the taper, but b's
  // own sections near its ends do not see a at all, so the energies agree.
  EXPECT_NEAR(bf.energy(), bfp.energy(), 1e-12 * std::abs(bfp.energy()));
  EXPECT_THROW(model::BeamBeamInteraction("bad", law_for(0.2, 0.15), plain.beams[0], plain.beams[1], 0.0, 0.01, 0.5),
               std::invalid_argument);
}

TEST(BeamBeamInteraction, FiberFoldedOntoItself) {
  model::Model m;
  const double z = 0.17;  // legs 0.34 apart: gap 0.04 for radius 0.15
  auto& a = m.add_beam(make_fiber("hairpin",
                                  {{2, 0, z}, {0.5, 0, z}, {-1, 0, z}, {-1.6, 0, z}, {-1.6, 0, -z}, {-1, 0, -z},
                                   {0.5, 0, -z}, {2, 0, -z}},
                                  0.15, 12));
  auto& bb = dynamic_cast<model::BeamBeamInteraction&>(
      m.add_contribution(std::make_unique<model::BeamBeamInteraction>("self", law_for(0.15, 0.15), a, a, 1.0)));
  m.finalize();
  check_derivatives(m, 5, 0.005);
  EXPECT_TRUE(bb.self());
  EXPECT_GT(bb.interacting_points(), 10);
  EXPECT_NEAR(bb.minimum_gap(), 0.04, 0.02);
  EXPECT_TRUE(bb.points(1).empty());
  // A straight fiber does not interact with itself.
  model::Model straight;
  auto& s = straight.add_beam(make_fiber("rod", {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}}, 0.15, 8));
  auto& ss = dynamic_cast<model::BeamBeamInteraction&>(straight.add_contribution(
      std::make_unique<model::BeamBeamInteraction>("self", law_for(0.15, 0.15), s, s, 0.5)));
  straight.finalize();
  straight.evaluate(Eigen::VectorXd::Zero(straight.size()), 1.0, true);
  EXPECT_EQ(ss.interacting_points(), 0);
}

}  // namespace
}  // namespace fibrane::testing
