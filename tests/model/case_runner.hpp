#pragma once
// Test helpers: run a case (an example file, optionally edited, or YAML text) in a fresh temporary
// directory through the library, and read its history.csv back as columns.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "case/case_reader.hpp"
#include "run/run.hpp"
#include "temp_directory.hpp"

namespace fibrane::testing {

inline std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The text of examples/<name>, with each (from, to) replacement applied once (it must occur).
inline std::string example_text(const std::string& name,
                                const std::vector<std::pair<std::string, std::string>>& edits = {}) {
  std::string text = read_text(std::filesystem::path(FIBRANE_SOURCE_DIR) / "examples" / name);
  for (const auto& [from, to] : edits) {
    const auto at = text.find(from);
    if (at == std::string::npos) throw std::runtime_error("edit target not found: " + from);
    text.replace(at, from.size(), to);
  }
  return text;
}

using History = std::map<std::string, std::vector<double>>;

inline History read_history(const std::filesystem::path& csv) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  std::stringstream header(line);
  for (std::string name; std::getline(header, name, ',');) names.push_back(name);
  History h;
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::size_t k = 0;
    for (std::string v; std::getline(row, v, ','); ++k) h[names.at(k)].push_back(std::stod(v));
  }
  return h;
}

// Every column of `b` equals `a`'s within tolerance(name, scale), scale being the column's largest magnitude
// in `a`; the columns that depend on how the solves went (iterations, residual, negative_eigenvalues) are
// left out. For comparing two solver paths to the same converged steps.
inline void expect_same_columns(const History& a, const History& b,
                                const std::function<double(const std::string&, double)>& tolerance) {
  ASSERT_EQ(a.at("t").size(), b.at("t").size()) << "steps";
  for (const auto& [name, column] : a) {
    if (name == "iterations" || name == "residual" || name == "negative_eigenvalues") continue;
    double scale = 0, worst = 0;
    for (std::size_t i = 0; i < column.size(); ++i) {
      scale = std::max(scale, std::abs(column[i]));
      worst = std::max(worst, std::abs(column[i] - b.at(name)[i]));
    }
    EXPECT_LE(worst, tolerance(name, scale)) << name;
  }
}

struct CaseRun {
  casefile::Case c;
  run::RunSummary summary;
  History history;
  std::filesystem::path directory;
};

// YAML text read as a case named `name`, from a file written in `dir`.
inline casefile::Case read_yaml_in(const std::filesystem::path& dir, const std::string& name, const std::string& yaml) {
  const auto file = dir / (name + ".yaml");
  std::ofstream(file) << yaml;
  return casefile::read_case(file.string());
}

// The same in a fresh temporary directory.
inline casefile::Case read_yaml(const std::string& name, const std::string& yaml) {
  return read_yaml_in(fresh_directory(name), name, yaml);
}

// n unknowns drawn uniformly from [-amplitude, amplitude]: a deformed state for the tangent tests.
inline Eigen::VectorXd random_unknowns(int n, unsigned seed, double amplitude = 0.05) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  Eigen::VectorXd q(n);
  for (int i = 0; i < n; ++i) q[i] = u(rng);
  return q;
}

// Runs YAML text as a case named `name` (quiet, in a fresh temporary directory).
inline CaseRun run_yaml(const std::string& name, const std::string& yaml, int threads = 0) {
  const auto dir = fresh_directory(name);
  CaseRun r{read_yaml_in(dir, name, yaml), {}, {}, dir / "out"};
  run::RunOptions opt;
  opt.output_directory = r.directory.string();
  opt.quiet = true;
  opt.threads = threads;
  r.summary = run::run_case(r.c, opt);
  r.history = read_history(r.directory / "history.csv");
  return r;
}

// A straight beam a little above a cylindrical panel (clamped at one edge), whose quadrature points
// project across several panel elements: the coupled tangent tests. `interaction_keys` is appended to
// the interaction's map (e.g. ", formulation: FF").
inline std::string beam_over_panel_case(const std::string& interaction_keys, const std::string& law_keys = "") {
  return R"(
shells:
  - name: panel
    geometry: {cylinder: {radius: 3, length: 2, angles: [60, 120]}}
    refine: {degree: 3, continuity: 2, elements: [4, 3]}
    thickness: 0.5
    material: {young: 1000, poisson: 0.3}
beams:
  - name: fiber
    geometry: {line: {from: [0.2, 0.1, 3.86], to: [1.8, -0.2, 3.9]}}
    refine: {degree: 3, continuity: 2, elements: 4}
    material: {young: 1000, poisson: 0.3}
    section: {circle: {radius: 0.5}}
interactions:
  - {beam: fiber, shell: panel, lennard_jones: {epsilon: 50, sigma: 0.05)" + law_keys + R"(})" + interaction_keys + R"(}
constraints:
  - {body: panel, at: {edge: v0}, fix: [x, y, z]}
  - {body: panel, at: {edge: v0}, clamp: true}
  - {body: fiber, at: {end: start}, fix: [twist]}
)";
}

// Central differences of the model's reduced residual: column j is (r(q + h e_j) - r(q - h e_j)) / 2h.
inline Eigen::MatrixXd finite_difference_tangent(model::Model& m, const Eigen::VectorXd& q, double t, double h) {
  Eigen::MatrixXd k(m.size(), m.size());
  for (int j = 0; j < q.size(); ++j) {
    Eigen::VectorXd qp = q, qm = q;
    qp[j] += h;
    qm[j] -= h;
    m.evaluate(qp, t, false);
    const Eigen::VectorXd rp = m.residual();
    m.evaluate(qm, t, false);
    k.col(j) = (rp - m.residual()) / (2.0 * h);
  }
  return k;
}

// The coupling's part of the reduced tangent of beam_over_panel_case(interaction_keys) at a random state
// (entries of q uniform in +-0.01), against central differences (h = 1e-7) of the coupling's part of the
// residual. The coupling is tiny next to the shell at the case's strength (entries ~1e-3 against ~2e4), so
// a tolerance relative to the whole tangent could not see an error in it: it is isolated as the difference
// of two models with interaction strengths 1e4 and 2e4 (nothing else depends on the strength), entries
// ~10. `prepare` runs on each model before the tangent is taken (e.g. to switch points to the soft
// minimum). Returns max |error| / max |entry| of the coupling's part.
inline double coupling_tangent_error(const std::string& name, const std::string& interaction_keys, unsigned seed,
                                     const std::function<void(model::Model&, const Eigen::VectorXd&)>& prepare) {
  const auto dir = fresh_directory(name);
  Eigen::VectorXd q;
  Eigen::MatrixXd K[2], Kfd[2];
  for (int k = 0; k < 2; ++k) {
    std::ofstream(dir / "case.yaml") << beam_over_panel_case(interaction_keys, k == 0 ? ", strength: 1.0e4"
                                                                                      : ", strength: 2.0e4");
    auto c = casefile::read_case((dir / "case.yaml").string());
    auto& m = *c.model;
    if (k == 0) {
      std::mt19937 rng(seed);
      std::uniform_real_distribution<double> u(-0.01, 0.01);
      q.resize(m.size());
      for (int i = 0; i < q.size(); ++i) q[i] = u(rng);
    }
    prepare(m, q);
    m.evaluate(q, 1.0, true);
    K[k] = Eigen::MatrixXd(m.tangent());
    Kfd[k] = finite_difference_tangent(m, q, 1.0, 1e-7);
  }
  const Eigen::MatrixXd coupling = K[1] - K[0];
  return (coupling - (Kfd[1] - Kfd[0])).cwiseAbs().maxCoeff() / coupling.cwiseAbs().maxCoeff();
}

}  // namespace fibrane::testing
