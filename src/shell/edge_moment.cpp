#include "shell/edge_moment.hpp"

namespace fibrane::shell {

namespace {
Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d s;
  s << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return s;
}
}  // namespace

void add_edge_moment_point(const Eigen::Vector3d& moment, const Eigen::RowVectorXd& dR, const Eigen::Matrix3Xd& x,
                           double weight, Eigen::VectorXd* residual, Eigen::MatrixXd* tangent) {
  const double m = moment.norm();
  if (m == 0.0) return;
  const Eigen::Vector3d e = moment / m;
  const Eigen::Vector3d a = x * dR.transpose();
  const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - e * e.transpose();
  const Eigen::Vector3d ap = P * a;
  const double s = ap.squaredNorm();
  const Eigen::Vector3d g = e.cross(ap) / s;
  const int n = static_cast<int>(dR.size());
  if (residual)
    for (int i = 0; i < n; ++i) residual->segment<3>(3 * i) -= weight * m * dR[i] * g;
  if (tangent) {
    const Eigen::Matrix3d dg = skew(e) / s - 2.0 * g * ap.transpose() / s;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) tangent->block<3, 3>(3 * i, 3 * j) -= weight * m * dR[i] * dR[j] * dg;
  }
}

}  // namespace fibrane::shell
