#include "laws/interaction_law.hpp"

#include <cmath>
#include <stdexcept>

namespace fibrane::laws {

double InteractionLaw::contact_distance(double c) const {
  const LawGeometry g = geometry();
  return c * g.disk_radius + 0.5 * g.plate_thickness;
}

double InteractionLaw::equilibrium_distance(double c) const {
  // phi_,d < 0 (repulsion) just outside contact and > 0 (attraction) far away; bracket the sign change,
  // then safeguarded Newton with bisection fallback.
  const double contact = contact_distance(c), scale = length_scale();
  const double size = contact + scale + geometry().disk_radius;
  double low = contact + 1e-3 * scale;
  while (evaluate(low, c).d_d >= 0) {
    low = contact + 0.5 * (low - contact);
    if (low - contact < 1e-12 * (contact + scale))
      throw std::runtime_error(name() + ": no repulsive branch, hence no equilibrium distance");
  }
  double high = contact + scale;
  while (evaluate(high, c).d_d <= 0) {
    high = contact + 2.0 * (high - contact);
    if (high - contact > 1e6 * size)
      throw std::runtime_error(name() + ": no attractive branch, hence no equilibrium distance");
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
