// An interaction kind that fibrane does not ship, added the way an extension adds one: a class deriving
// from model::Interaction and one registration in casefile::interaction_kinds(), then named in a case
// file. Nothing of output/ or of the stop rules knows it, yet its quantity is a history column and a stop
// rule's column, its record and summary section are in summary.json, and its point data are in the VTK
// series and the interaction tables.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>

#include "case/case_interactions.hpp"
#include "case_runner.hpp"
#include "common/error.hpp"
#include "linalg/dof_map.hpp"
#include "model/beam_body.hpp"
#include "model/observables.hpp"

namespace fibrane::testing {
namespace {

// A linear spring of stiffness k between the end of beam a and the start of beam b (their end control
// points): energy k |u_b - u_a|^2 / 2 in the relative displacement of the two points.
class EndSpring final : public model::Interaction {
 public:
  EndSpring(std::string name, const model::BeamBody& a, const model::BeamBody& b, double k)
      : name_(std::move(name)), a_(a), b_(b), k_(k) {}
  std::string name() const override { return name_; }
  std::vector<std::vector<int>> element_dofs(const solve::DofMap& dofs) const override {
    std::vector<int> d;
    for (int c = 0; c < 3; ++c) d.push_back(dofs.dof(a_.block, cp_a(), c));
    for (int c = 0; c < 3; ++c) d.push_back(dofs.dof(b_.block, 0, c));
    return {d};
  }
  double evaluate(const model::State& s, model::ElementSink& sink, model::Status&) override {
    Eigen::Vector3d ua, ub;
    for (int c = 0; c < 3; ++c) {
      ua[c] = s.u[s.dofs.dof(a_.block, cp_a(), c)];
      ub[c] = s.u[s.dofs.dof(b_.block, 0, c)];
    }
    delta_ = ub - ua;
    position_a_ = a_.curve.control_points()[static_cast<std::size_t>(cp_a())] + ua;
    position_b_ = b_.curve.control_points()[0] + ub;
    Eigen::VectorXd r(6);
    r << -k_ * delta_, k_ * delta_;
    Eigen::MatrixXd k = Eigen::MatrixXd::Zero(6, 6);
    k.topLeftCorner(3, 3) = k.bottomRightCorner(3, 3) = k_ * Eigen::Matrix3d::Identity();
    k.topRightCorner(3, 3) = k.bottomLeftCorner(3, 3) = -k_ * Eigen::Matrix3d::Identity();
    if (sink.owns(0)) sink.add(0, r, sink.with_tangent() ? &k : nullptr);
    return energy();
  }

  std::pair<std::string, std::string> bodies() const override { return {a_.name(), b_.name()}; }
  std::vector<std::string> quantity_names() const override { return {"energy", "extension"}; }
  double quantity(std::size_t q) const override { return q == 0 ? energy() : delta_.norm(); }
  // One series per body, with the force the spring exerts on that body at its attachment point.
  std::vector<model::PointSeries> point_series() const override {
    return {{name_ + "_" + a_.name(), a_.name(), true}, {name_ + "_" + b_.name(), b_.name(), false}};
  }
  model::PointCloud point_cloud(std::size_t series) const override {
    const Eigen::Vector3d f = (series == 0 ? k_ : -k_) * delta_;
    return {{series == 0 ? position_a_ : position_b_}, {{"spring_force", 3, {f.x(), f.y(), f.z()}}}};
  }
  model::PointTable point_table(std::size_t) const override {
    return {{{"tension", {k_ * delta_.norm()}, {}}, {"state", {}, {delta_.norm() > 0 ? "stretched" : "slack"}}}};
  }
  std::vector<model::SummaryField> summary_sections() const override {
    return {{"test_spring_stiffness", k_}};
  }

 private:
  int cp_a() const { return a_.num_control_points() - 1; }
  double energy() const { return 0.5 * k_ * delta_.squaredNorm(); }
  std::string name_;
  const model::BeamBody &a_, &b_;
  double k_;
  Eigen::Vector3d delta_ = Eigen::Vector3d::Zero(), position_a_ = Eigen::Vector3d::Zero(),
                  position_b_ = Eigen::Vector3d::Zero();
};

void register_end_spring() {
  auto& kinds = casefile::interaction_kinds();
  if (kinds.find("test_end_spring")) return;
  kinds.add({"test_end_spring", "a linear spring between two beam ends (test)", {}, {"test_spring_stiffness"},
             [](const casefile::InteractionRequest& r) -> std::unique_ptr<model::Interaction> {
               if (!r.a.beam) r.a.at.fail("a beam");
               if (!r.b.beam) r.b.at.fail("a beam");
               return std::make_unique<EndSpring>(r.name, *r.a.beam, *r.b.beam, r.entry["stiffness"].positive());
             }});
}

// Two collinear beams, `left` clamped at its start, `right` held only across its axis and pulled along
// it at its end by F(t) = 2 f(t); the spring between left's end and right's start carries F.
std::string two_beams(const std::string& interaction, const std::string& load_keys = "",
                      const std::string& steps = "{dt: 0.25, dt_max: 0.25}") {
  return R"(
beams:
  - name: left
    geometry: {line: {from: [0, 0, 0], to: [1, 0, 0]}}
    refine: {degree: 2, continuity: 1, elements: 2}
    material: {young: 1000, poisson: 0.3}
    section: {circle: {radius: 0.05}}
  - name: right
    geometry: {line: {from: [1.5, 0, 0], to: [2.5, 0, 0]}}
    refine: {degree: 2, continuity: 1, elements: 2}
    material: {young: 1000, poisson: 0.3}
    section: {circle: {radius: 0.05}}
interactions:
  - )" + interaction + R"(
constraints:
  - {body: left, at: {end: start}, clamp: true}
  - {body: left, at: {end: start}, fix: [x, y, z, twist]}
  - {body: right, at: [{end: start}, {end: end}], fix: [y, z]}
  - {body: right, at: {end: start}, fix: [twist]}
loads:
  - {body: right, type: point_force, at: {end: end}, force: [2, 0, 0])" + load_keys + R"(}
steps: )" + steps + "\n";
}

std::string text_of(const std::filesystem::path& p) { return read_text(p); }

TEST(InteractionExtension, ANewKindThroughTheRegistryReachesHistorySummaryAndVtk) {
  register_end_spring();
  const double k = 40.0;
  const CaseRun r = run_yaml("interaction-extension",
                             two_beams("{name: spring, between: [left, right], kind: test_end_spring, stiffness: 40}"));
  ASSERT_TRUE(r.summary.result.completed()) << r.summary.result.message;
  // Equilibrium of `right` along x: the spring's tension k |delta| equals the pull F = 2 t.
  const auto& t = r.history.at("t");
  const auto& extension = r.history.at("spring_extension");
  const auto& energy = r.history.at("spring_energy");
  ASSERT_EQ(t.size(), 5u);
  for (std::size_t i = 0; i < t.size(); ++i) {
    EXPECT_NEAR(extension[i], 2.0 * t[i] / k, 1e-9) << "step " << i;
    EXPECT_NEAR(energy[i], 0.5 * k * extension[i] * extension[i], 1e-12) << "step " << i;
  }
  // The interaction energy counts as such in the model.
  EXPECT_NEAR(r.c.model->energy(model::EnergyKind::interaction), energy.back(), 1e-15);

  // summary.json: the default record (final_<quantity>) and the kind's own section.
  const std::string summary = text_of(r.directory / "summary.json");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(summary, m, std::regex("\"spring\": \\{\\s*\"final_energy\": ([^,]+),\\s*"
                                                       "\"final_extension\": ([^\\s,}]+)")))
      << summary;
  EXPECT_NEAR(std::stod(m[1]), energy.back(), 1e-12);
  EXPECT_NEAR(std::stod(m[2]), 2.0 / k, 1e-9);
  EXPECT_TRUE(std::regex_search(summary, std::regex("\"test_spring_stiffness\": \\{\\s*\"spring\": 40")))
      << summary;

  // VTK: a series per body with the spring's force on it at the current attachment point.
  for (const char* body : {"left", "right"}) {
    const std::string series = std::string("spring_") + body;
    ASSERT_TRUE(std::filesystem::exists(r.directory / (series + ".pvd"))) << series;
    const std::string vtu = text_of(r.directory / "vtk" / (series + "_000004.vtu"));
    EXPECT_NE(vtu.find("Name=\"spring_force\""), std::string::npos) << series;
  }
  // The table of the series that has one: interaction/spring_left_<step>.csv.
  const std::string table = text_of(r.directory / "interaction" / "spring_left_000004.csv");
  ASSERT_TRUE(std::regex_match(table, m, std::regex("tension,state\n([^,]+),stretched\n"))) << table;
  EXPECT_NEAR(std::stod(m[1]), 2.0, 1e-9);
  EXPECT_FALSE(std::filesystem::exists(r.directory / "interaction" / "spring_right_000004.csv"));
}

TEST(InteractionExtension, AStopRuleNamesTheNewKindsQuantity) {
  register_end_spring();
  // The pull rises to 2 at t = 0.5 and falls back to 0 at t = 1; the run stops once the spring's energy is
  // below 0.3 of its peak, i.e. once the pull is below sqrt(0.3) = 0.55 of its peak: at t = 0.75 (0.5 of
  // the peak; at t = 0.625 it is 0.75).
  const CaseRun r = run_yaml(
      "interaction-extension-stop",
      "functions: {up_down: {table: [[0, 0], [0.5, 1], [1, 0]]}}\n" +
          two_beams("{name: spring, between: [left, right], kind: test_end_spring, stiffness: 40}",
                    ", function: up_down",
                    "{dt: 0.125, dt_max: 0.125, stop: {column: spring_energy, below_fraction_of_peak: 0.3}}"));
  const auto& t = r.history.at("t");
  const auto& energy = r.history.at("spring_energy");
  const double peak = *std::max_element(energy.begin(), energy.end());
  EXPECT_NEAR(t.back(), 0.75, 1e-12);
  EXPECT_LT(energy.back(), 0.3 * peak);
  EXPECT_GE(energy[energy.size() - 2], 0.3 * peak);
}

// The beam-shell form and the between form (bodies in either order) build the same SBS coupling.
TEST(InteractionExtension, TheBetweenFormBuildsTheBeamShellCoupling) {
  const auto dir = fresh_directory("interaction-between-form");
  const std::string beam_shell = beam_over_panel_case(", formulation: FF");
  std::string between = beam_shell;
  between.replace(between.find("beam: fiber, shell: panel"), 25, "between: [panel, fiber], kind: sbs");
  Eigen::VectorXd residual[2];
  std::vector<std::string> names[2];
  for (int k = 0; k < 2; ++k) {
    std::ofstream(dir / "case.yaml") << (k == 0 ? beam_shell : between);
    const auto c = casefile::read_case((dir / "case.yaml").string());
    const Eigen::VectorXd q = Eigen::VectorXd::LinSpaced(c.model->size(), 0.0, 0.01);
    c.model->evaluate(q, 1.0, false);
    residual[k] = c.model->residual();
    for (const auto& o : model::observables(*c.model)) names[k].push_back(o.name);
    ASSERT_EQ(c.model->interactions().size(), 1u);
    EXPECT_EQ(c.model->interactions()[0]->bodies(), std::make_pair(std::string("fiber"), std::string("panel")));
  }
  EXPECT_GT(residual[0].norm(), 0.0);
  EXPECT_EQ(residual[0], residual[1]);
  EXPECT_EQ(names[0], (std::vector<std::string>{"strain_energy", "fiber_panel_energy", "fiber_panel_force_x",
                                                "fiber_panel_force_y", "fiber_panel_force_z",
                                                "fiber_panel_lost_points"}));
  EXPECT_EQ(names[1][1], "panel_fiber_energy");  // the default name follows the entry's order
}

// The error of reading `yaml` as a case file.
std::string read_error(const std::string& name, const std::string& yaml) {
  const auto dir = fresh_directory(name);
  std::ofstream(dir / "case.yaml") << yaml;
  try {
    casefile::read_case((dir / "case.yaml").string());
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(InteractionExtension, UnknownKindsAndBodiesAreLocatedErrors) {
  register_end_spring();
  std::string e = read_error("interaction-unknown-kind", two_beams("{between: [left, right], kind: spiral}"));
  EXPECT_NE(e.find("case.yaml:14: interactions[0].kind: expected one of sbs, "), std::string::npos) << e;
  EXPECT_NE(e.find("test_end_spring"), std::string::npos) << e;
  e = read_error("interaction-unknown-body", two_beams("{between: [left, middle], kind: test_end_spring, stiffness: 1}"));
  EXPECT_NE(e.find("case.yaml:14: interactions[0].between[1]: expected the name of a body defined in this case "
                   "(left, right)"),
            std::string::npos)
      << e;
  std::string shell_shell = beam_over_panel_case("");
  shell_shell.replace(shell_shell.find("beam: fiber, shell: panel"), 25, "between: [panel, panel]");
  e = read_error("interaction-no-default", shell_shell);
  EXPECT_NE(e.find("interactions[0].between"), std::string::npos) << e;
  EXPECT_NE(e.find("no interaction kind is the default for a shell and a shell"), std::string::npos) << e;
  e = read_error("interaction-unknown-key",
                 two_beams("{between: [left, right], kind: test_end_spring, stiffness: 1, stifness: 2}"));
  EXPECT_NE(e.find("interactions[0]"), std::string::npos) << e;
  EXPECT_NE(e.find("stifness"), std::string::npos) << e;
}

}  // namespace
}  // namespace fibrane::testing
