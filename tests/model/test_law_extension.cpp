// A law that fibrane does not ship, added the way an extension adds one: a class implementing
// laws::InteractionLaw and one registry line, then named in a case file. Here a purely repulsive inverse
// ninth power (m = 9) carries a beam pressed onto a fixed plate by a uniform line load q: the beam stays
// straight at the distance d* where the law's repulsion per length balances the load, -phi_,d(d*, 1) = q.
#include <gtest/gtest.h>

#include <cmath>

#include "case_runner.hpp"
#include "laws/disk_plate.hpp"
#include "laws/law_registry.hpp"

namespace fibrane::testing {
namespace {

// phi = k Pi^9_DPT(d, c): the law's own file would hold just this class.
class PureNinthPower final : public laws::InteractionLaw {
 public:
  PureNinthPower(double k, laws::LawGeometry g) : k_(k), g_(g), plate_(9, g.disk_radius, g.plate_thickness) {}
  std::string name() const override { return "pure_m9"; }
  laws::LawValue evaluate(double d, double c) const override { return plate_.jet(d, c).scaled(k_).to_law_value(c); }
  laws::LawGeometry geometry() const override { return g_; }
  double length_scale() const override { return g_.disk_radius; }

 private:
  double k_;
  laws::LawGeometry g_;
  laws::DiskPlate plate_;
};

const char* const beam_on_plate = R"(
shells:
  - name: plate
    geometry: {rectangle: {origin: [-3, -2, 0], edge_u: [6, 0, 0], edge_v: [0, 4, 0]}}
    refine: {degree: 2, continuity: 1, elements: [6, 4]}
    thickness: 0.2
    material: {young: 1000, poisson: 0.3}
beams:
  - name: fiber
    geometry: {line: {from: [-2, 0, 0.45], to: [2, 0, 0.45]}}
    refine: {degree: 3, continuity: 2, elements: 8}
    material: {young: 100, poisson: 0.3}
    section: {circle: {radius: 0.2}}
interactions:
  - {beam: fiber, shell: plate, law: {model: pure_m9, coefficient: 1.0e-4}}
constraints:
  - {body: plate, at: {all: true}, fix: [x, y, z]}
  - {body: fiber, at: [{end: start}, {end: end}], fix: [x, y]}
  - {body: fiber, at: {end: start}, fix: [twist]}
loads:
  - {body: fiber, type: line_load, force: [0, 0, -0.05]}
monitors:
  - {name: mid_z, type: position, body: fiber, at: {xi: 0.5}, component: z}
  - {name: end_z, type: position, body: fiber, at: {end: start}, component: z}
steps: {dt: 0.25, dt_max: 0.25}
)";

TEST(LawExtension, ANewLawThroughTheRegistryCarriesABeam) {
  auto& registry = laws::law_registry();
  if (!registry.find("pure_m9"))
    registry.add("pure_m9", "k Pi^9 (test)", [](const Parameters& p, const laws::LawGeometry& g) {
      p.reject_unknown({"coefficient"});
      return std::make_shared<PureNinthPower>(p.positive("coefficient"), g);
    });
  const CaseRun r = run_yaml("law-extension", beam_on_plate);
  ASSERT_TRUE(r.summary.result.completed()) << r.summary.result.message;
  // d* from the law itself: -phi_,d(d*, 1) = q = 0.05 by bisection (phi_,d is monotonic for a pure power).
  const PureNinthPower law(1e-4, {0.2, 0.2});
  double lo = law.contact_distance(1.0) + 1e-9, hi = 5.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (-law.evaluate(mid, 1.0).d_d > 0.05 ? lo : hi) = mid;
  }
  // Newton converged to 1e-9 of the load; the beam's bending is zero for a uniform load on a uniform
  // support, so both points sit at d* up to that tolerance over the law's stiffness (|phi_,dd| ~ 1):
  // 1e-8 absolute.
  EXPECT_NEAR(r.history.at("mid_z").back(), 0.5 * (lo + hi), 1e-8);
  EXPECT_NEAR(r.history.at("end_z").back(), 0.5 * (lo + hi), 1e-8);
}

}  // namespace
}  // namespace fibrane::testing
