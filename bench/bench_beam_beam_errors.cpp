// The beam-beam error study as a table: the relative error of the section-beam interaction potential's
// energy and force (SBIP, interaction/section_beam.hpp) against the direct integration of the point-pair
// law over both cylinders' volumes (tests/interaction/cylinder_reference.hpp), for two parallel and two
// crossed fibers (R_A = 1, R_B = 0.6), single inverse-power terms m = 6 and m = 12, over the separation
// g / R_A from 0.5 to 1e-3: `bench_beam_beam_errors` prints `case m g energy_error force_error` rows.
// The reference force is the central difference of the reference energy (step 1e-4 g), as in the test
// SectionBeamVerification.*; scripts/beam_beam_error_figure.py draws the figure from the table.
#include <cmath>
#include <cstdio>

#include "../tests/interaction/cylinder_reference.hpp"
#include "../tests/interaction/sbip_energies.hpp"
#include "interaction/section_beam.hpp"

namespace {

using namespace fibrane;
using interaction::test::sbip_crossed;
using interaction::test::sbip_parallel;
using laws::SectionCylinderLaw;

constexpr double kRa = 1.0, kRb = 0.6;

template <class Sbip, class Reference>
void row(const char* what, double m, double g, const Sbip& sbip, const Reference& reference) {
  const double d = kRa + kRb + g, h = 1e-4 * g;
  const double ep = reference(d + h), em = reference(d - h);
  const double exact = 0.5 * (ep + em), exact_force = -(ep - em) / (2 * h);
  const double force = -(sbip(d + h) - sbip(d - h)) / (2 * h);
  std::printf("%s %g %.6e %.6e %.6e\n", what, m, g, std::abs(sbip(d) / exact - 1),
              std::abs(force / exact_force - 1));
  std::fflush(stdout);
}

}  // namespace

int main() {
  std::printf("case m g energy_error force_error\n");
  const double gaps[] = {0.5, 0.2, 0.1, 0.05, 0.02, 0.01, 0.005, 0.002, 0.001};
  for (double m : {6.0, 12.0}) {
    const SectionCylinderLaw law({{m, -1.0}}, kRa, kRb);
    for (double g : gaps)
      row("parallel", m, g, [&](double d) { return sbip_parallel(law, d); },
          [&](double d) { return -interaction::test::parallel_cylinders(m, kRa, kRb, d, 10); });
    for (double g : gaps)
      row("crossed", m, g, [&](double d) { return sbip_crossed(law, d, 10); },
          [&](double d) { return -interaction::test::crossed_cylinders(m, kRa, kRb, d, 6); });
  }
}
