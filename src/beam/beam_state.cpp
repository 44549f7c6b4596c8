// Initial quadrature-point states of the undeformed beam axis (Sec. 3.2.1): tangent T, directors
// A2, A3, their xi-derivatives, and the reference strain measures K_1, A_1,1.A_alpha (Eqs. 37-38).
#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

#include "beam/beam.hpp"
#include "common/error.hpp"

namespace fibrane::beam {

namespace {

struct AxisGeometry {
  Eigen::Vector3d position = Eigen::Vector3d::Zero(), a1 = Eigen::Vector3d::Zero(),
                  a11 = Eigen::Vector3d::Zero(), T = Eigen::Vector3d::Zero(), T_xi = Eigen::Vector3d::Zero();
};

AxisGeometry axis_geometry(const BasisDerivs& R, const Eigen::Matrix3Xd& X) {
  if (X.cols() != R.cols()) throw std::invalid_argument("beam state: basis and control points differ in size");
  AxisGeometry g;
  g.position = X * R.row(0).transpose();
  g.a1 = X * R.row(1).transpose();
  g.a11 = X * R.row(2).transpose();
  const double length = g.a1.norm();
  if (!(length > 0)) throw InputError("beam: degenerate parametrisation (zero tangent) of the beam axis");
  g.T = g.a1 / length;
  g.T_xi = (g.a11 - g.T * g.T.dot(g.a11)) / length;
  return g;
}

Eigen::Vector3d least_aligned_axis(const Eigen::Vector3d& T) {
  Eigen::Index k;
  T.cwiseAbs().minCoeff(&k);
  return Eigen::Vector3d::Unit(k);
}

// Completes a state from the axis geometry and the director D2 with its xi-derivative.
BeamPointState complete_state(const AxisGeometry& g, const Eigen::Vector3d& d2, const Eigen::Vector3d& d2_xi) {
  BeamPointState st;
  st.ref_metric = g.a1.squaredNorm();
  st.frame_t = g.T;
  st.frame_t_xi = g.T_xi;
  st.frame_d2 = d2;
  st.frame_d2_xi = d2_xi;
  st.frame_d3 = g.T.cross(d2);
  st.frame_d3_xi = g.T_xi.cross(d2) + g.T.cross(d2_xi);
  st.ref_torsion = d2_xi.dot(st.frame_d3);  // K_1, Eq. 38
  st.ref_bend2 = g.a11.dot(st.frame_d3);
  st.ref_bend3 = g.a11.dot(d2);
  return st;
}

// A2 = P v / |P v| with P = I - T (x) T and a constant v; derivative by the chain rule.
BeamPointState state_from_vector(const AxisGeometry& g, const Eigen::Vector3d& v) {
  const Eigen::Vector3d pv = v - g.T * g.T.dot(v);
  const double n = pv.norm();
  if (!(n > 1e-8 * v.norm()))
    throw InputError("beam: reference director a2 is parallel to the beam axis");
  const Eigen::Vector3d pv_xi = -g.T_xi * g.T.dot(v) - g.T * g.T_xi.dot(v);
  const Eigen::Vector3d d2 = pv / n;
  const Eigen::Vector3d d2_xi = (pv_xi - d2 * d2.dot(pv_xi)) / n;
  return complete_state(g, d2, d2_xi);
}

}  // namespace

BeamPointState make_point_state(const BasisDerivs& R, const Eigen::Matrix3Xd& X,
                                const Eigen::Vector3d& a2_reference) {
  const AxisGeometry g = axis_geometry(R, X);
  const Eigen::Vector3d v = a2_reference.isZero(0.0) ? least_aligned_axis(g.T) : a2_reference;
  return state_from_vector(g, v);
}

std::vector<BeamPointState> make_curve_point_states(const std::vector<BasisDerivs>& basis,
                                                    const std::vector<Eigen::Matrix3Xd>& control_points,
                                                    const Eigen::Vector3d& a2_reference) {
  if (basis.size() != control_points.size())
    throw std::invalid_argument("beam states: one set of control points per point is required");
  std::vector<BeamPointState> states;
  states.reserve(basis.size());
  if (!a2_reference.isZero(0.0)) {
    for (size_t i = 0; i < basis.size(); ++i) states.push_back(make_point_state(basis[i], control_points[i], a2_reference));
    return states;
  }
  // Rotation-minimising (Bishop) frame by double reflection between consecutive points
  // (Wang, Juettler, Zheng, Liu 2008). Its torsion about T vanishes: A2_,1 = -(A2 . T_,1) T.
  AxisGeometry previous;
  Eigen::Vector3d d2 = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < basis.size(); ++i) {
    const AxisGeometry g = axis_geometry(basis[i], control_points[i]);
    if (i == 0) {
      const Eigen::Vector3d v = least_aligned_axis(g.T);
      d2 = (v - g.T * g.T.dot(v)).normalized();
    } else {
      const Eigen::Vector3d v1 = g.position - previous.position;
      const double c1 = v1.squaredNorm();
      Eigen::Vector3d r = d2, tl = previous.T;
      if (c1 > 0) {
        r -= (2.0 / c1) * v1.dot(r) * v1;
        tl -= (2.0 / c1) * v1.dot(tl) * v1;
      }
      const Eigen::Vector3d v2 = g.T - tl;
      const double c2 = v2.squaredNorm();
      if (c2 > 0) r -= (2.0 / c2) * v2.dot(r) * v2;
      d2 = (r - g.T * g.T.dot(r)).normalized();  // remove the O(h^3) drift off the normal plane
    }
    states.push_back(complete_state(g, d2, -g.T * d2.dot(g.T_xi)));
    previous = g;
  }
  return states;
}

}  // namespace fibrane::beam
