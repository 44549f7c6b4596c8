#pragma once
// Third parametric derivatives of the rational surface basis. Needed by the exact tangent of the full
// (FF) beam-shell interaction: the closest-point parameters theta-hat depend on the configuration, and
// their SECOND variation involves the third derivative of the surface (see docs/interaction.md).
#include <Eigen/Dense>
#include <vector>

#include "spline/surface.hpp"

namespace fibrane::spline {

struct SurfaceBasis3 {
  std::vector<int> indices;  // as SurfaceBasis::indices
  // Rows: R_uuu, R_uuv, R_uvv, R_vvv; column a matches indices[a].
  Eigen::Matrix<double, 4, Eigen::Dynamic> R;
};

SurfaceBasis3 basis3(const NurbsSurface& surface, double u, double v);
// Same with the knot spans given (cf. NurbsSurface::basis_in).
SurfaceBasis3 basis3_in(const NurbsSurface& surface, int span_u, int span_v, double u, double v);

}  // namespace fibrane::spline
