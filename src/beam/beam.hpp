#pragma once
// Geometrically exact Bernoulli-Euler beam: pure quadrature-point kernels (paper Sec. 3.2, App. B).
//
// DOFs: 4 per control point, ordered [x, y, z, phi]; phi is the twist of the cross section
// interpolated with the same basis as the axis. The current triad (t, a2, a3) is obtained from a
// frame reference (T, D2, D3) by the smallest-rotation map (Eq. 34) followed by a rotation by the
// relative twist phi - phi_ref about t (Eq. 35). The frame reference is updated incrementally after
// converged steps (update_point_state); strains are always measured against the original reference.
//
// Strain measures (Eq. 43, with the printed factors corrected):
//   eps11   = (a - A) / 2,                 a = a_1.a_1, A = A_1.A_1
//   kappa_1 = k_1 - K_1,                   k_1 = a_2,1 . a_3 (Eq. 38)
//   kappa_2 = -a_1,1.a_3 + A_1,1.A_3,      kappa_3 = a_1,1.a_2 - A_1,1.A_2   (= a k_alpha - A K_alpha)
// Stored energy per unit xi (this is the energy whose variation is exactly Eq. 46):
//   Pi = int [ EF eps11^2 / (2 A^2) + G I_t kappa_1^2 / (2 A) + E I_2 kappa_2^2 / (2 A^2)
//            + E I_3 kappa_3^2 / (2 A^2) ] J_B dxi,    J_B = sqrt(A),
// i.e. Eq. 46 with N = EF eps11 / A^2, M^1 = G I_t kappa_1 / A, M^alpha = E I_alpha kappa_alpha / A^2
// (Eq. 47 with the constitutive metric taken in the reference configuration, which makes the
// formulation hyperelastic). Per unit reference arc length this is the classical
// EF e^2/2 + G I_t theta'^2/2 + E I (curvature change)^2/2 with e = eps11/A, theta' = kappa_1/sqrt(A),
// curvature change = kappa_alpha / A.
#include <Eigen/Core>
#include <vector>

namespace fibrane::beam {

struct BeamSection {  // Eqs. 47-48
  double young = 0, shear = 0, area = 0;
  double inertia2 = 0;  // I_zeta_zeta, multiplies kappa_2 (bending about a_2)
  double inertia3 = 0;  // I_eta_eta, multiplies kappa_3 (bending about a_3)
  double torsion = 0;   // I_t
  static BeamSection circular(double young, double poisson, double radius);
  static BeamSection general(double young, double poisson, double area, double i2, double i3, double it);
};

using BasisDerivs = Eigen::Matrix<double, 3, Eigen::Dynamic>;  // rows R, R_xi, R_xixi; one column per CP
using BeamDofs = Eigen::Matrix<double, 4, Eigen::Dynamic>;     // rows x, y, z, phi (current), per CP

struct BeamPointState {
  // Original undeformed configuration (never changed by updates).
  double ref_metric = 1.0;     // A = A_1.A_1
  double ref_torsion = 0.0;    // K_1 = A_2,1 . A_3 (per unit xi)
  double ref_bend2 = 0.0;      // A_1,1 . A_3  (= -A K_2)
  double ref_bend3 = 0.0;      // A_1,1 . A_2  (=  A K_3)
  // Frame reference of the smallest-rotation map (Eq. 34) and its derivative along xi.
  Eigen::Vector3d frame_t{1, 0, 0}, frame_d2{0, 1, 0}, frame_d3{0, 0, 1};
  Eigen::Vector3d frame_t_xi = Eigen::Vector3d::Zero();
  Eigen::Vector3d frame_d2_xi = Eigen::Vector3d::Zero();
  Eigen::Vector3d frame_d3_xi = Eigen::Vector3d::Zero();
  // Interpolated twist (and its xi-derivative) at which the frame reference was taken; the SR map is
  // rotated by phi - twist_offset.
  double twist_offset = 0.0, twist_offset_xi = 0.0;
};

// State of the undeformed configuration at one point. X holds the reference control points (3 x n).
// A2 is the projection of `a2_reference` onto the normal plane of T; a zero vector selects the global
// axis least aligned with T. Throws InputError if a2_reference is parallel to the tangent.
BeamPointState make_point_state(const BasisDerivs& R, const Eigen::Matrix3Xd& X,
                                const Eigen::Vector3d& a2_reference);

// States for the quadrature points of one curve, given in order of increasing xi (basis and the
// matching control points of each point's element). Non-zero `a2_reference`: as make_point_state.
// Zero: rotation-minimising frame propagated from the start by the double-reflection method
// (K_1 = 0 by construction), starting from the global axis least aligned with the first tangent.
std::vector<BeamPointState> make_curve_point_states(const std::vector<BasisDerivs>& basis,
                                                    const std::vector<Eigen::Matrix3Xd>& control_points,
                                                    const Eigen::Vector3d& a2_reference);

// Adds weight * Pi-density (energy), weight * dPi/dq (residual, Eqs. 46, 53) and weight * d2Pi/dq2
// (tangent, App. B) to the non-null outputs (sized 4n, or empty to be created zeroed).
void add_beam_point(const BeamSection& s, const BasisDerivs& R, const BeamDofs& q, const BeamPointState& st,
                    double weight, double* energy, Eigen::VectorXd* residual, Eigen::MatrixXd* tangent);

// Incremental update after a converged step: the frame reference becomes the current triad.
// Leaves the energy and the twist part of the residual unchanged (see tests for what else is kept).
void update_point_state(BeamPointState& st, const BasisDerivs& R, const BeamDofs& q);

// Fixed spatial point moment M (Eq. 54): adds -delta W_ext to residual and its derivative (B8-B9)
// to tangent (non-symmetric in general).
void add_point_moment(const Eigen::Vector3d& M, const BasisDerivs& R, const BeamDofs& q,
                      const BeamPointState& st, Eigen::VectorXd* residual, Eigen::MatrixXd* tangent);

// Follower point moment with components m = (m1, m2, m3) in the current triad (t, a2, a3).
void add_follower_point_moment(const Eigen::Vector3d& m, const BasisDerivs& R, const BeamDofs& q,
                               const BeamPointState& st, Eigen::VectorXd* residual,
                               Eigen::MatrixXd* tangent);

// Output quantities in physical units (per unit reference arc length): eps11 = (a - A)/(2A),
// kappa[0] = kappa_1/sqrt(A) (twist rate), kappa[1..2] = kappa_alpha / A (curvature changes);
// N = EF eps11, M[0] = G I_t kappa[0] (torque), M[1] = E I_2 kappa[1], M[2] = E I_3 kappa[2].
struct BeamPointOutput {
  Eigen::Vector3d r, t, a2, a3;
  double eps11, kappa[3], N, M[3];
};
BeamPointOutput evaluate_point(const BeamSection& s, const BasisDerivs& R, const BeamDofs& q,
                               const BeamPointState& st);

}  // namespace fibrane::beam
