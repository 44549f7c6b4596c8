// Point moments on the beam (Eq. 54) and their load stiffness (App. B, Eqs. B8-B9).
//
// The virtual work of a moment M is M . delta omega with (Eq. 50)
//   delta omega = t delta phi + (I - t (x) T / t_T) (t x delta a_1) / sqrt(a),
// hence  delta W = (M . t) delta phi + f . delta a_1,  f = ((M - T (M . t) / t_T) x t) / sqrt(a),
// which is Eq. 54. The load stiffness is the derivative of (f, M . t) with respect to the local
// quantities, obtained exactly with the Jet (the moment does not depend on a_1,1 or phi_,1).
#include <stdexcept>

#include "beam/beam.hpp"
#include "beam/beam_kinematics.hpp"

namespace fibrane::beam {

using namespace detail;

namespace {

// Generalised force conjugate to the local quantities: components 0-2 (a_1) and 6 (phi).
struct MomentWork {
  Vec3<Jet> on_a1;
  Jet on_phi;
};

MomentWork moment_work(const Vec3<Jet>& M, const Kinematics<Jet>& k, const BeamPointState& st) {
  const Vec3<double> T = to_vec3<double>(st.frame_t);
  const Jet tT = 1.0 + dot(T, k.t);
  const Jet m_axial = dot(M, k.t);
  const Jet inv_length = 1.0 / sqrt(k.metric);
  return {inv_length * cross(M - (m_axial / tT) * T, k.t), m_axial};
}

void assemble_moment(const MomentWork& work, const BasisDerivs& R, Eigen::VectorXd* residual,
                     Eigen::MatrixXd* tangent) {
  const Eigen::Index ndof = 4 * R.cols();
  if (residual && residual->size() == 0) *residual = Eigen::VectorXd::Zero(ndof);
  if (tangent && tangent->size() == 0) *tangent = Eigen::MatrixXd::Zero(ndof, ndof);
  if ((residual && residual->size() != ndof) || (tangent && (tangent->rows() != ndof || tangent->cols() != ndof)))
    throw std::invalid_argument("point moment: output size does not match 4 x number of control points");
  // Row j of `load` holds the generalised force conjugate to local quantity j as a Jet.
  const Jet* load[kLocalVars] = {&work.on_a1.x, &work.on_a1.y, &work.on_a1.z, nullptr,
                                 nullptr,       nullptr,       &work.on_phi,  nullptr};
  Eigen::Matrix<double, kLocalVars, 1> force = Eigen::Matrix<double, kLocalVars, 1>::Zero();
  Eigen::Matrix<double, kLocalVars, kLocalVars> stiffness = Eigen::Matrix<double, kLocalVars, kLocalVars>::Zero();
  for (int j = 0; j < kLocalVars; ++j) {
    if (!load[j]) continue;
    force[j] = load[j]->v;
    stiffness.row(j) = load[j]->g.transpose();
  }
  const Eigen::MatrixXd B = local_map(R);
  // Residual = -delta W_ext; tangent = its derivative.
  if (residual) residual->noalias() -= B.transpose() * force;
  if (tangent) tangent->noalias() -= B.transpose() * stiffness * B;
}

}  // namespace

void add_point_moment(const Eigen::Vector3d& M, const BasisDerivs& R, const BeamDofs& q,
                      const BeamPointState& st, Eigen::VectorXd* residual, Eigen::MatrixXd* tangent) {
  const LocalVars<Jet> w = seed(local_vars(R, q, st));
  const Kinematics<Jet> k = kinematics(w, st);
  assemble_moment(moment_work(to_vec3<Jet>(M), k, st), R, residual, tangent);
}

void add_follower_point_moment(const Eigen::Vector3d& m, const BasisDerivs& R, const BeamDofs& q,
                               const BeamPointState& st, Eigen::VectorXd* residual,
                               Eigen::MatrixXd* tangent) {
  const LocalVars<Jet> w = seed(local_vars(R, q, st));
  const Kinematics<Jet> k = kinematics(w, st);
  const Vec3<Jet> M = m.x() * k.t + m.y() * k.a2 + m.z() * k.a3;
  assemble_moment(moment_work(M, k, st), R, residual, tangent);
}

}  // namespace fibrane::beam
