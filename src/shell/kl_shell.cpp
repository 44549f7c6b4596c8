// Point kernel of the Kirchhoff-Love shell: energy (Eqs. 25-29), internal virtual work (Eqs. 28, 30, 31)
// and its linearization (Appendix A), in covariant components. The material (material.hpp) gives the
// energy density, N, M and the blocks dN/de, dN/dk, dM/de, dM/dk; the kernel adds the geometry.
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
//
// Material part of block (A, B) (Eq. A1 with a general material), m_A := de/du_A (3 x 3, columns per
// strain), dk/du_A = c_A n^T:
//   m_A dN/de m_B^T + (c_A . dM/dk c_B) n n^T + m_A dN/dk c_B n^T + n (dM/de^T c_A)^T m_B^T,
// the last two (membrane-bending coupling) only for materials whose cross blocks do not vanish.
#include <stdexcept>

#include "shell/kl_shell.hpp"
#include "shell/material.hpp"
#include "shell/surface_metric.hpp"

// Portable binaries with a fast path: GCC compiles the kernel twice and picks the AVX2 version at load
// time where the processor has it (x86-64 only; elsewhere one generic version).
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(__AVX2__)
#define FIBRANE_SIMD_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define FIBRANE_SIMD_CLONES
#endif

namespace fibrane::shell {
namespace {

// First derivatives of the Voigt strains with respect to the displacement of one control point.
struct NodeTerms {
  double r1, r2;                   // R_1A, R_2A
  Eigen::Matrix3d membrane;        // columns: d(E11, E22, 2E12)/du_A
  Eigen::Vector3d bending;         // (c11, c22, 2 c12): d(K11, K22, 2K12)/du_A = bending * n^T
  double moment_work;              // M^ab c_abA, summed with the Voigt factor 2 on 12
};

// The node terms the tangent needs of the column node B, as arrays over B (see ElementTangent).
struct ColumnTerms {
  double r1[kMaxShellNodes], r2[kMaxShellNodes];
  double membrane[3][3][kMaxShellNodes];  // [strain k][component j][B] = d(strain k)/du_B,j
  double bending[3][kMaxShellNodes];
  double v[3][kMaxShellNodes];            // v_B = R_1B g^1 + R_2B g^2
  double moment_work[kMaxShellNodes];
};

void check_sizes(const BasisDerivs& R, const Eigen::Matrix3Xd& X, const Eigen::Matrix3Xd& x,
                 const Eigen::VectorXd* residual, Eigen::Index tangent_nodes) {
  const Eigen::Index nen = R.cols(), ndof = 3 * nen;
  if (X.cols() != nen || x.cols() != nen)
    throw std::invalid_argument("add_shell_point: basis and control points disagree on the node count");
  if (nen > kMaxShellNodes) throw std::invalid_argument("add_shell_point: too many control points");
  if (residual && residual->size() != ndof)
    throw std::invalid_argument("add_shell_point: residual must have size 3 * nen");
  if (tangent_nodes >= 0 && tangent_nodes != nen)
    throw std::invalid_argument("add_shell_point: tangent must have size 3 nen x 3 nen");
}

// The tangent's material and geometric parts for every node pair B >= A (Appendix A), accumulated into
// `tangent`. kCoupled adds the membrane-bending coupling blocks; the uncoupled instance (SVK) carries no
// trace of them. Always inlined, so that it is compiled for each target of add_shell_point.
template <bool kCoupled>
[[gnu::always_inline]] inline void accumulate_tangent(const NodeTerms* nodes, int nen, const SurfaceMetric& cur,
                                                      double scale, const SectionResponse& material,
                                                      ElementTangent& tangent) {
  // Local copies: `material` was written through a pointer, so its members would be reloaded after every
  // store into the tangent.
  const Eigen::Vector3d N = material.N, M = material.M;
  const Eigen::Matrix3d dN_de = material.dN_de, dM_dk = material.dM_dk;
  Eigen::Matrix3d dN_dk, dM_de;
  if constexpr (kCoupled) dN_dk = material.dN_dk, dM_de = material.dM_de;
  const Eigen::Vector3d& n = cur.normal;
  ColumnTerms c;
  for (int B = 0; B < nen; ++B) {
    const NodeTerms& t = nodes[B];
    c.r1[B] = t.r1;
    c.r2[B] = t.r2;
    for (int a = 0; a < 3; ++a) {
      for (int j = 0; j < 3; ++j) c.membrane[a][j][B] = t.membrane(j, a);
      c.bending[a][B] = t.bending[a];
      c.v[a][B] = t.r1 * cur.dual1[a] + t.r2 * cur.dual2[a];
    }
    c.moment_work[B] = t.moment_work;
  }
  // Moment-weighted curvature M^ab b_ab of the second variation of b_ab (Voigt factor 2 on 12).
  const double moment_curvature = M[0] * cur.curvature[0] + M[1] * cur.curvature[1] +
                                  2.0 * M[2] * cur.curvature[2];
  double normal[kMaxShellNodes] = {}, isotropic[kMaxShellNodes] = {};
  for (int A = 0; A < nen; ++A) {
    const NodeTerms& a = nodes[A];
    // Row-node factors of block (A, B), each times `scale`:
    //   material part dN/du_A . dE/du_B + dM/du_A . dK/du_B (Eq. A1), the bending part along n n^T;
    //   geometric part N^ab d2E_ab (Eq. A2): an isotropic block;
    //   geometric part M^ab d2b_ab (Eq. A8 regrouped): -b_ab (v_A . v_B) n n^T - c_abA v_B n^T - c_abB n v_A^T.
    Eigen::Matrix3d ms = scale * a.membrane * dN_de;  // ms(i, k) = scale d(N^k)/du_A,i via e
    const Eigen::Vector3d bs = scale * (dM_dk * a.bending);
    // Coupling (Eq. A1, cross blocks): n (dM/de^T c_A)^T joins the factors of m_B; mb(i, l) = scale
    // (m_A dN/dk)(i, l) multiplies c_B,l n_j.
    Eigen::Matrix3d mb;
    if constexpr (kCoupled) {
      ms.noalias() += n * (scale * (dM_de.transpose() * a.bending)).transpose();
      mb.noalias() = scale * a.membrane * dN_dk;
    }
    const double va[3] = {c.v[0][A], c.v[1][A], c.v[2][A]};
    const double mv[3] = {scale * moment_curvature * va[0], scale * moment_curvature * va[1],
                          scale * moment_curvature * va[2]};
    const double p1 = scale * (N[0] * a.r1 + N[2] * a.r2), p2 = scale * (N[1] * a.r2 + N[2] * a.r1);
    // The scalar factors of n n^T and of the identity for every column node B >= A, once per row node.
    for (int B = A; B < nen; ++B) {
      normal[B] = bs[0] * c.bending[0][B] + bs[1] * c.bending[1][B] + bs[2] * c.bending[2][B] -
                  (mv[0] * c.v[0][B] + mv[1] * c.v[1][B] + mv[2] * c.v[2][B]);
      isotropic[B] = p1 * c.r1[B] + p2 * c.r2[B];
    }
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const double nn = n[i] * n[j];
        const double by_v = -scale * a.moment_work * n[j];  // times v_B,i
        const double by_moment = -scale * n[i] * va[j];     // times M^ab c_abB
        const double ms0 = ms(i, 0), ms1 = ms(i, 1), ms2 = ms(i, 2);
        double* __restrict out = tangent.row(A, i, j);
        const double* __restrict m0 = c.membrane[0][j];
        const double* __restrict m1 = c.membrane[1][j];
        const double* __restrict m2 = c.membrane[2][j];
        const double* __restrict vi = c.v[i];
        const double* __restrict mw = c.moment_work;
        for (int B = A; B < nen; ++B)
          out[B] += ms0 * m0[B] + ms1 * m1[B] + ms2 * m2[B] + nn * normal[B] + by_v * vi[B] + by_moment * mw[B];
        if constexpr (kCoupled) {
          const double mb0 = n[j] * mb(i, 0), mb1 = n[j] * mb(i, 1), mb2 = n[j] * mb(i, 2);
          const double* __restrict c0 = c.bending[0];
          const double* __restrict c1 = c.bending[1];
          const double* __restrict c2 = c.bending[2];
          for (int B = A; B < nen; ++B) out[B] += mb0 * c0[B] + mb1 * c1[B] + mb2 * c2[B];
        }
        if (i == j)
          for (int B = A; B < nen; ++B) out[B] += isotropic[B];
      }
  }
}

}  // namespace

void ElementTangent::reset(int nen) {
  nen_ = nen;
  data_.assign(static_cast<std::size_t>(9) * nen * nen, 0.0);
}

void ElementTangent::add_to(Eigen::MatrixXd& k) const {
  if (k.rows() != 3 * nen_ || k.cols() != 3 * nen_)
    throw std::invalid_argument("ElementTangent::add_to: matrix must have size 3 nen x 3 nen");
  for (int A = 0; A < nen_; ++A)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const double* from = row(A, i, j);
        k(3 * A + i, 3 * A + j) += from[A];
        for (int B = A + 1; B < nen_; ++B) {
          k(3 * A + i, 3 * B + j) += from[B];
          k(3 * B + j, 3 * A + i) += from[B];
        }
      }
}

FIBRANE_SIMD_CLONES void add_shell_point(const ShellSection& s, const BasisDerivs& R, const Eigen::Matrix3Xd& X,
                     const Eigen::Matrix3Xd& x, double weight, double* energy, Eigen::VectorXd* residual,
                     ElementTangent* tangent) {
  check_sizes(R, X, x, residual, tangent ? tangent->nodes() : -1);
  if (!s.material) throw std::invalid_argument("add_shell_point: the section has no material");
  const SurfaceMetric ref = surface_metric(R, X);
  const SurfaceMetric cur = surface_metric(R, x);
  const double scale = weight * ref.area_jacobian;  // dA = J_S dtheta1 dtheta2 (Eq. 28)
  const SectionResponse material = s.material->respond(ref, cur, s.thickness, tangent != nullptr);
  // Local copies: `material` was written through a pointer, so its members would be reloaded after every
  // store into the residual.
  const Eigen::Vector3d N = material.N;  // (N^11, N^22, N^12), Eqs. 28, 29
  const Eigen::Vector3d M = material.M;  // (M^11, M^22, M^12)

  if (energy) *energy += scale * material.energy;  // Eq. 25 integrated through the thickness
  if (!residual && !tangent) return;

  const Eigen::Vector3d& n = cur.normal;
  // Christoffel symbols Gamma^c_ab = g_a,b . g^c, one column per Voigt pair ab.
  Eigen::Matrix<double, 2, 3> gamma;
  gamma << cur.g11.dot(cur.dual1), cur.g22.dot(cur.dual1), cur.g12.dot(cur.dual1),
      cur.g11.dot(cur.dual2), cur.g22.dot(cur.dual2), cur.g12.dot(cur.dual2);

  const int nen = static_cast<int>(R.cols());
  NodeTerms nodes[kMaxShellNodes];
  for (int A = 0; A < nen; ++A) {
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
  if (material.coupled)
    accumulate_tangent<true>(nodes, nen, cur, scale, material, *tangent);
  else
    accumulate_tangent<false>(nodes, nen, cur, scale, material, *tangent);
}

void add_shell_point(const ShellSection& s, const BasisDerivs& R, const Eigen::Matrix3Xd& X,
                     const Eigen::Matrix3Xd& x, double weight, double* energy, Eigen::VectorXd* residual,
                     Eigen::MatrixXd* tangent) {
  if (!tangent) return add_shell_point(s, R, X, x, weight, energy, residual);
  const Eigen::Index ndof = 3 * R.cols();
  if (tangent->rows() != ndof || tangent->cols() != ndof)
    throw std::invalid_argument("add_shell_point: tangent must have size 3 nen x 3 nen");
  ElementTangent scratch;
  scratch.reset(static_cast<int>(R.cols()));
  add_shell_point(s, R, X, x, weight, energy, residual, &scratch);
  scratch.add_to(*tangent);
}

}  // namespace fibrane::shell
