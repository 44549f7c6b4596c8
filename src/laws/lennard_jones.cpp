#include "laws/lennard_jones.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "common/error.hpp"
#include "laws/disk_plate.hpp"

namespace fibrane::laws {

LawValue LennardJonesDiskPlate::evaluate(double d, double c) const {
  const double sigma6 = std::pow(sigma, 6);
  const double scale = strength * density_beam * density_shell * 4.0 * epsilon;
  DistanceSquaredCosJet jet =
      disk_plate_integer_jet(6, disk_radius, plate_thickness, d, c).scaled(-scale * sigma6);
  jet += disk_plate_integer_jet(12, disk_radius, plate_thickness, d, c)
             .scaled(scale * sigma6 * sigma6);
  return jet.to_law_value(c);
}

void LennardJonesDiskPlate::validate() const {
  auto require = [](bool ok, const char* what) {
    if (!ok) throw InputError(std::string("Lennard-Jones disk-plate law: ") + what);
  };
  require(epsilon > 0 && std::isfinite(epsilon), "epsilon must be positive");
  require(sigma > 0 && std::isfinite(sigma), "sigma must be positive");
  require(disk_radius > 0 && std::isfinite(disk_radius), "disk radius must be positive");
  require(plate_thickness > 0 && std::isfinite(plate_thickness), "plate thickness must be positive");
  require(density_beam > 0 && density_shell > 0, "densities must be positive");
  require(strength > 0 && std::isfinite(strength), "strength must be positive");
}

double LennardJonesDiskPlate::equilibrium_distance(double c) const {
  // phi_{,d} < 0 (repulsion) just outside contact and > 0 (attraction) far away; bracket the sign
  // change, then safeguarded Newton with bisection fallback.
  const double contact = c * disk_radius + 0.5 * plate_thickness;
  double low = contact + 1e-3 * sigma;
  while (evaluate(low, c).d_d >= 0) {
    low = contact + 0.5 * (low - contact);
    if (low - contact < 1e-12 * (contact + sigma))
      throw std::runtime_error("equilibrium_distance: no repulsive branch found");
  }
  double high = contact + sigma;
  while (evaluate(high, c).d_d <= 0) {
    high = contact + 2.0 * (high - contact);
    if (high - contact > 1e6 * (sigma + disk_radius))
      throw std::runtime_error("equilibrium_distance: no attractive branch found");
  }
  double d = 0.5 * (low + high);
  for (int iteration = 0; iteration < 200; ++iteration) {
    const LawValue v = evaluate(d, c);
    if (v.d_d < 0) low = d; else high = d;
    double next = d - v.d_d / v.d_dd;
    if (!(next > low && next < high)) next = 0.5 * (low + high);
    if (std::abs(next - d) <= 1e-15 * d) return next;
    d = next;
    if (high - low <= 4e-16 * d) return d;
  }
  return d;
}

}  // namespace fibrane::laws
