// Point kernel of the Kirchhoff-Love shell: energy (Eqs. 25-29), internal virtual work (Eqs. 28, 30, 31)
// and its linearization (Appendix A), in covariant components.
//
// Derivation used here (checked against Eqs. 30, 31 and A8; the sign of the DeltaGamma term in Eq. A3 is a
// typo, A8 is right). For control point A with basis derivatives R_aA, R_abA:
//   dE_ab/du_A = (R_aA g_b + R_bA g_a) / 2                                     (Eq. 30)
//   db_ab/du_A = c_abA n,   c_abA := R_abA - Gamma^1_ab R_1A - Gamma^2_ab R_2A  (Eq. 31)
// with Gamma^c_ab = g_a,b . g^c. Second derivatives for the node pair (A, B):
//   d2E_ab/du_A du_B = (R_aA R_bB + R_bA R_aB) / 2 * I                         (Eq. A2)
//   d2b_ab/du_A du_B = -c_abA v_B n^T - c_abB n v_A^T - b_ab (v_A . v_B) n n^T  (Eq. A8 regrouped)
// where v_A := R_1A g^1 + R_2A g^2. The five terms of A8 collapse into these three because the terms with
// and without Christoffel symbols share the factor c_ab, and g^cd R_cA R_dB = v_A . v_B.
#include <stdexcept>

#include "shell/kl_shell.hpp"
#include "shell/surface_metric.hpp"

namespace fibrane::shell {
namespace {

// First derivatives of the Voigt strains with respect to the displacement of one control point.
struct NodeTerms {
  double r1, r2;                   // R_1A, R_2A
  Eigen::Matrix3d membrane;        // columns: d(E11, E22, 2E12)/du_A
  Eigen::Vector3d bending;         // (c11, c22, 2 c12): d(K11, K22, 2K12)/du_A = bending * n^T
  Eigen::Matrix3d membrane_stiff;  // membrane * (h D); column i: d(N^11, N^22, N^12)_i / du_A
  Eigen::Vector3d bending_stiff;   // (h^3/12) D bending: d(M^11, M^22, M^12)/du_A along n
  Eigen::Vector3d v;               // R_1A g^1 + R_2A g^2
  double moment_work;              // M^ab c_abA, summed with the Voigt factor 2 on 12
};

void check_sizes(const BasisDerivs& R, const Eigen::Matrix3Xd& X, const Eigen::Matrix3Xd& x,
                 const Eigen::VectorXd* residual, const Eigen::MatrixXd* tangent) {
  const Eigen::Index nen = R.cols(), ndof = 3 * nen;
  if (X.cols() != nen || x.cols() != nen)
    throw std::invalid_argument("add_shell_point: basis and control points disagree on the node count");
  if (nen > kMaxShellNodes) throw std::invalid_argument("add_shell_point: too many control points");
  if (residual && residual->size() != ndof)
    throw std::invalid_argument("add_shell_point: residual must have size 3 * nen");
  if (tangent && (tangent->rows() != ndof || tangent->cols() != ndof))
    throw std::invalid_argument("add_shell_point: tangent must have size 3 nen x 3 nen");
}

}  // namespace

void add_shell_point(const ShellSection& s, const BasisDerivs& R, const Eigen::Matrix3Xd& X,
                     const Eigen::Matrix3Xd& x, double weight, double* energy, Eigen::VectorXd* residual,
                     Eigen::MatrixXd* tangent) {
  check_sizes(R, X, x, residual, tangent);
  const SurfaceMetric ref = surface_metric(R, X);
  const SurfaceMetric cur = surface_metric(R, x);
  const double scale = weight * ref.area_jacobian;  // dA = J_S dtheta1 dtheta2 (Eq. 28)
  const double h = s.thickness;
  const Eigen::Matrix3d D = plane_stress_matrix(s, ref.inverse_metric);
  const Eigen::Matrix3d Dm = h * D;                     // membrane stiffness, Eq. 29
  const Eigen::Matrix3d Db = (h * h * h / 12.0) * D;    // bending stiffness, Eq. 29
  const Eigen::Vector3d e = membrane_strain(cur, ref);  // (E11, E22, 2E12)
  const Eigen::Vector3d k = curvature_change(cur, ref);  // (K11, K22, 2K12)
  const Eigen::Vector3d N = Dm * e;                     // (N^11, N^22, N^12)
  const Eigen::Vector3d M = Db * k;                     // (M^11, M^22, M^12)

  // Energy density (h/2) E:C:E + (h^3/24) K:C:K (Eq. 25 integrated through the thickness).
  if (energy) *energy += scale * 0.5 * (e.dot(N) + k.dot(M));
  if (!residual && !tangent) return;

  const Eigen::Vector3d& n = cur.normal;
  // Christoffel symbols Gamma^c_ab = g_a,b . g^c, one column per Voigt pair ab.
  Eigen::Matrix<double, 2, 3> gamma;
  gamma << cur.g11.dot(cur.dual1), cur.g22.dot(cur.dual1), cur.g12.dot(cur.dual1),
      cur.g11.dot(cur.dual2), cur.g22.dot(cur.dual2), cur.g12.dot(cur.dual2);

  const Eigen::Index nen = R.cols();
  NodeTerms nodes[kMaxShellNodes];
  for (Eigen::Index A = 0; A < nen; ++A) {
    NodeTerms& t = nodes[A];
    t.r1 = R(1, A);
    t.r2 = R(2, A);
    t.membrane.col(0) = t.r1 * cur.g1;
    t.membrane.col(1) = t.r2 * cur.g2;
    t.membrane.col(2) = t.r1 * cur.g2 + t.r2 * cur.g1;
    // R rows 3, 4, 5 are R_11, R_12, R_22; Voigt order is 11, 22, 12.
    t.bending[0] = R(3, A) - gamma(0, 0) * t.r1 - gamma(1, 0) * t.r2;
    t.bending[1] = R(5, A) - gamma(0, 1) * t.r1 - gamma(1, 1) * t.r2;
    t.bending[2] = 2.0 * (R(4, A) - gamma(0, 2) * t.r1 - gamma(1, 2) * t.r2);
    t.moment_work = M.dot(t.bending);
    if (residual) residual->segment<3>(3 * A) += scale * (t.membrane * N + t.moment_work * n);
  }
  if (!tangent) return;

  for (Eigen::Index A = 0; A < nen; ++A) {
    NodeTerms& t = nodes[A];
    t.membrane_stiff.noalias() = t.membrane * Dm;
    t.bending_stiff.noalias() = Db * t.bending;
    t.v = t.r1 * cur.dual1 + t.r2 * cur.dual2;
  }
  // Moment-weighted curvature M^ab b_ab of the second variation of b_ab (Voigt factor 2 on 12).
  const double moment_curvature = M[0] * cur.curvature[0] + M[1] * cur.curvature[1] +
                                  2.0 * M[2] * cur.curvature[2];
  const Eigen::Matrix3d nn = n * n.transpose();
  for (Eigen::Index A = 0; A < nen; ++A) {
    const NodeTerms& a = nodes[A];
    for (Eigen::Index B = A; B < nen; ++B) {
      const NodeTerms& b = nodes[B];
      // Material part: dN/du_A . dE/du_B + dM/du_A . dK/du_B (Eq. A1); the bending part is along n n^T,
      // as is the b_ab (v_A . v_B) term of M^ab d2b_ab.
      Eigen::Matrix3d kab;
      kab.noalias() = a.membrane_stiff * b.membrane.transpose();
      const double normal_coeff = a.bending_stiff.dot(b.bending) - moment_curvature * a.v.dot(b.v);
      // Geometric part from the membrane forces, N^ab d2E_ab (Eq. A2).
      const double isotropic = N[0] * a.r1 * b.r1 + N[1] * a.r2 * b.r2 + N[2] * (a.r1 * b.r2 + a.r2 * b.r1);
      kab += normal_coeff * nn;
      kab.diagonal().array() += isotropic;
      // Remaining geometric part from the moments, M^ab d2b_ab (Eq. A8).
      kab.noalias() -= (a.moment_work * b.v) * n.transpose() + (b.moment_work * n) * a.v.transpose();
      tangent->block<3, 3>(3 * A, 3 * B) += scale * kab;
      if (B != A) tangent->block<3, 3>(3 * B, 3 * A) += scale * kab.transpose();
    }
  }
}

}  // namespace fibrane::shell
