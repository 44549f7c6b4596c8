#pragma once
// Where a condition acts: a list of "sites", each the displacement of one point written as a linear
// combination of control-point values (a control point itself, or a parametric point through the basis).
// Also: rows of control points along an edge or end, for clamping and symmetry of C1 splines.
#include <utility>
#include <vector>

#include "io/yaml_input.hpp"
#include "model/model.hpp"

namespace fibrane::casefile {

using model::Model;

using Site = std::vector<std::pair<int, double>>;  // (control point, weight)

struct BodyRef {
  bool is_beam = false;
  int index = 0;
  int block = 0;
  int dofs_per_node = 3;
};

BodyRef find_body(const Model& m, const io::YamlNode& name_node);
// `at` is one of {edge: u0|u1|v0|v1}, {corner: [i, j]}, {point: [u, v]}, {all: true} for shells and
// {end: start|end}, {xi: s}, {all: true} for beams.
std::vector<Site> sites(const Model& m, const BodyRef& b, const io::YamlNode& at);
// Control-point rows at an edge (shell) or end (beam): row 0 on the boundary, row 1 next inward.
std::vector<int> boundary_row(const Model& m, const BodyRef& b, const io::YamlNode& at, int row);
// Component name -> index: x, y, z (all bodies), twist (beams).
int component(const BodyRef& b, const io::YamlNode& node);
// The beam parameter of `at`: {end: start|end} or {xi: s} inside the knot range; InputError otherwise.
double beam_parameter(const model::BeamBody& b, const io::YamlNode& at);

}  // namespace fibrane::casefile
