#pragma once
// Soft-minimum distance of a beam point to a region of the shell: a regularisation of the closest-point
// distance (Eq. 64) for beam points where the closest point is (nearly) not unique. Not in the paper.
//
// Why: where the shell is bent around a beam point at a radius close to the distance (a fiber's end
// pressed into a soft shell, which then wraps around it), |r_B - r_S(theta)| is flat to ~0.1 % over a
// region of the shell and has several shallow local minima. The closest point then jumps between them
// under tiny changes of the state, the residual of the SBS potential phi(d) is discontinuous there, and
// Newton cycles (docs/interaction.md, "Soft minimum at a non-unique closest point").
//
// What: with beta = 1 / (width x d_ref), the Gibbs integral over the shell region W (reference area
//   dA_0, the mirror images of the modelled part included)
//     I(x) = integral_W exp(-beta |r_B - r_S(theta)|) dA_0
// is a smooth function of the state however many minima the distance has, and tends to the closest
// point's exp(-beta d) times the area of its neighbourhood. The soft distance D is the distance of an
// infinite flat plate with the same integral,
//     I_plate(D) = 2 pi exp(-beta D) (D / beta + 1 / beta^2)   (polar coordinates about the foot point),
// so D = d exactly for a flat shell, and D < d by about (width d / 2) |ln(lambda_1 lambda_2)| for a shell
// curved toward the point with relative curvatures lambda_a = 1 - d kappa_a (ShellProximity's
// relative_curvature): where the shell wraps around the point (lambda -> 0) more of it is near, and the
// point sees it. The RF2 potential phi(D, 1) replaces phi(d, 1) at such points.
//
// The kernel is a pure function of the beam point's basis and control points, and of the window: a
// fixed set of material quadrature points of the shell (fixed during a load step, so the residual is
// smooth in the state).
#include <Eigen/Dense>
#include <vector>

#include "laws/interaction_law.hpp"
#include "spline/surface.hpp"

namespace fibrane::interaction {

// A rigid image r -> S r + c of the modelled shell: the identity, or the mirror image across a symmetry
// plane (or two).
struct ShellImage {
  Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
};

// A mirror-symmetry plane of the modelled part: x[axis] = offset.
struct MirrorPlane {
  int axis = 0;
  double offset = 0;
};

// Material quadrature points of a shell region, their basis functions over the window's control points
// (local indices into `control_points`), and the images each point is counted in.
struct SoftWindow {
  std::vector<int> control_points;  // global control point indices of the shell
  int basis_size = 0;               // non-zero functions per sample
  std::vector<double> weight;       // Gauss weight x reference area element, per sample
  std::vector<int> local;           // sample-major: basis_size local control point indices per sample
  std::vector<double> basis;        // sample-major: their values
  // Samples of the j-th shell element in the window: [element_begin[j], element_begin[j + 1]); they share
  // their local control point indices (in the same order).
  std::vector<int> element_begin{0};
  std::vector<ShellImage> images;   // identity first
  Eigen::Vector2d half_extent = Eigen::Vector2d::Zero();  // the parameter half-widths asked for
  int num_samples() const { return static_cast<int>(weight.size()); }
};

// The window's size for Gibbs width `width` (relative to d_ref): it must hold every shell point whose Gibbs
// weight exp(-beta (d - d_min)) is above e^-45 (below round-off of the sum): on a flat plate the radius
// d_ref sqrt(90 width), plus the arc over which a shell wrapped around the point stays at nearly the same
// distance (+-0.16 d at the bending example's 32x8x8 stall): half-width d_ref (sqrt(90 width) + 0.2).
// Quadrature cells: half the integrand's width d_ref sqrt(width) (flat plate to 1e-15 d, tests).
double soft_window_half_width(double width, double d_ref);
double soft_window_cell(double width, double d_ref);

// The window: every element of `surface` whose parameter box meets the box of reference half-width
// `half_width` (in each parametric direction, measured with the reference metric at `centre`) around
// the parameter point `centre`, each split into sub-cells no larger than `cell` (reference length), of
// which those that meet the box are kept, each with a 3 x 3 Gauss rule. Images: one per subset of the
// mirror planes within 2 half_width of the centre.
SoftWindow make_soft_window(const spline::NurbsSurface& surface, const Eigen::Vector2d& centre, double half_width,
                            double cell, const std::vector<MirrorPlane>& mirrors);

// D with its gradient and Hessian with respect to the local DOFs
// [beam CP_0: x, y, z, phi, ..., window CP_0: x, y, z, ...] (twist entries zero).
struct SoftDistance {
  double distance = 0;
  double nearest = 0;                                  // the smallest sample distance (for output)
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();  // dD/dr_B: the mean unit vector from the shell
  Eigen::VectorXd gradient;
  Eigen::MatrixXd hessian;  // empty unless asked for
};

SoftDistance soft_distance(double beta, const Eigen::RowVectorXd& beam_basis, const Eigen::Matrix3Xd& beam_x,
                           const SoftWindow& window, const Eigen::Matrix3Xd& window_x, bool with_hessian);

// RF2 with the soft distance shifted by a constant: adds weight phi(D + offset, 1) to *energy, its
// gradient to *residual and its Hessian to *tangent (each may be null; residual / tangent empty or of
// the local size, accumulated). Returns D + offset; `force` gets the force per length on the beam's side
// in the sign convention of add_sbs_point (phi_,d dD/dr_B). Throws std::domain_error if the law rejects
// D + offset (overlap). (The offset lets a point switch from d to the soft distance without a jump: the
// caller sets it to d - D at the state where it switches.)
// With `support` given, *residual and *tangent are instead overwritten with their entries on the support:
// the local DOFs listed in *support (the beam's and those of the window control points under a sample of
// non-negligible weight; all others are zero), which is what an assembler needs.
// With `rank_one` given as well as `tangent`, the Hessian's dense term weight (phi_dd a^2 + phi_d c) m m^T
// is left out of *tangent and given as its coefficient and m (on the local DOFs, or on the support with
// `support`): what remains couples the window's control points only within its elements.
struct RankOneTerm {
  double coefficient = 0;
  Eigen::VectorXd vector;
};
double add_soft_rf2_point(const laws::InteractionLaw& law, double beta, const Eigen::RowVectorXd& beam_basis,
                          const Eigen::Matrix3Xd& beam_x, const SoftWindow& window, const Eigen::Matrix3Xd& window_x,
                          double offset, double weight, double* energy, Eigen::VectorXd* residual,
                          Eigen::MatrixXd* tangent, Eigen::Vector3d* force = nullptr,
                          std::vector<int>* support = nullptr, RankOneTerm* rank_one = nullptr);

}  // namespace fibrane::interaction
