#include "io/bezier_vtu.hpp"

#include <fmt/format.h>

#include <stdexcept>
#include <utility>

#include "spline/bezier.hpp"

namespace fibrane::io {

namespace {

// (k, l) of every Bezier point of a cell in VTK's order (see the header); l = 0 throughout for a curve.
std::vector<std::pair<int, int>> vtk_point_order(int p, int q, bool curve) {
  std::vector<std::pair<int, int>> order;
  if (curve) {
    order = {{0, 0}, {p, 0}};
    for (int k = 1; k < p; ++k) order.emplace_back(k, 0);
    return order;
  }
  order = {{0, 0}, {p, 0}, {p, q}, {0, q}};
  for (int k = 1; k < p; ++k) order.emplace_back(k, 0);
  for (int l = 1; l < q; ++l) order.emplace_back(p, l);
  for (int k = 1; k < p; ++k) order.emplace_back(k, q);
  for (int l = 1; l < q; ++l) order.emplace_back(0, l);
  for (int l = 1; l < q; ++l)
    for (int k = 1; k < p; ++k) order.emplace_back(k, l);
  return order;
}

void check_inputs(std::size_t control_points, const std::vector<Eigen::Vector3d>& current,
                  const std::vector<VtuMesh::Field>& fields) {
  if (current.size() != control_points)
    throw std::invalid_argument(
        fmt::format("Bezier mesh: {} current control points, the NURBS has {}", current.size(), control_points));
  for (const auto& field : fields) {
    if (field.name == vtk_bezier::weights || field.name == vtk_bezier::degrees)
      throw std::invalid_argument(fmt::format("Bezier mesh: the field name '{}' is reserved", field.name));
    if (field.components < 1 || field.values.size() != control_points * field.components)
      throw std::invalid_argument(fmt::format("Bezier mesh: field '{}' has {} values, expected {} x {}", field.name,
                                              field.values.size(), control_points, field.components));
  }
}

// The Bezier points of a patch as one grid of `row_length` points per row. Element e occupies the grid
// block whose first point is origins[e]; its points and fields are written there (a point shared with
// an earlier element is overwritten by the same value up to round-off).
struct BezierGrid {
  int row_length = 0, num_points = 0;
  std::vector<std::pair<int, int>> origins;
  std::uint8_t cell_type = 0;
};

VtuMesh build_mesh(const std::vector<spline::BezierElement>& elements, const BezierGrid& grid,
                   const std::vector<Eigen::Vector3d>& current, const std::vector<VtuMesh::Field>& fields) {
  VtuMesh mesh;
  mesh.points.assign(grid.num_points, Eigen::Vector3d::Zero());
  VtuMesh::Field weights{vtk_bezier::weights, 1, std::vector<double>(grid.num_points, 1.0)};
  VtuMesh::Field degrees{vtk_bezier::degrees, 3, {}};
  std::vector<VtuMesh::Field> point_fields;
  for (const auto& f : fields) point_fields.push_back({f.name, f.components, std::vector<double>(grid.num_points * f.components)});
  const Eigen::Map<const Eigen::Matrix3Xd> points(reinterpret_cast<const double*>(current.data()), 3,
                                                  static_cast<Eigen::Index>(current.size()));
  const bool curve = grid.cell_type == vtk_cell::bezier_curve;
  for (std::size_t e = 0; e < elements.size(); ++e) {
    const spline::BezierElement& el = elements[e];
    const int nu = el.degree_u + 1;
    auto grid_index = [&](int k, int l) {
      return grid.origins[e].first + k + grid.row_length * (grid.origins[e].second + l);
    };
    const Eigen::MatrixXd xb = el.extract(points);
    std::vector<Eigen::MatrixXd> fb;
    for (const auto& f : fields)
      fb.push_back(el.extract(Eigen::Map<const Eigen::MatrixXd>(f.values.data(), f.components,
                                                                 static_cast<Eigen::Index>(current.size()))));
    for (int b = 0; b < el.num_points(); ++b) {
      const int g = grid_index(b % nu, b / nu);
      mesh.points[g] = xb.col(b);
      weights.values[g] = el.weights[b];
      for (std::size_t f = 0; f < fields.size(); ++f)
        for (int c = 0; c < fields[f].components; ++c) point_fields[f].values[g * fields[f].components + c] = fb[f](c, b);
    }
    for (const auto& [k, l] : vtk_point_order(el.degree_u, el.degree_v, curve)) mesh.connectivity.push_back(grid_index(k, l));
    mesh.offsets.push_back(static_cast<int>(mesh.connectivity.size()));
    mesh.types.push_back(grid.cell_type);
    degrees.values.insert(degrees.values.end(), {double(el.degree_u), double(el.degree_v), 0.0});
  }
  point_fields.push_back(std::move(weights));
  mesh.point_data = std::move(point_fields);
  mesh.cell_data = {std::move(degrees)};
  return mesh;
}

}  // namespace

VtuMesh bezier_surface_vtu(const spline::NurbsSurface& reference, const std::vector<Eigen::Vector3d>& current,
                           const std::vector<VtuMesh::Field>& fields) {
  check_inputs(reference.control_points().size(), current, fields);
  const int p = reference.degree(0), q = reference.degree(1);
  const int elements_u = reference.knots(0).num_elements(), elements_v = reference.knots(1).num_elements();
  BezierGrid grid;
  grid.row_length = elements_u * p + 1;
  grid.num_points = grid.row_length * (elements_v * q + 1);
  grid.cell_type = vtk_cell::bezier_quadrilateral;
  for (int ev = 0; ev < elements_v; ++ev)
    for (int eu = 0; eu < elements_u; ++eu) grid.origins.emplace_back(eu * p, ev * q);
  return build_mesh(spline::bezier_elements(reference), grid, current, fields);
}

VtuMesh bezier_curve_vtu(const spline::NurbsCurve& reference, const std::vector<Eigen::Vector3d>& current,
                         const std::vector<VtuMesh::Field>& fields) {
  check_inputs(reference.control_points().size(), current, fields);
  const int p = reference.degree(), elements = reference.knots().num_elements();
  BezierGrid grid;
  grid.row_length = elements * p + 1;
  grid.num_points = grid.row_length;
  grid.cell_type = vtk_cell::bezier_curve;
  for (int e = 0; e < elements; ++e) grid.origins.emplace_back(e * p, 0);
  return build_mesh(spline::bezier_elements(reference), grid, current, fields);
}

}  // namespace fibrane::io
