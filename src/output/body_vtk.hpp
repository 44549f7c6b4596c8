#pragma once
// Sampled geometry and fields of the model's bodies and interactions for ParaView.
#include <vector>

#include "io/vtk.hpp"
#include "model/model.hpp"
#include "path/continuation.hpp"

namespace fibrane::output {

// `samples` points per element edge; shells: displacement and section forces/moments (local frame and
// contravariant); beams: displacement, twist, directors, section force and moments.
io::VtuMesh shell_vtu(const model::Model& m, const model::ShellBody& s, int samples);
io::VtuMesh beam_vtu(const model::Model& m, const model::BeamBody& b, int samples);
// Exact geometry: Bezier cells of the deformed NURBS (io/bezier_vtu.hpp) with the displacement (and, for
// beams, the twist) as control-point fields, which VTK interpolates exactly as the splines do.
io::VtuMesh shell_bezier_vtu(const model::Model& m, const model::ShellBody& s);
io::VtuMesh beam_bezier_vtu(const model::Model& m, const model::BeamBody& b);
// An interaction's point data (model/interaction.hpp): one vertex cell per point, its fields as point data.
io::VtuMesh point_cloud_vtu(const model::PointCloud& cloud);

// The .pvd timestep of a step. ParaView orders a series by timestep, so it must grow along the run: t, or
// with `by_path_length` (arc-length runs, whose t turns back at limit points) the path length.
double series_timestep(const solve::StepReport& r, bool by_path_length);
// What every .vtu of a step carries as <FieldData>: `step`, `t`, and with `by_path_length` `path_length`.
std::vector<io::VtuMesh::Field> step_field_data(const solve::StepReport& r, bool by_path_length);

}  // namespace fibrane::output
