// The gap law of the section-beam potential (laws/section_cylinder.hpp): the coefficient C_m of (S2),
// derivatives against central differences, C2 continuity at the regularization gap, at the taper's ends
// and of the slope term G, and the rejected parameters.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "common/error.hpp"
#include "laws/section_cylinder.hpp"
#include "laws/section_law_registry.hpp"

namespace fibrane::laws {
namespace {

TEST(SectionCylinderLaw, CoefficientOfTheVdwTerm) {
  // C_6 = 2 pi sqrt(pi) Gamma(3/2) / (4 * 3 * 2 * Gamma(2)) = pi^2 / 24.
  EXPECT_NEAR(SectionCylinderLaw::coefficient(6), std::numbers::pi * std::numbers::pi / 24, 1e-15);
}

// Values and derivatives just below and above `g` agree (C2): their jumps are below 1e-5 of the
// function's magnitude M = |f| + |f_g| L + |f_gg| L^2 a little below g (L = `scale`), divided by L^k.
template <class F>
void expect_c2(const F& f, double g, double scale) {
  const double e = 1e-9 * scale;
  const GapValue lo = f(g - e), hi = f(g + e), ref = f(g - 0.05 * scale);
  const double m = std::abs(ref.f) + std::abs(ref.f_g) * scale + std::abs(ref.f_gg) * scale * scale;
  EXPECT_NEAR(lo.f, hi.f, 1e-5 * m) << g;
  EXPECT_NEAR(lo.f_g, hi.f_g, 1e-5 * m / scale) << g;
  EXPECT_NEAR(lo.f_gg, hi.f_gg, 1e-5 * m / (scale * scale)) << g;
}

TEST(SectionCylinderLaw, DerivativesAndC2Joints) {
  const SectionCylinderLaw law({{6, -1.0}, {12, 1e-6}}, 0.3, 0.2, 2.0, 0.02, 0.5);
  auto f = [&](double g) { return law.evaluate(g); };
  for (double g : {-0.05, 0.01, 0.03, 0.1, 0.3, 0.45}) {
    const double h = 1e-6;
    const GapValue v = f(g), p = f(g + h), m = f(g - h);
    EXPECT_NEAR((p.f - m.f) / (2 * h), v.f_g, 1e-6 * std::abs(v.f_g) + 1e-9) << g;
    EXPECT_NEAR((p.f_g - m.f_g) / (2 * h), v.f_gg, 1e-6 * std::abs(v.f_gg) + 1e-9) << g;
  }
  expect_c2(f, 0.02, 0.02);   // regularization gap
  expect_c2(f, 0.25, 0.25);   // the taper's start (cut-off 0.5, width 0.25)
  expect_c2(f, 0.5, 0.5);     // the cut-off: zero from there on
  EXPECT_EQ(f(0.5).f, 0.0);
  EXPECT_EQ(f(0.7).f, 0.0);
  // Regularized: finite for every gap, overlaps included.
  EXPECT_TRUE(std::isfinite(f(-0.5).f));
  expect_c2([&](double g) { return law.slope_gap(g); }, 0.02, 0.02);
  EXPECT_GT(law.slope_gap(-10).f, 0.0);
  // Without regularization a non-positive gap has no value.
  const SectionCylinderLaw plain({{6, -1.0}}, 0.3, 0.2);
  EXPECT_THROW(plain.evaluate(0.0), std::domain_error);
  EXPECT_EQ(plain.slope_gap(0.3).f, 0.3);
}

TEST(SectionCylinderLaw, RejectsParametersOutsideItsDomain) {
  EXPECT_THROW(SectionCylinderLaw({{4, -1.0}}, 0.3, 0.2), InputError);  // m <= 4.5 diverges
  EXPECT_THROW(SectionCylinderLaw({{6, 0.0}}, 0.3, 0.2), InputError);
  EXPECT_THROW(SectionCylinderLaw({{6, -1.0}}, 0.0, 0.2), InputError);
  EXPECT_THROW(SectionCylinderLaw({{6, -1.0}}, 0.3, 0.2, -1.0), InputError);
  EXPECT_THROW(SectionCylinderLaw({{6, -1.0}}, 0.3, 0.2, 1.0, 0.1, 0.05), InputError);  // cut-off below g_r
  const SectionCylinderLaw lj = SectionCylinderLaw::lennard_jones(1.0, 0.1, 0.3, 0.2);
  EXPECT_EQ(lj.terms().size(), 2u);
  EXPECT_EQ(lj.swapped().radius_a(), 0.2);
}

TEST(SectionLawRegistry, BuildsTheLawsByNameAndRejectsBadKeys) {
  const SectionGeometry g{0.3, 0.2};
  const MapParameters lj("case.yaml: law", {{"epsilon", 2.0}, {"sigma", 0.1}, {"regularization", 0.01},
                                            {"cutoff", 0.5}, {"strength", 3.0}});
  const auto law = section_law_registry().make("lennard_jones", lj, g);
  const SectionCylinderLaw expected = SectionCylinderLaw::lennard_jones(2.0, 0.1, 0.3, 0.2, 3.0, 0.01, 0.5);
  for (double gap : {0.005, 0.05, 0.3}) EXPECT_DOUBLE_EQ(law->evaluate(gap).f, expected.evaluate(gap).f);
  const MapParameters sum("case.yaml: law", {}, {{"terms", {MapParameters("t", {{"exponent", 6}, {"coefficient", -1}}),
                                                           MapParameters("t", {{"exponent", 9}, {"coefficient", 1e-3}})}}});
  EXPECT_EQ(section_law_registry().make("inverse_power_sum", sum, g)->terms().size(), 2u);
  const MapParameters low("case.yaml: law", {{"exponent", 4}, {"coefficient", -1}});
  EXPECT_THROW(section_law_registry().make("inverse_power", low, g), InputError);
  const MapParameters typo("case.yaml: law", {{"epsilon", 2.0}, {"sigma", 0.1}, {"cutof", 0.5}});
  EXPECT_THROW(section_law_registry().make("lennard_jones", typo, g), InputError);
  EXPECT_THROW(section_law_registry().make("morse", lj, g), InputError);
  // A new law through the registry alone: a pure steric term with its own key.
  section_law_registry().add("steric_test", "k r^-12", [](const Parameters& p, const SectionGeometry& geometry) {
    p.reject_unknown({"k"});
    return std::make_shared<const SectionCylinderLaw>(std::vector<InversePowerTerm>{{12, p.positive("k")}},
                                                      geometry.radius_a, geometry.radius_b);
  });
  const auto steric = section_law_registry().make("steric_test", MapParameters("t", {{"k", 1e-6}}), g);
  EXPECT_GT(steric->evaluate(0.1).f, 0.0);
}

}  // namespace
}  // namespace fibrane::laws
