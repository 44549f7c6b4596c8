#pragma once
// Surrogate beam-shell (SBS) interaction at ONE beam quadrature point paired with its closest point on
// the shell (paper Sec. 2.2, Eq. 5; Sec. 5, Eqs. 62-78; App. C-E). Pure function of the bases and the
// current control points at that pair; the closest-point parameters theta-hat must already satisfy the
// orthogonality condition (63) (ShellProximity::project).
#include <Eigen/Dense>

#include "laws/interaction_law.hpp"
#include "shell/kl_shell.hpp"

namespace fibrane::interaction {

// FF: phi(d, cos a) with its complete variation, Eq. (78). RF1: residual Eq. (73) with phi_,d(d, cos a)
// (the variation of the angle is dropped). RF2: phi(d, 1), Eq. (73).
enum class Formulation { FF, RF1, RF2 };
// Tangent used with FF: the RF1 tangent (as the paper, App. E) or the exact Hessian of the energy.
enum class FfTangent { rf1, exact };

struct PairPoint {
  Eigen::Matrix<double, 2, Eigen::Dynamic> beam_basis;    // rows N, N_xi at the beam point; nB columns
  Eigen::Matrix3Xd beam_x;                                // current beam control points, 3 x nB
  shell::BasisDerivs shell_basis;                         // at theta-hat: R, R_1, R_2, R_11, R_12, R_22
  Eigen::Matrix<double, 4, Eigen::Dynamic> shell_basis3;  // R_111, R_112, R_122, R_222 (FF exact only)
  Eigen::Matrix3Xd shell_x;                               // current shell control points, 3 x nS
  double weight = 0;  // Gauss weight x parent Jacobian x REFERENCE beam Jacobian J_B (Eq. 5)
};

struct PairResult {
  double energy = 0;     // phi per unit (reference) length at this point (not multiplied by weight)
  double distance = 0;   // d (Eq. 64)
  double cos_alpha = 1;  // cos a = sqrt(1 - t_n^2) (Eq. 70), also reported for RF2
  // Per unit length, the paper's sign convention (Eq. 73: delta phi = f . delta u_B + ...): FF f + f_C
  // (Eqs. 73, 76), RF1/RF2 f = phi_,d n. The force the shell exerts on the beam is -force.
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
};

// Adds weight * phi to *energy, the residual dPi/dq to *residual and its tangent to *tangent (each may
// be null). DOF order: [beam CP_0: x, y, z, phi, ..., beam CP_{nB-1}: x, y, z, phi, shell CP_0: x, y, z,
// ..., shell CP_{nS-1}: x, y, z]; the twist entries stay zero. residual / tangent are either empty
// (then sized and zeroed here) or already of size n = 4 nB + 3 nS (accumulated into).
//   RF2: residual = weight phi_,d(d,1) d_,q (exact gradient of weight phi(d,1)); tangent its Hessian
//        (App. D, symmetric).
//   RF1: residual = weight phi_,d(d,c) d_,q (Eq. 73); tangent its exact derivative (App. E: K_RF1 + K_RF2).
//   FF:  residual = exact gradient of weight phi(d, c) (Eq. 78); tangent the RF1 one or the exact Hessian
//        (needs shell_basis3: theta-hat's second variation involves the surface's third derivatives).
// Throws std::invalid_argument on inconsistent sizes, std::domain_error if d <= 0 or the law rejects
// (d, c) (overlap).
PairResult add_sbs_point(const laws::InteractionLaw& law, Formulation f, FfTangent ff_tangent,
                         const PairPoint& p, double* energy, Eigen::VectorXd* residual,
                         Eigen::MatrixXd* tangent);

}  // namespace fibrane::interaction
