#pragma once
// Internal: kinematics and strains of the beam axis at one point as functions of the local
// quantities w = [a_1, a_1,1, phi_rel, phi_rel,1]; templated on double or Jet (common/jet.hpp).
#include "beam/beam.hpp"
#include "common/jet.hpp"

namespace fibrane::beam::detail {

// The beam energy density at a point depends on the element DOFs only through 8 local quantities
// w = [a_1 (3), a_1,1 (3), phi, phi_,1], linear in the DOFs: residual and tangent are B^T g, B^T H B.
constexpr int kLocalVars = 8;
using Jet = ad::Jet<kLocalVars>;
using ad::chain;
using ad::cos;
using ad::cross;
using ad::dot;
using ad::sin;
using ad::sqrt;
using ad::to_eigen;
using ad::to_vec3;
using ad::value;
using ad::Vec3;

template <class S>
struct LocalVars {
  Vec3<S> a1, a11;  // a_1 = r_,1 and a_1,1 = r_,11
  S phi, phi_xi;    // twist relative to the frame reference and its xi-derivative
};

template <class S>
struct Kinematics {
  S metric;                        // a = a_1.a_1
  Vec3<S> t, t_xi, a2, a3, a2_xi, a3_xi;
  S torsion;                       // k_1 = a_2,1 . a_3 (Eq. 38)
};

template <class S>
struct Strains {
  S eps11, kappa1, kappa2, kappa3;  // Eq. 43 (see beam.hpp for the exact definitions)
};

// The 8 local quantities from the element DOFs (linear in q).
inline LocalVars<double> local_vars(const BasisDerivs& R, const BeamDofs& q, const BeamPointState& st) {
  const Eigen::Vector3d a1 = q.topRows<3>() * R.row(1).transpose();
  const Eigen::Vector3d a11 = q.topRows<3>() * R.row(2).transpose();
  return {{a1.x(), a1.y(), a1.z()},
          {a11.x(), a11.y(), a11.z()},
          q.row(3).dot(R.row(0)) - st.twist_offset,
          q.row(3).dot(R.row(1)) - st.twist_offset_xi};
}

inline LocalVars<Jet> seed(const LocalVars<double>& w) {
  return {{Jet::variable(w.a1.x, 0), Jet::variable(w.a1.y, 1), Jet::variable(w.a1.z, 2)},
          {Jet::variable(w.a11.x, 3), Jet::variable(w.a11.y, 4), Jet::variable(w.a11.z, 5)},
          Jet::variable(w.phi, 6),
          Jet::variable(w.phi_xi, 7)};
}

// Smallest-rotation image of a frame director D (derivative D_xi) onto the plane normal to t (Eq. 34),
// together with its xi-derivative.
template <class S>
void smallest_rotation(const Vec3<S>& t, const Vec3<S>& t_xi, const BeamPointState& st,
                       const Eigen::Vector3d& D, const Eigen::Vector3d& D_xi, Vec3<S>& out,
                       Vec3<S>& out_xi) {
  const Vec3<double> T = to_vec3<double>(st.frame_t), T_xi = to_vec3<double>(st.frame_t_xi);
  const Vec3<double> d = to_vec3<double>(D), d_xi = to_vec3<double>(D_xi);
  const S tT = 1.0 + dot(T, t);                     // t_T in Eq. 34
  const S tT_xi = dot(T_xi, t) + dot(T, t_xi);
  const S dt = dot(d, t);
  const S dt_xi = dot(d_xi, t) + dot(d, t_xi);
  const Vec3<S> sum = t + T, sum_xi = t_xi + T_xi;
  const S ratio = dt / tT;
  const S ratio_xi = dt_xi / tT - dt * tT_xi / (tT * tT);
  out = d - ratio * sum;
  out_xi = d_xi - ratio_xi * sum - ratio * sum_xi;
}

template <class S>
Kinematics<S> kinematics(const LocalVars<S>& w, const BeamPointState& st) {
  Kinematics<S> k;
  k.metric = dot(w.a1, w.a1);
  const S g = sqrt(k.metric);  // j_B, Eq. 32
  k.t = (1.0 / g) * w.a1;
  k.t_xi = (1.0 / g) * (w.a11 - dot(k.t, w.a11) * k.t);
  Vec3<S> a2s, a2s_xi, a3s, a3s_xi;
  smallest_rotation(k.t, k.t_xi, st, st.frame_d2, st.frame_d2_xi, a2s, a2s_xi);
  smallest_rotation(k.t, k.t_xi, st, st.frame_d3, st.frame_d3_xi, a3s, a3s_xi);
  const S c = cos(w.phi), s = sin(w.phi);  // Eq. 35
  k.a2 = c * a2s + s * a3s;
  k.a3 = (-s) * a2s + c * a3s;
  k.a2_xi = w.phi_xi * k.a3 + c * a2s_xi + s * a3s_xi;
  k.a3_xi = (-w.phi_xi) * k.a2 + c * a3s_xi - s * a2s_xi;
  k.torsion = dot(a2s_xi, a3s) + w.phi_xi;  // Eq. 38: k_1 = a^SR_2,1 . a^SR_3 + phi_,1
  return k;
}

template <class S>
Strains<S> strains(const LocalVars<S>& w, const Kinematics<S>& k, const BeamPointState& st) {
  return {0.5 * (k.metric - st.ref_metric), k.torsion - st.ref_torsion,
          st.ref_bend2 - dot(w.a11, k.a3), dot(w.a11, k.a2) - st.ref_bend3};
}

// Energy per unit xi (J_B included), see beam.hpp.
template <class S>
S energy_density(const BeamSection& sec, const Strains<S>& e, const BeamPointState& st) {
  const double A = st.ref_metric, A2 = A * A;
  const S sum = (sec.young * sec.area / A2) * (e.eps11 * e.eps11) +
                (sec.shear * sec.torsion / A) * (e.kappa1 * e.kappa1) +
                (sec.young * sec.inertia2 / A2) * (e.kappa2 * e.kappa2) +
                (sec.young * sec.inertia3 / A2) * (e.kappa3 * e.kappa3);
  return (0.5 * std::sqrt(A)) * sum;
}

// B = dw/dq (8 x 4n), rows ordered as the Jet variables.
inline Eigen::MatrixXd local_map(const BasisDerivs& R) {
  const Eigen::Index n = R.cols();
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(kLocalVars, 4 * n);
  for (Eigen::Index j = 0; j < n; ++j) {
    for (int c = 0; c < 3; ++c) {
      B(c, 4 * j + c) = R(1, j);
      B(3 + c, 4 * j + c) = R(2, j);
    }
    B(6, 4 * j + 3) = R(0, j);
    B(7, 4 * j + 3) = R(1, j);
  }
  return B;
}

}  // namespace fibrane::beam::detail
