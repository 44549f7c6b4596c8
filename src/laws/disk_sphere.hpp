#pragma once
// Point-sphere and disk-sphere laws for the van der Waals exponent m = 6 (k_6 = 1, unit densities),
// paper App. F with the garbled Eqs. (F1) and (F4) corrected (derivation in docs/laws.md).
#include "laws/disk_halfspace.hpp"

namespace fibrane::laws {

// Point at distance t > R from the centre of a solid sphere of radius R (corrected Eq. F1):
//   Pi_PS(t) = 4 pi R^3 / (3 (t^2 - R^2)^3).
ScalarJet point_sphere(double sphere_radius, double t);

// Disk of radius R_D whose plane contains the centre of a sphere of radius R_S (perpendicular
// orientation, Fig. 27); d > R_D + R_S is the distance between the centres. Corrected Eq. (F4):
//   Pi_DS = pi^2/(3 R_S) (1 + N / ([d^2 - (R_D+R_S)^2][d^2 - (R_D-R_S)^2])^(3/2)),
//   N = R_S^6 + (R_D^2 - 3d^2) R_S^4 + 3(d^4 - R_D^4) R_S^2 - (d^2 - R_D^2)^3,
// evaluated in a cancellation-free rearrangement; derivatives are with respect to d.
ScalarJet disk_sphere(double disk_radius, double sphere_radius, double d);

// Disk against a spherical shell of mid-surface radius R_SS and thickness h (same orientation):
// the difference of the disk-sphere laws for radii R_SS + h/2 and R_SS - h/2.
ScalarJet disk_spherical_shell(double disk_radius, double shell_radius, double thickness, double d);

}  // namespace fibrane::laws
