// The beam-beam interaction through a case file (kind beam_beam): two crossed fibers, the lower one pinned
// at its ends, the upper one's ends pressed down into the lower one and then pulled up by a prescribed
// displacement. The interaction's quantities are history columns, its point data VTK series and tables,
// its record a member of summary.json; the case reader rejects its bad keys with located errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <regex>

#include "case_runner.hpp"
#include "common/error.hpp"
#include "model/beam_beam.hpp"

namespace fibrane::testing {
namespace {

// `interaction` is the entry of `interactions`; the upper fiber's ends move by 0.02 f(t) in z with f
// going 0 -> -1 (pressed, t = 0.5) -> +1 (pulled, t = 1).
std::string crossed_fibers(const std::string& interaction =
                               "{name: cross, between: [lower, upper], law: {model: lennard_jones, epsilon: 1.0e6, "
                               "sigma: 0.01}}") {
  return R"(
beams:
  - name: lower
    geometry: {line: {from: [-1, 0, 0], to: [1, 0, 0]}}
    refine: {degree: 2, continuity: 1, elements: 8}
    material: {young: 1.0e6, poisson: 0.3}
    section: {circle: {radius: 0.1}}
  - name: upper
    geometry: {line: {from: [0, -1, 0.21], to: [0, 1, 0.21]}}
    refine: {degree: 2, continuity: 1, elements: 8}
    material: {young: 1.0e6, poisson: 0.3}
    section: {circle: {radius: 0.1}}
functions: {press_pull: {table: [[0, 0], [0.5, -1], [1, 1]]}}
interactions:
  - )" + interaction + R"(
constraints:
  - {body: lower, at: [{end: start}, {end: end}], fix: [x, y, z]}
  - {body: lower, at: {end: start}, fix: [twist]}
  - {name: ends, body: upper, at: [{end: start}, {end: end}], prescribe: {z: 0.02}, fix: [x, y], function: press_pull}
  - {body: upper, at: {end: start}, fix: [twist]}
monitors:
  - {name: reaction_z, type: reaction, constraint: ends, component: z}
steps: {dt: 0.1, dt_max: 0.1}
)";
}

TEST(BeamBeamCase, CrossedFibersPressedAndPulledReportBalancedForcesAndTheirPoints) {
  const CaseRun r = run_yaml("beam-beam-case", crossed_fibers());
  ASSERT_TRUE(r.summary.result.completed()) << r.summary.result.message;
  const auto& h = r.history;
  for (const char* column : {"cross_energy", "cross_force_lower_x", "cross_force_lower_y", "cross_force_lower_z",
                             "cross_force_upper_x", "cross_force_upper_y", "cross_force_upper_z",
                             "cross_interacting_pairs", "cross_interacting_points", "cross_minimum_gap"})
    ASSERT_TRUE(h.count(column)) << column;
  const auto& t = h.at("t");
  ASSERT_EQ(t.size(), 11u);
  const auto& fz_lower = h.at("cross_force_lower_z");
  // Pressed (t = 0.5): repulsion pushes the lower fiber down; pulled (t = 1): attraction lifts it.
  EXPECT_LT(fz_lower[5], -0.1);
  EXPECT_GT(fz_lower[10], 0.0);
  EXPECT_LT(h.at("cross_minimum_gap")[5], h.at("cross_minimum_gap")[10]);
  for (std::size_t i = 0; i < t.size(); ++i) {
    // Translation invariance: the forces on the two fibers balance to round-off (1e-10 of the force).
    const double scale = std::abs(fz_lower[i]);
    for (const char* c : {"x", "y", "z"})
      EXPECT_NEAR(h.at(std::string("cross_force_lower_") + c)[i] + h.at(std::string("cross_force_upper_") + c)[i], 0.0,
                  1e-10 * scale)
          << "step " << i << " " << c;
    // The upper fiber is in equilibrium: its held ends carry the interaction's force on it (to the
    // Newton tolerance, 1e-6 of the force).
    if (i > 0) {
      EXPECT_NEAR(h.at("reaction_z")[i] + h.at("cross_force_upper_z")[i], 0.0, 1e-6 * scale) << "step " << i;
    }
    EXPECT_GT(h.at("cross_interacting_points")[i], 0) << "step " << i;
  }

  // The tables: one per fiber and step; the energy column equals the sum of the points' energies.
  for (int step : {5, 10}) {
    double sum = 0;
    int found = 0;
    for (const char* fiber : {"lower", "upper"}) {
      const auto table = read_history(r.directory / "interaction" /
                                      (std::string("cross_") + fiber + (step == 5 ? "_000005.csv" : "_000010.csv")));
      for (const char* column : {"xi", "s", "found", "active", "gap", "distance", "energy_density", "energy",
                                 "force_per_length_x", "force_per_length_y", "force_per_length_z"})
        ASSERT_TRUE(table.count(column)) << fiber << " " << column;
      for (double e : table.at("energy")) sum += e;
      for (double f : table.at("found")) found += f > 0.5;
    }
    const double energy = h.at("cross_energy")[static_cast<std::size_t>(step)];
    EXPECT_NE(energy, 0.0);
    EXPECT_NEAR(sum, energy, 1e-12 * std::abs(energy)) << "step " << step;
    EXPECT_GT(found, 0);
  }

  // VTK: a point series per fiber with the point data.
  for (const char* fiber : {"lower", "upper"}) {
    const std::string series = std::string("cross_") + fiber;
    ASSERT_TRUE(std::filesystem::exists(r.directory / (series + ".pvd"))) << series;
    const std::string vtu = read_text(r.directory / "vtk" / (series + "_000005.vtu"));
    for (const char* field : {"gap", "energy_density", "force_per_length", "active"})
      EXPECT_NE(vtu.find(std::string("Name=\"") + field + "\""), std::string::npos) << series << " " << field;
  }

  // summary.json: the record with the smallest gap of the run (at the deepest press, step 5).
  const std::string summary = read_text(r.directory / "summary.json");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(summary, m, std::regex("\"smallest_gap\": ([^,]+),\\s*\"smallest_gap_step\": 5")))
      << summary;
  EXPECT_NEAR(std::stod(m[1]), h.at("cross_minimum_gap")[5], 1e-15);
  EXPECT_NE(summary.find("\"final_force_lower_z\""), std::string::npos);
}

// examples/crossed-fibers.yaml: arc-length continuation passes the pull-off limit point (t turns back,
// one negative eigenvalue on the unstable branch) and the second limit point, and ends with the fibers
// apart; along the whole path the upper fiber's held ends carry the interaction's force on it.
TEST(BeamBeamCase, CrossedFibersExamplePassesPullOff) {
  const CaseRun r = run_yaml("beam-beam-crossed-example", example_text("crossed-fibers.yaml"));
  ASSERT_TRUE(r.summary.result.completed()) << r.summary.result.message;
  const auto& h = r.history;
  const auto& t = h.at("t");
  const auto& f = h.at("reaction_z");
  std::size_t limits = 0, unstable = 0, turn = 0;
  for (std::size_t i = 1; i < t.size(); ++i) {
    limits += h.at("limit_point")[i] > 0.5;
    unstable += h.at("negative_eigenvalues")[i] > 0.5;
    if (turn == 0 && t[i] < t[i - 1]) turn = i;
    const double scale = std::max(1.0, std::abs(f[i]));
    EXPECT_NEAR(f[i] + h.at("cross_force_upper_z")[i], 0.0, 1e-6 * scale) << "step " << i;
    EXPECT_NEAR(h.at("cross_force_lower_z")[i] + h.at("cross_force_upper_z")[i], 0.0, 1e-10 * scale) << "step " << i;
  }
  EXPECT_EQ(limits, 2u);
  EXPECT_GT(unstable, 0u);
  ASSERT_GT(turn, 1u) << "t never turns back: no pull-off limit point";
  // The pull-off force is the largest force of the path, at the limit point.
  const auto peak = std::max_element(f.begin(), f.end()) - f.begin();
  EXPECT_LE(std::abs(static_cast<long>(peak) - static_cast<long>(turn - 1)), 1);
  EXPECT_GT(f[static_cast<std::size_t>(peak)], 0.0);
  // At the end the fibers are apart, beyond the cut-off.
  EXPECT_EQ(h.at("cross_energy").back(), 0.0);
  EXPECT_EQ(h.at("cross_interacting_points").back(), 0.0);
  EXPECT_NEAR(t.back(), 0.3, 1e-12);
}

// beam_beam is the default kind for two beams, and the entry's law becomes the interaction's.
TEST(BeamBeamCase, TheDefaultKindForTwoBeamsIsBeamBeam) {
  const auto dir = fresh_directory("beam-beam-default");
  std::ofstream(dir / "case.yaml") << crossed_fibers(
      "{between: [upper, lower], contact_gap: 0.01, law: {model: inverse_power, exponent: 6, coefficient: -1, "
      "cutoff: 0.05}}");
  const auto c = casefile::read_case((dir / "case.yaml").string());
  const auto found = c.model->interactions_of<model::BeamBeamInteraction>();
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0]->name(), "upper_lower");
  EXPECT_EQ(found[0]->bodies(), std::make_pair(std::string("upper"), std::string("lower")));
  EXPECT_FALSE(found[0]->self());
  EXPECT_EQ(found[0]->end_taper(), 0.0);
  std::ofstream(dir / "case.yaml") << crossed_fibers(
      "{between: [upper, lower], end_taper: 0.02, law: {model: lennard_jones, epsilon: 1, sigma: 0.01}}");
  EXPECT_EQ(casefile::read_case((dir / "case.yaml").string()).model->interactions_of<model::BeamBeamInteraction>()
                .at(0)->end_taper(), 0.02);
}

// A fiber with itself needs `exclusion`; two fibers take none; the law is a section law with its keys.
TEST(BeamBeamCase, BadEntriesAreRejectedAtTheirKeys) {
  const auto dir = fresh_directory("beam-beam-bad");
  const std::string law = "law: {model: lennard_jones, epsilon: 1, sigma: 0.01}";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"{between: [lower, lower], " + law + "}", "needs 'exclusion'"},
      {"{between: [lower, upper], exclusion: 0.5, " + law + "}", "'exclusion' applies to a beam interacting with itself"},
      {"{between: [lower, upper], law: {model: disk_plate, epsilon: 1}}", "one of lennard_jones"},
      {"{between: [lower, upper], law: {model: lennard_jones, epsilon: 1, sigma: 0.01, depth: 2}}", "depth"},
      {"{between: [lower, upper]}", "law"},
      {"{between: [lower, lower], exclusion: -1, " + law + "}", "exclusion"},
      {"{between: [lower, upper], end_taper: 0.5, " + law + "}", "end_taper"},
      {"{between: [lower, upper], end_taper: -0.1, " + law + "}", "end_taper"},
  };
  for (const auto& [entry, expected] : cases) {
    std::ofstream(dir / "case.yaml") << crossed_fibers(entry);
    try {
      casefile::read_case((dir / "case.yaml").string());
      ADD_FAILURE() << "accepted: " << entry;
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(expected), std::string::npos) << entry << "\n" << what;
      EXPECT_NE(what.find("case.yaml"), std::string::npos) << what;
    }
  }
}

// A fiber with itself (kind beam_beam, exclusion): one series named like the interaction, no force columns.
TEST(BeamBeamCase, SelfInteractionHasOneSeriesAndNoForceColumns) {
  const auto dir = fresh_directory("beam-beam-self");
  std::ofstream(dir / "case.yaml") << crossed_fibers(
      "{name: fold, between: [upper, upper], exclusion: 0.5, law: {model: lennard_jones, epsilon: 1, sigma: 0.01}}");
  const auto c = casefile::read_case((dir / "case.yaml").string());
  const auto& i = *c.model->interactions().at(0);
  EXPECT_EQ(i.quantity_names(),
            (std::vector<std::string>{"energy", "interacting_pairs", "interacting_points", "minimum_gap",
                                      "contact_length"}));
  ASSERT_EQ(i.point_series().size(), 1u);
  EXPECT_EQ(i.point_series()[0].name, "fold");
}

}  // namespace
}  // namespace fibrane::testing
