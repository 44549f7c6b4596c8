#pragma once
// Geometry blocks of a case file: shell surfaces and beam axes, explicit or generated, then refined.
#include <string>
#include <vector>

#include "case/case_limits.hpp"
#include "io/yaml_input.hpp"
#include "spline/curve.hpp"
#include "spline/surface.hpp"

namespace fibrane::casefile {

// A shell's surface and a beam's axis from their geometry and refine blocks. `others` is the size of the
// bodies read before: a refinement whose model would not fit into memory is refused before it is made.
// The result is checked with check_surface_metric / check_curve_metric.
spline::NurbsSurface read_surface(const io::YamlNode& geometry, const std::optional<io::YamlNode>& refine,
                                  const ModelSize& others);
spline::NurbsCurve read_curve(const io::YamlNode& geometry, const std::optional<io::YamlNode>& refine,
                              const ModelSize& others);

// InputError at `geometry` where the surface's reference metric is singular: an edge collapsed to a point
// (a pole), or an area Jacobian ~0 relative to the patch size at a quadrature point of an element.
void check_surface_metric(const spline::NurbsSurface& surface, const io::YamlNode& geometry);
// InputError at `geometry` where the axis has zero speed at a quadrature point.
void check_curve_metric(const spline::NurbsCurve& curve, const io::YamlNode& geometry);
// InputError where a body's geometry is only C0 at an interior knot (multiplicity >= degree in one of
// `directions`): the rotation-free shell and beam kernels make such a knot a hinge. A shell entry `body`
// may say `allow_kinks: true` to keep such hinges; a beam cannot (its tangent would be singular). Located
// at refine.continuity when that is 0, else at the geometry; names the body (`kind` "shell" or "beam"),
// the knot and the remedies.
void check_no_kinks(const std::vector<const spline::KnotVector*>& directions, const io::YamlNode& body,
                    const std::string& kind);
// Length of the axis (Gauss quadrature of its speed).
double curve_length(const spline::NurbsCurve& curve);
// InputError at `node` where the (non-zero) director is parallel to the axis at a quadrature point.
void check_director(const spline::NurbsCurve& curve, const Eigen::Vector3d& director, const io::YamlNode& node);

}  // namespace fibrane::casefile
