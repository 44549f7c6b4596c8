#pragma once
// Newmark kinematics and the parameters of the generalized-alpha family of time integrators, as pure
// relations on vectors (or scalars). The time stepping that uses them is solve/generalized_alpha.
//
// Equation of motion, full vectors (constrained DOFs included), r = f_int - f_ext as everywhere in fibrane:
//   M a + C v + r(u, t) = R   (R: support reactions, non-zero at constrained DOFs only).
// Generalized-alpha (Chung & Hulbert 1993, J. Appl. Mech. 60:371-375) enforces it at weighted states
//   x_{n+1-alpha} = (1 - alpha) x_{n+1} + alpha x_n,
// with the non-inertial forces averaged between the end points ("trapezoidal-like"), so that r is
// evaluated only at the end points, never at an intermediate state (the form of generalized-alpha used
// for non-linear structural dynamics by Kuhl & Crisfield 1999, IJNME 45:569-599; the method's accuracy
// and stability for non-linear problems: Erlicher, Bonaventura & Bursi 2002, Comput. Mech. 28:83-104):
//   M a_{n+1-alpha_m} + C v_{n+1-alpha_f} + (1 - alpha_f) r(u_{n+1}, t_{n+1}) + alpha_f r(u_n, t_n) = R_w.
// For a linear r = K u - f(t) this is Chung & Hulbert's scheme with the load interpolated linearly in time,
// so their amplification matrix, spectral radius and stability conditions hold unchanged.
#include <Eigen/Dense>

namespace fibrane::solve {

// Parameters of the generalized-alpha method: alpha_m weights the inertia term, alpha_f the others; beta
// and gamma are Newmark's. A default-constructed set is the trapezoidal rule (Newmark's average
// acceleration): alpha_m = alpha_f = 0, beta = 1/4, gamma = 1/2.
struct GeneralizedAlphaParameters {
  double alpha_m = 0.0, alpha_f = 0.0, beta = 0.25, gamma = 0.5;

  // Chung & Hulbert's optimal one-parameter set for a spectral radius rho_inf in [0, 1] at
  // omega dt -> infinity (their Eqs. (17), (20), (25)):
  //   alpha_m = (2 rho - 1) / (rho + 1), alpha_f = rho / (rho + 1),
  //   gamma = 1/2 - alpha_m + alpha_f,   beta = (1 - alpha_m + alpha_f)^2 / 4.
  // rho_inf = 1 gives alpha_m = alpha_f = 1/2, beta = 1/4, gamma = 1/2: for linear problems the
  // trapezoidal rule with the balance averaged over t_n and t_{n+1}. The trapezoidal rule itself is
  // trapezoidal(). Throws InputError for rho_inf outside [0, 1].
  static GeneralizedAlphaParameters chung_hulbert(double rho_inf);
  // alpha_m = alpha_f = 0, beta = 1/4, gamma = 1/2: equilibrium at t_{n+1}, no numerical dissipation.
  static GeneralizedAlphaParameters trapezoidal() { return {}; }
};

// Throws InputError unless the set is second-order accurate, gamma = 1/2 - alpha_m + alpha_f (to 1e-12),
// and unconditionally stable for linear problems, alpha_m <= alpha_f <= 1/2 and
// beta >= 1/4 + (alpha_f - alpha_m)/2 (Chung & Hulbert 1993, Sec. 3).
void check_parameters(const GeneralizedAlphaParameters& p);

// Newmark's relations (Newmark 1959): the acceleration at t_{n+1} = t_n + dt from the state at t_n and
//   u_{n+1}:  a_{n+1} = (u_{n+1} - u_n - dt v_n) / (beta dt^2) - (1 / (2 beta) - 1) a_n.
template <class V>
V newmark_acceleration(const GeneralizedAlphaParameters& p, double dt, const V& u_n, const V& v_n, const V& a_n,
                       const V& u) {
  return (u - u_n - dt * v_n) / (p.beta * dt * dt) - (0.5 / p.beta - 1.0) * a_n;
}

// v_{n+1} = v_n + dt ((1 - gamma) a_n + gamma a_{n+1}).
template <class V>
V newmark_velocity(const GeneralizedAlphaParameters& p, double dt, const V& v_n, const V& a_n, const V& a) {
  return v_n + dt * ((1.0 - p.gamma) * a_n + p.gamma * a);
}

// The weighted state x_{n+1-alpha} = (1 - alpha) x_{n+1} + alpha x_n.
template <class V>
V weighted(double alpha, const V& x_n, const V& x) {
  return (1.0 - alpha) * x + alpha * x_n;
}

// d/du_{n+1} of a_{n+1-alpha_m} / (1 - alpha_f):  c = (1 - alpha_m) / (beta dt^2 (1 - alpha_f)).
inline double inertia_tangent_factor(const GeneralizedAlphaParameters& p, double dt) {
  return (1.0 - p.alpha_m) / (p.beta * dt * dt * (1.0 - p.alpha_f));
}

// d/du_{n+1} of v_{n+1-alpha_f} / (1 - alpha_f):  gamma / (beta dt).
inline double damping_tangent_factor(const GeneralizedAlphaParameters& p, double dt) {
  return p.gamma / (p.beta * dt);
}

// The acceleration at t_{n+1} to second order from the method's acceleration variable: a_n approximates
// the acceleration at t_n + (alpha_m - alpha_f) dt, not at t_n (Arnold & Bruls 2007, Multibody Syst. Dyn.
// 18:185-202; from (1 - alpha_m) a_{n+1} + alpha_m a_n = (1 - alpha_f) f_{n+1} + alpha_f f_n for a'' = f(t)),
// so a_{n+1} - (alpha_m - alpha_f) (a_{n+1} - a_n) is the one at t_{n+1}. Equal to
// a_{n+1} for the trapezoidal rule and rho_inf = 1. Used for reactions, not for the time stepping.
template <class V>
V acceleration_at_end(const GeneralizedAlphaParameters& p, const V& a_n, const V& a) {
  const double shift = p.alpha_m - p.alpha_f;
  return (1.0 - shift) * a + shift * a_n;
}

// One step of the generalized-alpha method as a TransientSystem sees it, on FULL vectors (DOF numbering of
// the model). The inertia and damping terms of the step's residual, divided by (1 - alpha_f), are M w with
//   w(u_{n+1}) = (a_w + a_M v_w) / (1 - alpha_f)
// (weighted acceleration a_w and velocity v_w as in solve/generalized_alpha.hpp, C = a_M M). w is affine
// in u_{n+1}, DOF by DOF, with one slope for all DOFs:
//   w(u) = w_ref + mass_factor (u - u_ref),
// u_ref = h_n + g(t_{n+1}) being the displacement at which the free part has not moved since t_n and
// w_ref = w(u_ref). The pointers refer to the method's vectors and stay valid while the step is set.
struct StepKinematics {
  double t_n = 0.0, t = 0.0, dt = 0.0;  // the step runs from t_n to t = t_n + dt
  // dw/du = (1 - alpha_m) / (beta dt^2 (1 - alpha_f)) + a_M gamma / (beta dt): the factor of M in the
  // step's tangent.
  double mass_factor = 0.0;
  const Eigen::VectorXd* u_ref = nullptr;
  const Eigen::VectorXd* w_ref = nullptr;

  // w at one DOF for u_{n+1} = u there (element-by-element assembly).
  double inertia(int dof, double u) const { return (*w_ref)[dof] + mass_factor * (u - (*u_ref)[dof]); }
  // w for the full vector u_{n+1}.
  Eigen::VectorXd inertia(const Eigen::VectorXd& u) const { return *w_ref + mass_factor * (u - *u_ref); }
};

}  // namespace fibrane::solve
