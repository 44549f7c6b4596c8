#include "laws/lennard_jones.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "common/error.hpp"
#include "laws/disk_plate.hpp"

namespace fibrane::laws {

LennardJonesDiskPlate::LennardJonesDiskPlate(double eps, double sig, double radius, double thickness, double beam,
                                             double shell, double s)
    : epsilon(eps), sigma(sig), disk_radius(radius), plate_thickness(thickness), density_beam(beam),
      density_shell(shell), strength(s) {}

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

}  // namespace fibrane::laws
