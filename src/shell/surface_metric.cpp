#include "shell/surface_metric.hpp"

namespace fibrane::shell {

SurfaceMetric surface_metric(const BasisDerivs& R, const Eigen::Matrix3Xd& points) {
  // One pass over the control points for r_,1 r_,2 r_,11 r_,12 r_,22; an explicit loop keeps the
  // fixed-size accumulators on the stack (no temporary from a dynamic-size product).
  Eigen::Vector3d d1 = Eigen::Vector3d::Zero(), d2 = d1, d11 = d1, d12 = d1, d22 = d1;
  for (Eigen::Index A = 0; A < R.cols(); ++A) {
    const Eigen::Vector3d p = points.col(A);
    d1 += R(1, A) * p;
    d2 += R(2, A) * p;
    d11 += R(3, A) * p;
    d12 += R(4, A) * p;
    d22 += R(5, A) * p;
  }
  SurfaceMetric m;
  m.g1 = d1;
  m.g2 = d2;
  m.g11 = d11;
  m.g12 = d12;
  m.g22 = d22;
  const Eigen::Vector3d a = d1.cross(d2);
  m.area_jacobian = a.norm();
  m.normal = a / m.area_jacobian;
  m.metric = {d1.dot(d1), d2.dot(d2), d1.dot(d2)};
  // det g_ab = |g1 x g2|^2 (Lagrange identity); using it keeps the inverse consistent with j.
  const double det = m.area_jacobian * m.area_jacobian;
  m.inverse_metric << m.metric[1] / det, -m.metric[2] / det, -m.metric[2] / det, m.metric[0] / det;
  m.dual1 = m.inverse_metric(0, 0) * d1 + m.inverse_metric(0, 1) * d2;
  m.dual2 = m.inverse_metric(1, 0) * d1 + m.inverse_metric(1, 1) * d2;
  m.curvature = {m.normal.dot(d11), m.normal.dot(d22), m.normal.dot(d12)};
  return m;
}

}  // namespace fibrane::shell
