// Beam strain energy, residual and tangent at one quadrature point (Eqs. 43-53, App. B).
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "beam/beam.hpp"
#include "beam/beam_kinematics.hpp"
#include "common/error.hpp"

namespace fibrane::beam {

using namespace detail;

BeamSection BeamSection::circular(double young, double poisson, double radius) {
  const double pi = std::numbers::pi;
  const double r2 = radius * radius;
  // Eq. 48 for a disk: F = pi r^2, I = pi r^4 / 4 about each axis, polar I_t = pi r^4 / 2.
  return general(young, poisson, pi * r2, pi * r2 * r2 / 4.0, pi * r2 * r2 / 4.0, pi * r2 * r2 / 2.0);
}

BeamSection BeamSection::general(double young, double poisson, double area, double i2, double i3,
                                 double it) {
  if (!(young > 0) || !(area > 0) || !(i2 > 0) || !(i3 > 0) || !(it > 0))
    throw InputError("beam section: Young's modulus, area and inertias must be positive");
  if (!(poisson > -1.0 && poisson < 0.5))
    throw InputError("beam section: Poisson's ratio must lie in (-1, 0.5)");
  BeamSection s;
  s.young = young;
  s.shear = young / (2.0 * (1.0 + poisson));
  s.area = area;
  s.inertia2 = i2;
  s.inertia3 = i3;
  s.torsion = it;
  return s;
}

namespace {

void prepare(Eigen::VectorXd* residual, Eigen::MatrixXd* tangent, Eigen::Index ndof) {
  if (residual && residual->size() == 0) *residual = Eigen::VectorXd::Zero(ndof);
  if (tangent && tangent->size() == 0) *tangent = Eigen::MatrixXd::Zero(ndof, ndof);
  if ((residual && residual->size() != ndof) || (tangent && (tangent->rows() != ndof || tangent->cols() != ndof)))
    throw std::invalid_argument("beam kernel: output size does not match 4 x number of control points");
}

}  // namespace

void add_beam_point(const BeamSection& s, const BasisDerivs& R, const BeamDofs& q, const BeamPointState& st,
                    double weight, double* energy, Eigen::VectorXd* residual, Eigen::MatrixXd* tangent) {
  const LocalVars<double> w = local_vars(R, q, st);
  if (!residual && !tangent) {
    if (energy) *energy += weight * energy_density(s, strains(w, kinematics(w, st), st), st);
    return;
  }
  prepare(residual, tangent, 4 * R.cols());
  const LocalVars<Jet> wj = seed(w);
  const Jet e = energy_density(s, strains(wj, kinematics(wj, st), st), st);
  if (energy) *energy += weight * e.v;
  const Eigen::MatrixXd B = local_map(R);
  // w is linear in q, so dPi/dq = B^T dPi/dw and d2Pi/dq2 = B^T d2Pi/dw2 B exactly.
  if (residual) residual->noalias() += weight * (B.transpose() * e.g);
  if (tangent) tangent->noalias() += B.transpose() * (weight * e.h) * B;
}

void update_point_state(BeamPointState& st, const BasisDerivs& R, const BeamDofs& q) {
  const LocalVars<double> w = local_vars(R, q, st);
  const Kinematics<double> k = kinematics(w, st);
  st.frame_t = to_eigen(k.t);
  st.frame_t_xi = to_eigen(k.t_xi);
  st.frame_d2 = to_eigen(k.a2);
  st.frame_d2_xi = to_eigen(k.a2_xi);
  st.frame_d3 = to_eigen(k.a3);
  st.frame_d3_xi = to_eigen(k.a3_xi);
  // With T = t the SR map is the identity and phi is measured from the new frame (Eqs. 34-35).
  st.twist_offset = q.row(3).dot(R.row(0));
  st.twist_offset_xi = q.row(3).dot(R.row(1));
}

BeamPointOutput evaluate_point(const BeamSection& s, const BasisDerivs& R, const BeamDofs& q,
                               const BeamPointState& st) {
  const LocalVars<double> w = local_vars(R, q, st);
  const Kinematics<double> k = kinematics(w, st);
  const Strains<double> e = strains(w, k, st);
  const double A = st.ref_metric;
  BeamPointOutput out;
  out.r = q.topRows<3>() * R.row(0).transpose();
  out.t = to_eigen(k.t);
  out.a2 = to_eigen(k.a2);
  out.a3 = to_eigen(k.a3);
  out.eps11 = e.eps11 / A;
  out.kappa[0] = e.kappa1 / std::sqrt(A);
  out.kappa[1] = e.kappa2 / A;
  out.kappa[2] = e.kappa3 / A;
  out.N = s.young * s.area * out.eps11;
  out.M[0] = s.shear * s.torsion * out.kappa[0];
  out.M[1] = s.young * s.inertia2 * out.kappa[1];
  out.M[2] = s.young * s.inertia3 * out.kappa[2];
  return out;
}

}  // namespace fibrane::beam
