// The contact length of the beam-beam interaction (model/beam_beam.hpp): the reference arc length of the
// first fiber whose gap to the other is below the contact gap, by the points' quadrature; its default
// contact gap from the law's equilibrium gap; the case key contact_gap and its errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <memory>

#include "case_runner.hpp"
#include "common/error.hpp"
#include "model/beam_beam.hpp"
#include "model/beam_body.hpp"
#include "model/model.hpp"
#include "spline/curve.hpp"
#include "spline/knot_vector.hpp"

namespace fibrane::testing {
namespace {

// A straight quadratic C1 fiber from `a` to `b` with `elements` elements, section radius 0.1.
model::BeamBody straight_fiber(const std::string& name, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                               int elements) {
  spline::NurbsCurve curve(spline::KnotVector(1, {0, 0, 1, 1}), {a, b});
  curve.refine(2, 1, elements);
  model::BeamBody body(name, curve, beam::BeamSection::circular(1e6, 0.3, 0.1), Eigen::Vector3d::Zero());
  body.section_radius = 0.1;
  return body;
}

std::shared_ptr<laws::SectionCylinderLaw> lj(double cutoff) {
  return std::make_shared<laws::SectionCylinderLaw>(
      laws::SectionCylinderLaw::lennard_jones(1e9, 0.01, 0.1, 0.1, 1.0, 0.0, cutoff));
}

// Two fibers at 5 degrees, crossing at z = 0.2055 (gap 0.0055 at the crossing): the gap grows along them,
// so the contact length is a part of the fiber that depends on the contact gap.
struct CrossingPair {
  model::Model m;
  model::BeamBeamInteraction* bb = nullptr;
  CrossingPair(double height, double contact_gap) {
    const double c = std::cos(5 * M_PI / 180), s = std::sin(5 * M_PI / 180);
    auto& a = m.add_beam(straight_fiber("lower", {-1, 0, 0}, {1, 0, 0}, 16));
    auto& b = m.add_beam(straight_fiber("upper", {-c, -s, height}, {c, s, height}, 16));
    bb = &dynamic_cast<model::BeamBeamInteraction&>(m.add_contribution(
        std::make_unique<model::BeamBeamInteraction>("zip", lj(0.05), a, b, 0.0, contact_gap)));
    m.finalize();
    m.evaluate(Eigen::VectorXd::Zero(m.size()), 1.0, false);
  }
};

// The definition recomputed from the per-point data: the lengths of fiber 0's points below the gap.
double recomputed(const model::BeamBeamInteraction& bb, double contact_gap) {
  double length = 0;
  for (const auto& p : bb.points(0))
    if (p.found && p.gap < contact_gap) length += p.length;
  return length;
}

TEST(BeamBeamContact, LengthIsTheArcLengthOfTheFirstFiberBelowTheContactGap) {
  for (double contact_gap : {0.008, 0.0128, 0.03}) {
    CrossingPair pair(0.2055, contact_gap);
    const auto& bb = *pair.bb;
    EXPECT_EQ(bb.contact_gap(), contact_gap);
    const auto names = bb.quantity_names();
    const auto k = std::find(names.begin(), names.end(), "contact_length") - names.begin();
    ASSERT_LT(static_cast<std::size_t>(k), names.size());
    const double length = bb.quantity(static_cast<std::size_t>(k));
    EXPECT_EQ(length, bb.contact_length());
    EXPECT_NEAR(length, recomputed(bb, contact_gap), 1e-12);
    // Geometry: the distance from the lower axis at x to the upper axis is sqrt(z^2 + (x sin 5 deg)^2), so
    // the gap is below g_contact for |x| < sqrt((2R + g_contact)^2 - z^2) / sin 5 deg (within one point's
    // length at either end of that stretch; the kernel's gap is the sections' own).
    const double reach = std::sqrt(std::pow(0.2 + contact_gap, 2) - 0.2055 * 0.2055) / std::sin(5 * M_PI / 180);
    const double expected = 2 * std::min(1.0, reach);
    EXPECT_NEAR(length, expected, 2 * 2.0 / 16) << contact_gap;
    EXPECT_GT(length, 0.0);
  }
  // The points' lengths add up to the fiber's reference length.
  CrossingPair pair(0.2055, 0.01);
  double total = 0;
  for (const auto& p : pair.bb->points(0)) total += p.length;
  EXPECT_NEAR(total, 2.0, 1e-12);
}

TEST(BeamBeamContact, LengthIsZeroForFibersFarApart) {
  CrossingPair pair(1.5, 0.03);
  EXPECT_EQ(pair.bb->contact_length(), 0.0);
  EXPECT_EQ(pair.bb->energy(), 0.0);
}

// The default contact gap is twice the law's equilibrium gap, g_0 = (5 C_12 / C_6)^(1/6) sigma for
// Lennard-Jones; a law without an equilibrium gap leaves it undefined (NaN).
TEST(BeamBeamContact, DefaultContactGapIsTwiceTheEquilibriumGap) {
  const double g0 = std::pow(5 * laws::SectionCylinderLaw::coefficient(12) / laws::SectionCylinderLaw::coefficient(6),
                             1.0 / 6) * 0.01;
  EXPECT_NEAR(lj(0.05)->equilibrium_gap(), g0, 1e-14);
  EXPECT_NEAR(lj(0.05)->raw(g0).f_g, 0.0, 1e-9 * std::abs(lj(0.05)->raw(0.5 * g0).f_g));
  CrossingPair pair(0.2055, std::numeric_limits<double>::quiet_NaN());
  EXPECT_NEAR(pair.bb->contact_gap(), 2 * g0, 1e-14);
  EXPECT_NEAR(pair.bb->contact_length(), recomputed(*pair.bb, 2 * g0), 1e-12);
  const laws::SectionCylinderLaw attractive({{6, -1.0}}, 0.1, 0.1);
  EXPECT_TRUE(std::isnan(attractive.equilibrium_gap()));
  EXPECT_TRUE(std::isnan(model::BeamBeamInteraction::default_contact_gap(attractive)));
}

std::string write_case(const std::string& name, const std::string& yaml) {
  const auto file = fresh_directory(name) / "case.yaml";
  std::ofstream(file) << yaml;
  return file.string();
}

std::string crossing_case(const std::string& interaction_keys, const std::string& steps = "{dt: 1, t_end: 1}") {
  return R"(
beams:
  - name: lower
    geometry: {line: {from: [-1, 0, 0], to: [1, 0, 0]}}
    refine: {degree: 2, continuity: 1, elements: 8}
    material: {young: 1.0e6, poisson: 0.3}
    section: {circle: {radius: 0.1}}
  - name: upper
    geometry: {line: {from: [-0.9962, -0.0872, 0.2055], to: [0.9962, 0.0872, 0.2055]}}
    refine: {degree: 2, continuity: 1, elements: 8}
    material: {young: 1.0e6, poisson: 0.3}
    section: {circle: {radius: 0.1}}
interactions:
  - {name: zip, between: [lower, upper], )" + interaction_keys + R"(}
constraints:
  - {body: lower, at: [{end: start}, {end: end}], fix: [x, y, z, twist]}
  - {body: upper, at: [{end: start}, {end: end}], fix: [x, y, z, twist]}
steps: )" + steps + "\n";
}

// The case key: contact_gap sets g_contact, the history gets <name>_contact_length (at its place after
// minimum_gap), and a stop rule may name it.
TEST(BeamBeamContact, CaseKeyAndHistoryColumn) {
  const std::string law = "law: {model: lennard_jones, epsilon: 1.0e9, sigma: 0.01, cutoff: 0.05}";
  const CaseRun r = run_yaml("beam-beam-contact-case",
                             crossing_case(law + ", contact_gap: 0.02",
                                           "{dt: 1, t_end: 1, stop: {column: zip_contact_length, "
                                           "below_fraction_of_peak: 0.001}}"));
  ASSERT_TRUE(r.summary.result.completed()) << r.summary.result.message;
  ASSERT_TRUE(r.history.count("zip_contact_length"));
  const auto& length = r.history.at("zip_contact_length");
  ASSERT_EQ(length.size(), 2u);
  // Recomputed from the table of the lower fiber's points (gap, length) at the last step.
  const auto table = read_history(r.directory / "interaction" / "zip_lower_000001.csv");
  double sum = 0;
  for (std::size_t i = 0; i < table.at("gap").size(); ++i)
    if (table.at("found")[i] > 0.5 && table.at("gap")[i] < 0.02) sum += table.at("length")[i];
  EXPECT_NEAR(length[1], sum, 1e-12);
  EXPECT_GT(length[1], 0.1);
  const auto c = casefile::read_case(write_case("beam-beam-contact-default", crossing_case(law)));
  const auto found = c.model->interactions_of<model::BeamBeamInteraction>();
  ASSERT_EQ(found.size(), 1u);
  EXPECT_NEAR(found[0]->contact_gap(), 2 * lj(0.05)->equilibrium_gap(), 1e-15);
}

TEST(BeamBeamContact, BadContactGapsAreRejectedAtTheKey) {
  const std::string law = "law: {model: lennard_jones, epsilon: 1.0e9, sigma: 0.01}";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {law + ", contact_gap: -0.01", "contact_gap"},
      {law + ", contact_gap: 0", "contact_gap"},
      {law + ", contact_gap: big", "contact_gap"},
  };
  for (const auto& [keys, expected] : cases) {
    try {
      casefile::read_case(write_case("beam-beam-contact-bad", crossing_case(keys)));
      ADD_FAILURE() << "accepted: " << keys;
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(expected), std::string::npos) << keys << "\n" << what;
      EXPECT_NE(what.find("case.yaml"), std::string::npos) << what;
    }
  }
  // A law without an equilibrium gap has a contact length only with contact_gap; without it, no column.
  const std::string power = "law: {model: inverse_power, exponent: 6, coefficient: -1}";
  const auto with_gap = casefile::read_case(write_case("beam-beam-contact-ok", crossing_case(power + ", contact_gap: 0.01")));
  const auto names = with_gap.model->interactions_of<model::BeamBeamInteraction>().at(0)->quantity_names();
  EXPECT_EQ(std::count(names.begin(), names.end(), "contact_length"), 1);
  const auto without = casefile::read_case(write_case("beam-beam-contact-none", crossing_case(power)));
  const auto* bb = without.model->interactions_of<model::BeamBeamInteraction>().at(0);
  EXPECT_TRUE(std::isnan(bb->contact_gap()));
  const auto bare = bb->quantity_names();
  EXPECT_EQ(std::count(bare.begin(), bare.end(), "contact_length"), 0);
  EXPECT_EQ(std::count(bare.begin(), bare.end(), "minimum_gap"), 1);
}

}  // namespace
}  // namespace fibrane::testing
