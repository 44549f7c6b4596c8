#pragma once
// VTK meshes of Bezier cells that draw NURBS curves and surfaces exactly (spline/bezier.hpp): one
// VTK_BEZIER_CURVE or VTK_BEZIER_QUADRILATERAL per element, with the point field "RationalWeights" and
// the cell field "HigherOrderDegrees" VTK needs for rational cells of any degree.
//
// Geometry: the knots and weights of `reference` with the control points `current` (reference plus
// displacement). VTK's rational Bezier interpolation of a cell then equals that NURBS at every point,
// and every per-control-point field given is interpolated exactly as the NURBS interpolates it,
// f = sum_i R_i f_i (the fields are extracted in homogeneous form).
//
// Points are shared between neighbouring cells: the Bezier points of a patch form one tensor grid of
// (n_el_u p + 1) x (n_el_v q + 1) points (n_el p + 1 for a curve). Both elements yield the same values
// on their common edge (the spline is continuous), so sharing loses nothing; it makes the mesh
// connected (ParaView's normals, feature edges and connectivity filters see one surface, not separate
// patches) and the file smaller by a factor of about ((p+1)/p)^2.
//
// Point order within a cell (VTK's higher-order layout; vtkHigherOrderCurve and
// vtkHigherOrderQuadrilateral::PointIndexFromIJK in VTK's Common/DataModel, and "Modeling
// arbitrary-order Lagrange finite elements in the Visualization Toolkit", Kitware blog, 2018), with
// (k, l) the Bezier indices along u and v, k = 0..p, l = 0..q:
//   curve:          k = 0, k = p, then k = 1..p-1;
//   quadrilateral:  corners (0,0), (p,0), (p,q), (0,q);
//                   edges (k,0) k = 1..p-1; (p,l) l = 1..q-1; (k,q) k = 1..p-1; (0,l) l = 1..q-1 (each
//                   edge runs in increasing k or l, not around the cell);
//                   interior (k,l), k = 1..p-1 fastest, l = 1..q-1.
// VTK's parametric coordinates of a cell are r = (u - u0) / (u1 - u0), s = (v - v0) / (v1 - v0) in
// [0, 1]. Cell c is element c in the order of NurbsSurface::elements() (u fastest) or of the curve's
// knot spans, so per-element values can be appended to cell_data afterwards.
#include <Eigen/Core>
#include <vector>

#include "io/vtk.hpp"
#include "spline/curve.hpp"
#include "spline/surface.hpp"

namespace fibrane::io {

// Bezier quadrilaterals of `reference` deformed to the control points `current`. `fields` hold
// `components` values per control point (control-point-major, as the point fields of a VtuMesh); they
// become point fields of the same names. Throws std::invalid_argument if `current` or a field has the
// wrong size, or a field is named "RationalWeights".
VtuMesh bezier_surface_vtu(const spline::NurbsSurface& reference, const std::vector<Eigen::Vector3d>& current,
                           const std::vector<VtuMesh::Field>& fields = {});

// The same for a curve: Bezier curves, one per element.
VtuMesh bezier_curve_vtu(const spline::NurbsCurve& reference, const std::vector<Eigen::Vector3d>& current,
                         const std::vector<VtuMesh::Field>& fields = {});

}  // namespace fibrane::io
