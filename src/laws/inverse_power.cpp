#include "laws/inverse_power.hpp"

#include <algorithm>
#include <cmath>

#include "common/error.hpp"
#include "common/format.hpp"

namespace fibrane::laws {
namespace {

bool closed_form(double m) { return m == std::floor(m) && m >= 6 && m <= 32; }

}  // namespace

InversePowerSum::InversePowerSum(std::vector<InversePowerTerm> terms, LawGeometry geometry, double factor)
    : terms_(std::move(terms)), geometry_(geometry), factor_(factor) {
  if (terms_.empty()) throw InputError("inverse-power law: at least one term is needed");
  if (!(geometry_.disk_radius > 0) || !(geometry_.plate_thickness > 0))
    throw InputError("inverse-power law: disk radius and plate thickness must be positive");
  if (!(factor_ > 0) || !std::isfinite(factor_))
    throw InputError("inverse-power law: strength x densities must be positive");
  for (const auto& t : terms_) {
    if (!(t.exponent > 3) || !std::isfinite(t.exponent))
      throw InputError("inverse-power law: exponent " + format_number(t.exponent) + " must exceed 3");
    if (t.coefficient == 0 || !std::isfinite(t.coefficient))
      throw InputError("inverse-power law: coefficients must be finite and non-zero");
    general_.push_back(closed_form(t.exponent) ? nullptr
                                               : std::make_unique<DiskPlate>(t.exponent, geometry_.disk_radius,
                                                                             geometry_.plate_thickness));
  }
}

LawValue InversePowerSum::evaluate(double d, double c) const {
  DistanceSquaredCosJet sum;
  for (std::size_t i = 0; i < terms_.size(); ++i) {
    const auto& t = terms_[i];
    const DistanceSquaredCosJet jet =
        general_[i] ? general_[i]->jet(d, c)
                    : disk_plate_integer_jet(static_cast<int>(t.exponent), geometry_.disk_radius,
                                             geometry_.plate_thickness, d, c);
    sum += jet.scaled(factor_ * t.coefficient);
  }
  return sum.to_law_value(c);
}

double InversePowerSum::length_scale() const {
  const auto [lo, hi] = std::minmax_element(terms_.begin(), terms_.end(), [](const auto& a, const auto& b) {
    return a.exponent < b.exponent;
  });
  if (lo->coefficient < 0 && hi->coefficient > 0 && hi->exponent > lo->exponent)
    return std::pow(hi->coefficient / -lo->coefficient, 1.0 / (hi->exponent - lo->exponent));
  return geometry_.disk_radius;
}

}  // namespace fibrane::laws
