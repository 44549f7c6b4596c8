#pragma once
// The error study of paper Sec. 4 (Figs. 6, 7, 8, 9, 11, 12) as CSV tables; see docs/laws.md for
// the chosen ratios and the comparison with the paper.
#include <ostream>
#include <string>
#include <vector>

namespace fibrane::laws::study {

std::vector<std::string> figure_names();  // "fig6", ..., "fig12"

// Writes the CSV of one figure. coarse = true uses fewer gap samples (for tests and quick looks).
void write_figure(const std::string& name, std::ostream& out, bool coarse = false);

// Force scaling factor S = -(g0 / F) dF/dg0 (Eq. 61 applied to the force) for the infinite
// cylinder - spherical shell pair of Sec. 4.3: exact (reference cubature) and SBS.
double scaling_factor_exact(double cylinder_radius, double shell_radius, double thickness, double gap);
double scaling_factor_sbs(double cylinder_radius, double shell_radius, double thickness, double gap,
                          bool exact_orientation);

}  // namespace fibrane::laws::study
