// Cost of the fiber-fiber pair search and of the beam-beam interaction in a model of many fibers:
// `bench_fibers [fibers = 100] [elements = 50] [evaluations = 5] [--threads N] [--membrane]`.
//
// The fibers form a mat of 10 layers of parallel, slightly wavy cubic fibers (radius 0.1, length 10, 1
// apart within a layer); the layers' directions turn by 18 degrees from one to the next, and the axes of
// neighbouring layers are 0.22 apart (gap 0.02), so every fiber crosses about ten fibers of each
// neighbouring layer. With --membrane the mat lies on a membrane: a flat quadratic C1 shell (16 x 16,
// thickness 0.1, 32 x 32 elements) 0.05 under the lowest layer, with one SBS coupling (RF2, Lennard-Jones
// disk-plate law, sigma = 0.01) per fiber; the beams' row then includes the shell. Lennard-Jones law, sigma = 0.01, cut-off gap 0.2. Measured (OpenMP's
// thread count unless --threads):
//   - the global search: a BoxTree over all elements' control-polygon boxes, rebuilt and refitted, and all
//     element pairs of different fibers within R_A + R_B + g_c (pairs found);
//   - Model::evaluate with tangent: the beams alone, and with one BeamBeamInteraction registered for every
//     pair of fibers that has an element pair within the search distance (from the global search);
//   - one SBIP kernel call (interaction::section_beam) near contact.
#include <fmt/format.h>
#include <omp.h>

#include <chrono>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include "interaction/box_tree.hpp"
#include "interaction/section_beam.hpp"
#include "linalg/linear_solver.hpp"
#include "model/beam_beam.hpp"
#include "laws/lennard_jones.hpp"
#include "model/beam_body.hpp"
#include "model/coupling.hpp"
#include "model/shell_body.hpp"
#include "spline/shapes.hpp"
#include "model/model.hpp"
#include "spline/curve.hpp"
#include "spline/knot_vector.hpp"

namespace {

using namespace fibrane;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

constexpr double kRadius = 0.1, kLength = 10, kCutoff = 0.2;

model::BeamBody fiber(int index, int layers, int per_layer, int elements) {
  const int layer = index / per_layer, k = index % per_layer;
  const double angle = layer * std::numbers::pi / 10, z = layer * (2 * kRadius + 0.02);
  const Eigen::Vector3d dir(std::cos(angle), std::sin(angle), 0), side(-std::sin(angle), std::cos(angle), 0);
  const double offset = (k - 0.5 * (per_layer - 1)) * kLength / per_layer;
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 6; ++i) {
    const double s = kLength * (i / 5.0 - 0.5);
    points.push_back(s * dir + (offset + 0.05 * std::sin(1.3 * i + index)) * side + Eigen::Vector3d(0, 0, z));
  }
  spline::NurbsCurve curve(spline::KnotVector(3, {0, 0, 0, 0, 1.0 / 3, 2.0 / 3, 1, 1, 1, 1}), points);
  curve.refine(3, 2, elements);
  model::BeamBody body("fiber" + std::to_string(index), curve, beam::BeamSection::circular(1e3, 0.3, kRadius),
                       Eigen::Vector3d::Zero());
  body.section_radius = kRadius;
  (void)layers;
  return body;
}

std::vector<Eigen::AlignedBox3d> element_boxes(const model::BeamBody& b) {
  std::vector<Eigen::AlignedBox3d> boxes;
  for (const auto& el : b.elements) {
    Eigen::AlignedBox3d box;
    for (int cp : el.control_points) box.extend(b.curve.control_points()[cp]);
    boxes.push_back(box);
  }
  return boxes;
}

// The command line: [fibers] [elements] [evaluations] [--threads N] [--membrane].
struct Options {
  int threads = 0, fibers = 100, elements = 50, evaluations = 5;
  bool membrane = false;
};

Options parse(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  Options o;
  if (const auto it = std::find(args.begin(), args.end(), "--membrane"); it != args.end()) {
    o.membrane = true;
    args.erase(it);
  }
  for (std::size_t i = 0; i + 1 < args.size(); ++i)
    if (args[i] == "--threads") {
      o.threads = std::atoi(args[i + 1].c_str());
      args.erase(args.begin() + static_cast<long>(i), args.begin() + static_cast<long>(i) + 2);
      break;
    }
  if (args.size() > 0) o.fibers = std::atoi(args[0].c_str());
  if (args.size() > 1) o.elements = std::atoi(args[1].c_str());
  if (args.size() > 2) o.evaluations = std::atoi(args[2].c_str());
  return o;
}

// The membrane under the mat and one SBS coupling per fiber, in both models; the couplings of `m`.
std::vector<model::Coupling*> add_membrane(model::Model& beams_only, model::Model& m,
                                           const std::vector<model::BeamBody*>& fibers) {
  const double h = 0.1, z = -(kRadius + 0.05 + 0.5 * h);
  auto sheet = [&] {
    spline::NurbsSurface s = spline::make_rectangle({-8, -8, z}, {16, 0, 0}, {0, 16, 0});
    s.refine(0, 2, 1, 32);
    s.refine(1, 2, 1, 32);
    return model::ShellBody("membrane", s, shell::ShellSection::svk(1e3, 0.3, h));
  };
  auto sbs = std::make_shared<laws::LennardJonesDiskPlate>(1.0, 0.01, kRadius, h);
  const model::ShellBody& alone = beams_only.add_shell(sheet());
  const model::ShellBody& with = m.add_shell(sheet());
  std::vector<model::Coupling*> couplings;
  for (std::size_t i = 0; i < fibers.size(); ++i) {
    beams_only.add_contribution(std::make_unique<model::Coupling>(
        fmt::format("sbs{}", i), sbs, interaction::Formulation::RF2, interaction::FfTangent::exact,
        beams_only.beams[i], alone));
    couplings.push_back(&dynamic_cast<model::Coupling&>(m.add_contribution(std::make_unique<model::Coupling>(
        fmt::format("sbs{}", i), sbs, interaction::Formulation::RF2, interaction::FfTangent::exact, *fibers[i],
        with))));
  }
  return couplings;
}

// The global search over all elements of all fibers, timed, and the pairs of fibers it finds.
struct ElementSearch {
  std::size_t boxes = 0;
  double build = 0, query = 0;  // seconds: the tree's construction, a refit with the pair query
  long pairs = 0;               // element pairs of different fibers within reach
  std::vector<std::pair<int, int>> fiber_pairs;
};

ElementSearch search_elements(const std::vector<model::BeamBody*>& fibers, double reach) {
  std::vector<Eigen::AlignedBox3d> boxes;
  std::vector<int> owner;
  for (std::size_t f = 0; f < fibers.size(); ++f)
    for (const auto& box : element_boxes(*fibers[f])) {
      boxes.push_back(box);
      owner.push_back(static_cast<int>(f));
    }
  ElementSearch result;
  result.boxes = boxes.size();
  auto t0 = Clock::now();
  interaction::BoxTree tree(boxes);
  result.build = seconds_since(t0);
  const int repeat = 20;
  t0 = Clock::now();
  for (int r = 0; r < repeat; ++r) {
    tree.refit(boxes);
    result.pairs = 0;
    tree.near_pairs(tree, reach, [&](int i, int j) { result.pairs += owner[i] != owner[j]; });
  }
  result.query = seconds_since(t0) / repeat;
  std::set<std::pair<int, int>> fiber_pair_set;
  tree.near_pairs(tree, reach, [&](int i, int j) {
    if (owner[i] != owner[j]) fiber_pair_set.emplace(std::min(owner[i], owner[j]), std::max(owner[i], owner[j]));
  });
  result.fiber_pairs.assign(fiber_pair_set.begin(), fiber_pair_set.end());
  return result;
}

// Seconds per SBIP point (energy, gradient and Hessian in its 15 local variables) near contact; `checksum`
// keeps the calls from being optimised away.
double time_sbip_point(const laws::SectionCylinderLaw& law, double& checksum) {
  interaction::SectionBeamPoint point;
  point.x = {0.01, 0.02, 2 * kRadius + 0.02};
  point.x_xi = {1, 0.1, 0.02};
  point.r[1] = {0.1, 1, 0};
  point.r[2] = {0.01, 0.02, 0.03};
  checksum = 0;
  const int calls = 20000;
  const auto t0 = Clock::now();
  for (int i = 0; i < calls; ++i) {
    point.x[0] = 0.01 + 1e-9 * i;
    checksum += interaction::section_beam(law, point).energy;
  }
  return seconds_since(t0) / calls;
}

// Seconds per Model::evaluate with tangent, after a first evaluation that makes the patterns.
double time_evaluations(model::Model& model, int evaluations) {
  const Eigen::VectorXd q = Eigen::VectorXd::Zero(model.size());
  model.evaluate(q, 1.0, true);
  const auto start = Clock::now();
  for (int e = 0; e < evaluations; ++e) model.evaluate(q, 1.0, true);
  return seconds_since(start) / evaluations;
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  if (o.threads > 0) solve::set_thread_count(o.threads);
  const int layers = 10, per_layer = (o.fibers + layers - 1) / layers;
  const double reach = 2 * kRadius + kCutoff;

  model::Model beams_only, m;
  std::vector<model::BeamBody*> fibers;
  for (int i = 0; i < o.fibers; ++i) {
    beams_only.add_beam(fiber(i, layers, per_layer, o.elements));
    fibers.push_back(&m.add_beam(fiber(i, layers, per_layer, o.elements)));
  }
  const std::vector<model::Coupling*> couplings = o.membrane ? add_membrane(beams_only, m, fibers)
                                                             : std::vector<model::Coupling*>{};
  const ElementSearch search = search_elements(fibers, reach);

  // One interaction per pair of fibers with an element pair within the search distance.
  auto law = std::make_shared<laws::SectionCylinderLaw>(
      laws::SectionCylinderLaw::lennard_jones(1.0, 0.01, kRadius, kRadius, 1.0, 0.002, kCutoff));
  std::vector<model::BeamBeamInteraction*> interactions;
  for (const auto& [i, j] : search.fiber_pairs)
    interactions.push_back(&dynamic_cast<model::BeamBeamInteraction&>(m.add_contribution(
        std::make_unique<model::BeamBeamInteraction>(fmt::format("f{}-f{}", i, j), law, *fibers[i], *fibers[j]))));
  beams_only.finalize();
  m.finalize();

  const double t_beams = time_evaluations(beams_only, o.evaluations);
  m.reset_times();
  const double t_all = time_evaluations(m, o.evaluations);
  const model::PhaseTimes times = m.times();
  long points = 0, element_pairs = 0, pattern = 0;
  double gap = 1e300;
  for (auto* bb : interactions) {
    points += bb->interacting_points();
    element_pairs += bb->interacting_pairs();
    pattern += bb->pattern_pairs();
    gap = std::min(gap, bb->minimum_gap());
  }
  double checksum = 0;
  const double kernel = time_sbip_point(*law, checksum);
  fmt::print("fibers {} x {} elements (cubic), {} DOFs, threads {}\n", o.fibers, o.elements, m.size(),
             o.threads > 0 ? o.threads : omp_get_max_threads());
  fmt::print("global search: {} element boxes, tree built in {:.3f} ms; refit + pair query {:.3f} ms; "
             "element pairs of different fibers within {:.2f}: {}\n",
             search.boxes, 1e3 * search.build, 1e3 * search.query, reach, search.pairs);
  fmt::print("registered fiber pairs: {}; element pairs in the patterns: {}; interacting element pairs: {}; "
             "interacting quadrature points: {}; minimum gap {:.4f}\n",
             search.fiber_pairs.size(), pattern, element_pairs, points, gap);
  fmt::print("Model::evaluate with tangent: beams alone {:.1f} ms, with the interactions {:.1f} ms "
             "(interactions {:.1f} ms per evaluation)\n",
             1e3 * t_beams, 1e3 * t_all, 1e3 * (t_all - t_beams));
  if (o.membrane) {
    long sbs_points = 0;
    for (auto* c : couplings) sbs_points += static_cast<long>(c->points().size());
    fmt::print("membrane: {} SBS couplings, {} beam quadrature points projected; both models include them\n",
               couplings.size(), sbs_points);
  }
  fmt::print("one SBIP point with gradient and Hessian: {:.1f} us (checksum {:.3g})\n", 1e6 * kernel, checksum);
  const double n = times.evaluations;
  fmt::print("per evaluation: closest points and patterns (update) {:.1f} ms, beam assembly {:.1f} ms, "
             "interaction assembly and the rest {:.1f} ms\n",
             1e3 * times.projection / n, 1e3 * times.beam / n, 1e3 * (times.other + times.pattern) / n);
  return 0;
}
