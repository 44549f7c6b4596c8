#pragma once
// The section-beam potential (interaction/section_beam.hpp) summed over two straight infinite fibers, both
// half passes averaged: per unit length for parallel fibers, in all for fibers crossed at right angles.
// Shared by the verification tests and bench_beam_beam_errors, which compare them with cylinder_reference.hpp.
#include <Eigen/Dense>

#include "cylinder_reference.hpp"
#include "interaction/section_beam.hpp"
#include "laws/section_cylinder.hpp"

namespace fibrane::interaction::test {

// SBIP energy per unit length of two parallel fibers, axes at distance d.
inline double sbip_parallel(const laws::SectionCylinderLaw& law, double d) {
  SectionBeamPoint p;
  p.x = {0, 0, d};
  p.r[1] = Eigen::Vector3d::UnitX();
  return 0.5 * (section_beam(law, p).energy + section_beam(law.swapped(), p).energy);
}

// SBIP energy of two infinite fibers crossed at right angles (A along x at height d, B along y), the
// integral along A by graded_integral with `points` per panel.
inline double sbip_crossed(const laws::SectionCylinderLaw& law, double d, int points) {
  auto pass = [&](const laws::SectionCylinderLaw& l) {
    auto f = [&](double s) {
      SectionBeamPoint p;
      p.x = {s, 0, d};
      p.x_xi = Eigen::Vector3d::UnitX();
      p.r[1] = Eigen::Vector3d::UnitY();
      return section_beam(l, p).energy;
    };
    return 2 * graded_integral(f, 0.0, 40 * (l.radius_a() + l.radius_b()), points);
  };
  return 0.5 * (pass(law) + pass(law.swapped()));
}

}  // namespace fibrane::interaction::test
