#pragma once
// Geometry blocks of a case file: shell surfaces and beam axes, explicit or generated, then refined.
#include "io/yaml_input.hpp"
#include "spline/curve.hpp"
#include "spline/surface.hpp"

namespace fibrane::casefile {

spline::NurbsSurface read_surface(const io::YamlNode& geometry, const std::optional<io::YamlNode>& refine);
spline::NurbsCurve read_curve(const io::YamlNode& geometry, const std::optional<io::YamlNode>& refine);

}  // namespace fibrane::casefile
