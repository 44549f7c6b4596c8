#pragma once
// The interface of a beam-shell interaction law per unit beam length (paper Eq. 5): the disk-surrogate
// plate potential phi(d, c) of a beam's circular cross-section at distance d from the mid-plane of the
// surrogate plate, c = cos(alpha) the angle between the disk and the plate (Sec. 5.2). The SBS kernels
// (src/interaction) see only this interface; the laws are chosen by name in a case file
// (laws/law_registry.hpp).
#include <string>

#include "laws/law_value.hpp"

namespace fibrane::laws {

// The geometry every disk-plate law depends on: the beam's section radius and the shell's thickness.
struct LawGeometry {
  double disk_radius = 0;
  double plate_thickness = 0;
};

class InteractionLaw {
 public:
  virtual ~InteractionLaw() = default;
  virtual std::string name() const = 0;
  // Value, first and second derivatives in (d, c) and the reduced forms of Eqs. (75), (E2). Throws
  // std::domain_error outside the domain d > contact_distance(c) (the disk overlaps the plate).
  virtual LawValue evaluate(double d, double c) const = 0;
  virtual LawGeometry geometry() const = 0;
  // A length over which the law changes appreciably near equilibrium (sigma for Lennard-Jones): the
  // scale of the root search and of the soft minimum's window.
  virtual double length_scale() const = 0;
  // The root of phi_,d(d, c) where repulsion turns into attraction (RF2 uses c = 1). Throws
  // std::runtime_error when the law has no such root (a purely attractive or repulsive law). The default
  // brackets the sign change from the contact distance outwards in steps of length_scale() and refines
  // it by safeguarded Newton.
  virtual double equilibrium_distance(double c = 1.0) const;
  // The contact distance c R + h/2: the disk touches the plate's surface.
  double contact_distance(double c) const;
};

}  // namespace fibrane::laws
