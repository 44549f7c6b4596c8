#pragma once
// A conservative moment distributed along a shell edge, for a rotation-free Kirchhoff-Love shell.
//
// The edge rotation about a fixed unit axis e is the angle theta of the projected outward tangent
// a_p = (I - e e^T) a, a = +-dx/du across the edge (Sec. 3.1 has no rotational DOFs, so the rotation is
// measured through the tangent). The load's potential is -m theta per unit reference length, with m the
// moment per unit length about e; its variation needs only
//   dtheta/da = (e x a_p) / |a_p|^2 =: g(a),   dg/da = [e]_x / |a_p|^2 - 2 (e x a_p)(P a)^T / |a_p|^4,
// so theta itself (and its unwrapping) is never needed. This is the load of the classic roll-up test: a
// cantilever strip with m = 2 pi E I / L per unit width closes into a full circle.
#include <Eigen/Dense>

namespace fibrane::shell {

// Adds -weight * m * g . delta a (residual = internal - external) and its derivative. `dR` holds the
// derivative across the edge (outward) of the element's basis functions at the edge point; `moment` is
// the moment vector per unit reference length (axis and magnitude); `weight` is the quadrature weight
// times the reference edge length element.
void add_edge_moment_point(const Eigen::Vector3d& moment, const Eigen::RowVectorXd& dR, const Eigen::Matrix3Xd& x,
                           double weight, Eigen::VectorXd* residual, Eigen::MatrixXd* tangent);

}  // namespace fibrane::shell
