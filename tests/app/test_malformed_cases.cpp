// Bad input must give a clear message naming file, line, key and expectation, exit code 2, and leave no
// output behind. Each row edits a valid case in one place.
#include <gtest/gtest.h>

#include <fstream>

#include "cli_util.hpp"
#include "temp_directory.hpp"

namespace fibrane::testing {
namespace {

const char* const valid_case = R"(shells:
  - name: plate
    geometry:
      rectangle: {origin: [0, 0, 0], edge_u: [1, 0, 0], edge_v: [0, 1, 0]}
    refine: {degree: 2, continuity: 1, elements: [2, 2]}
    thickness: 0.1
    material: {young: 1000, poisson: 0.3}
constraints:
  - {body: plate, at: {edge: u0}, fix: [x, y, z]}
  - {body: plate, at: {edge: u0}, clamp: true}
loads:
  - {body: plate, type: pressure, value: 1}
monitors:
  - {name: w, type: displacement, body: plate, at: {corner: [1, 1]}, component: z}
steps: {dt: 0.5}
)";

struct Malformed {
  const char* name;
  const char* from;
  const char* to;
  const char* message;  // must appear in the output
};

const Malformed cases[] = {
    {"missing_key", "    thickness: 0.1\n", "", ":2: shells[0]: missing required key 'thickness'"},
    {"misspelt_key", "thickness:", "thicknes:", "missing required key 'thickness' (found 'thicknes': a typo?)"},
    {"unknown_key", "steps: {dt: 0.5}", "steps: {dt: 0.5, dtt: 3}", ":15: steps: unknown key 'dtt'"},
    {"wrong_type", "thickness: 0.1", "thickness: abc", ":6: shells[0].thickness: expected a number, got 'abc'"},
    {"zero_thickness", "thickness: 0.1", "thickness: 0", "shells[0].thickness: expected a positive number, got 0"},
    {"poisson_too_large", "poisson: 0.3", "poisson: 0.7",
     "shells[0].material.poisson: expected a number in (-1, 0.5), got 0.7"},
    {"poisson_too_small", "poisson: 0.3", "poisson: -1", "expected a number in (-1, 0.5), got -1"},
    {"negative_young", "young: 1000", "young: -5", "shells[0].material.young: expected a positive number, got -5"},
    {"bad_edge", "edge: u0", "edge: u5", "constraints[0].at.edge: expected one of 'u0', 'u1', 'v0', 'v1', got 'u5'"},
    {"unknown_body", "body: plate, at: {edge", "body: plat, at: {edge",
     "constraints[0].body: expected the name of a shell or beam defined in this case, got 'plat'"},
    {"bad_component", "fix: [x, y, z]", "fix: [x, w]", "constraints[0].fix[1]: expected one of 'x', 'y', 'z', got 'w'"},
    {"unknown_function", "value: 1}", "value: 1, function: slow}",
     "loads[0].function: expected the name of a load function (ramp), got 'slow'"},
    {"continuity_too_high", "continuity: 1", "continuity: 2", "shells[0].refine.continuity: expected an inter-element"},
    {"dt_min_above_dt", "steps: {dt: 0.5}", "steps: {dt: 0.5, dt_min: 1}", "steps.dt_min: expected dt_min <= dt"},
    {"reuse_out_of_range", "steps: {dt: 0.5}", "steps: {dt: 0.5, reuse_factorization: 1}",
     "steps.reuse_factorization: expected a number in [0, 1), got 1"},
    {"stall_negative", "steps: {dt: 0.5}", "steps: {dt: 0.5, stall_iterations: -1}",
     "steps.stall_iterations: expected the most Newton updates without halving |r| (0: no limit), an integer in [0, 1000]"},
    {"reuse_first_without_reuse", "steps: {dt: 0.5}", "steps: {dt: 0.5, reuse_first_factorization: true}",
     "steps.reuse_first_factorization: needs reuse_factorization > 0"},
    {"short_step_reuse_without_reuse", "steps: {dt: 0.5}", "steps: {dt: 0.5, reuse_in_short_steps: 0.25}",
     "steps.reuse_in_short_steps: needs reuse_factorization > 0"},
    {"short_step_reuse_out_of_range", "steps: {dt: 0.5}",
     "steps: {dt: 0.5, reuse_factorization: 0.1, reuse_in_short_steps: 1.5}",
     "steps.reuse_in_short_steps: expected a number in [0, 1], got 1.5"},
    {"short_step_reuse_for_arc_length", "steps: {dt: 0.5}",
     "steps: {dt: 0.5, method: arc_length, reuse_factorization: 0.1, reuse_in_short_steps: 0.25}",
     "steps.reuse_in_short_steps: applies to method: load_stepping"},
    {"unknown_predictor", "steps: {dt: 0.5}", "steps: {dt: 0.5, predictor: quartic}",
     "steps.predictor: expected one of 'secant', 'quadratic', 'cubic', got 'quartic'"},
    {"predictor_for_arc_length", "steps: {dt: 0.5}", "steps: {dt: 0.5, method: arc_length, predictor: quadratic}",
     "steps.predictor: applies to method: load_stepping"},
    {"local_update_for_arc_length", "steps: {dt: 0.5}",
     "steps: {dt: 0.5, method: arc_length, local_first_update: 0.1}",
     "steps.local_first_update: applies to method: load_stepping"},
    {"local_newton_for_arc_length", "steps: {dt: 0.5}", "steps: {dt: 0.5, method: arc_length, local_newton: 4}",
     "steps.local_newton: applies to method: load_stepping"},
    {"local_newton_negative", "steps: {dt: 0.5}", "steps: {dt: 0.5, local_newton: -1}",
     "steps.local_newton: expected the most updates of a local Newton solve (0: none), an integer in [0, 20]"},
    {"event_tolerance_for_arc_length", "steps: {dt: 0.5}",
     "steps: {dt: 0.5, method: arc_length, event_tolerance: 1.0e-3}",
     "steps.event_tolerance: applies to method: load_stepping"},
    {"event_tolerance_negative", "steps: {dt: 0.5}", "steps: {dt: 0.5, event_tolerance: -1}",
     "steps.event_tolerance: expected a non-negative number, got -1"},
    {"local_update_out_of_range", "steps: {dt: 0.5}", "steps: {dt: 0.5, local_first_update: 0.5}",
     "steps.local_first_update: expected a number in [0, 0.5), got 0.5"},
    {"predictor_without_extrapolation", "steps: {dt: 0.5}", "steps: {dt: 0.5, extrapolate: false, predictor: secant}",
     "steps.predictor: a predictor needs extrapolate: true"},
    {"out_of_core_with_cholmod", "steps: {dt: 0.5}", "steps: {dt: 0.5, solver: cholmod, out_of_core: true}",
     "steps.out_of_core: single-precision, low-rank and out-of-core factorisations are MUMPS's: they need solver "
     "auto, mumps or mumps-lu, not cholmod"},
    {"out_of_core_when_needed_with_cholmod", "steps: {dt: 0.5}", "steps: {dt: 0.5, solver: cholmod, out_of_core: when_needed}",
     "steps.out_of_core: single-precision, low-rank and out-of-core factorisations are MUMPS's: they need solver "
     "auto, mumps or mumps-lu, not cholmod"},
    {"out_of_core_when_unknown", "steps: {dt: 0.5}", "steps: {dt: 0.5, out_of_core: {when: sometimes}}",
     "steps.out_of_core.when: expected one of 'always', 'needed', got 'sometimes'"},
    {"split_with_mumps", "steps: {dt: 0.5}", "steps: {dt: 0.5, solver: mumps, split: true}",
     "steps.split: split is CHOLMOD's Cholesky in two halves: it needs solver auto or cholmod, not mumps"},
    {"split_with_single_precision", "steps: {dt: 0.5}", "steps: {dt: 0.5, split: true, precision: single}",
     "steps.split: split is CHOLMOD's Cholesky in two halves; single-precision, low-rank and out-of-core "
     "factorisations are MUMPS's"},
    {"out_of_core_missing_directory", "steps: {dt: 0.5}", "steps: {dt: 0.5, out_of_core: /nonexistent/factor-files}",
     "steps.out_of_core: the directory '/nonexistent/factor-files' for the out-of-core factor files does not exist"},
    {"vector_of_two", "origin: [0, 0, 0]", "origin: [0, 0]",
     "geometry.rectangle.origin: expected a sequence of 3 numbers [x, y, z], got a sequence of 2"},
    {"syntax_error", "steps: {dt: 0.5}", "steps: {dt: 0.5", "YAML syntax error"},
    {"knots_decrease", "      rectangle: {origin: [0, 0, 0], edge_u: [1, 0, 0], edge_v: [0, 1, 0]}",
     "      nurbs: {degrees: [1, 1], knots_u: [0, 0, 1, 0.5, 1, 1], knots_v: [0, 0, 1, 1],\n"
     "              control_points: [[0,0,0],[0.5,0,0],[1,0,0],[1,0,0],[0,1,0],[0.5,1,0],[1,1,0],[1,1,0]]}",
     "geometry.nurbs.knots_u: invalid knot vector for degree 1: KnotVector: knots decrease at index 3"},
    {"control_point_count", "      rectangle: {origin: [0, 0, 0], edge_u: [1, 0, 0], edge_v: [0, 1, 0]}",
     "      nurbs: {degrees: [1, 1], knots_u: [0, 0, 1, 1], knots_v: [0, 0, 1, 1],\n"
     "              control_points: [[0,0,0],[1,0,0],[0,1,0]]}",
     "geometry.nurbs.control_points: expected 4 control points (2 x 2, u fastest), got 3"},
    {"weight_count", "      rectangle: {origin: [0, 0, 0], edge_u: [1, 0, 0], edge_v: [0, 1, 0]}",
     "      nurbs: {degrees: [1, 1], knots_u: [0, 0, 1, 1], knots_v: [0, 0, 1, 1],\n"
     "              control_points: [[0,0,0],[1,0,0],[0,1,0],[1,1,0]], weights: [1, 1, 1]}",
     "geometry.nurbs.weights: expected 4 weights (one per control point), got 3 values"},
    {"point_outside_domain", "at: {corner: [1, 1]}", "at: {point: [1.5, 0.5]}",
     "monitors[0].at.point: expected [u, v] inside the parameter domain of shell 'plate'"},
    {"conflicting_constraints", "constraints:\n", "constraints:\n  - {body: plate, at: {edge: u0}, prescribe: {z: 1}}\n",
     "conflicting constraints"},
    {"load_type_for_beams", "type: pressure, value: 1", "type: point_moment, moment: [0, 0, 1], at: {end: start}",
     "loads[0].type: expected a load type for shells"},
};

void PrintTo(const Malformed& m, std::ostream* os) { *os << m.name; }

class MalformedCase : public ::testing::TestWithParam<Malformed> {};

TEST_P(MalformedCase, ClearMessageExitCodeTwoNoOutput) {
  if (fibrane_binary().empty()) GTEST_SKIP() << "FIBRANE_BIN not set (run through ctest)";
  const Malformed& m = GetParam();
  std::string text = valid_case;
  const auto at = text.find(m.from);
  ASSERT_NE(at, std::string::npos) << m.from;
  text.replace(at, std::string(m.from).size(), m.to);
  const auto dir = fresh_directory(std::string("bad-") + m.name);
  const auto file = dir / "case.yaml";
  std::ofstream(file) << text;
  const auto out = dir / "out";
  const auto r = run_cli("run '" + file.string() + "' -q -o '" + out.string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(m.message), std::string::npos) << "output was: " << r.output;
  EXPECT_NE(r.output.find(file.string()), std::string::npos) << "the message must name the file: " << r.output;
  EXPECT_FALSE(std::filesystem::exists(out)) << "no output may be written for bad input";
}

INSTANTIATE_TEST_SUITE_P(Cases, MalformedCase, ::testing::ValuesIn(cases),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(Cli, ValidCaseRunsAndMissingFileIsInputError) {
  if (fibrane_binary().empty()) GTEST_SKIP();
  const auto dir = fresh_directory("good");
  std::ofstream(dir / "case.yaml") << valid_case;
  const auto ok = run_cli("run '" + (dir / "case.yaml").string() + "' -q -o '" + (dir / "out").string() + "'");
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "out" / "history.csv"));
  const auto missing = run_cli("run '" + (dir / "nope.yaml").string() + "'");
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.output.find("nope.yaml: cannot open"), std::string::npos) << missing.output;
  const auto usage = run_cli("run");
  EXPECT_EQ(usage.exit_code, 2);
  const auto version = run_cli("--version");
  EXPECT_EQ(version.exit_code, 0);
  EXPECT_NE(version.output.find("fibrane "), std::string::npos);
}

}  // namespace
}  // namespace fibrane::testing
