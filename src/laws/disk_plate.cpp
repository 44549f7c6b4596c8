#include "laws/disk_plate.hpp"

#include <stdexcept>

#include "common/error.hpp"
#include "common/gauss_legendre.hpp"

namespace fibrane::laws {
namespace {

// Nodes and weights of the thickness rule, built once.
const QuadratureRule& thickness_rule() {
  static const QuadratureRule rule = gauss_legendre(kThicknessQuadraturePoints);
  return rule;
}

bool use_thickness_quadrature(double radius, double thickness, double d, double c) {
  return d - c * radius >= kThicknessQuadratureRatio * 0.5 * thickness;
}

}  // namespace

DiskPlate::DiskPlate(double m, double radius, double thickness)
    : half_space_(m, radius), layer_(m + 1.0, radius), thickness_(thickness),
      rule_(thickness_rule()) {
  if (!(thickness > 0.0)) throw InputError("plate thickness must be positive");
}

DistanceSquaredCosJet DiskPlate::jet(double d, double c) const {
  const double half = 0.5 * thickness_;
  if (!use_thickness_quadrature(radius(), thickness_, d, c)) {
    DistanceSquaredCosJet out = half_space_.jet(d - half, c);
    out += half_space_.jet(d + half, c).scaled(-1.0);
    return out;
  }
  DistanceSquaredCosJet out;
  for (std::size_t i = 0; i < rule_.points.size(); ++i)
    out += layer_.jet(d + half * rule_.points[i], c).scaled(rule_.weights[i] * half);
  return out.scaled(exponent() - 1.0);
}

DistanceSquaredCosJet disk_plate_integer_jet(int m, double radius, double thickness, double d,
                                             double c) {
  const double half = 0.5 * thickness;
  if (!use_thickness_quadrature(radius, thickness, d, c)) {
    DistanceSquaredCosJet out = disk_halfspace_integer_jet(m, radius, d - half, c);
    out += disk_halfspace_integer_jet(m, radius, d + half, c).scaled(-1.0);
    return out;
  }
  const QuadratureRule& rule = thickness_rule();
  DistanceSquaredCosJet out;
  for (std::size_t i = 0; i < rule.points.size(); ++i)
    out += disk_halfspace_integer_jet(m + 1, radius, d + half * rule.points[i], c)
               .scaled(rule.weights[i] * half);
  return out.scaled(m - 1.0);
}

}  // namespace fibrane::laws
