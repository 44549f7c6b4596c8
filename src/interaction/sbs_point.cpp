#include "interaction/sbs_point.hpp"

#include <cmath>
#include <stdexcept>
#include <vector>

#include "common/jet.hpp"

namespace fibrane::interaction {
namespace {

// Local quantities, all linear in the DOFs q (z = L q), plus the two parameter increments of theta:
//   z = [r_B, a_1 = r_B,xi, r_S, g_1, g_2, g_11, g_12, g_22] (3 each) at theta-hat, then dtheta^1, dtheta^2.
// The pair energy depends on q only through these (g_ab enter through theta-hat's second variation).
constexpr int kZ = 24;
constexpr int kVars = kZ + 2;
constexpr int kRB = 0, kA1 = 3, kRS = 6, kG1 = 9, kG2 = 12, kG11 = 15, kG12 = 18, kG22 = 21, kTheta = 24;
using J = ad::Jet<kVars>;
using V = ad::Vec3<J>;

V variable(const Eigen::Vector3d& x, int first) {
  return {J::variable(x.x(), first), J::variable(x.y(), first + 1), J::variable(x.z(), first + 2)};
}
// a c for a constant vector c (cheaper than a jet product).
V times(const J& a, const Eigen::Vector3d& c) { return {c.x() * a, c.y() * a, c.z() * a}; }

// Distance d and s = cos^2 a = 1 - t_n^2 (Eq. 70) as jets over z: value, gradient and Hessian, with
// theta-hat eliminated through the orthogonality condition (63).
struct PairJets {
  J d, s;
};

PairJets pair_jets(const PairPoint& p, bool need_angle) {
  const Eigen::Vector3d rb = p.beam_x * p.beam_basis.row(0).transpose();
  const Eigen::Vector3d a1 = p.beam_x * p.beam_basis.row(1).transpose();
  Eigen::Matrix<double, 3, 6> s;  // r_S, g_1, g_2, g_11, g_12, g_22 at theta-hat
  s.noalias() = p.shell_x * p.shell_basis.transpose();
  Eigen::Matrix<double, 3, 4> s3 = Eigen::Matrix<double, 3, 4>::Zero();  // g_111, g_112, g_122, g_222
  if (p.shell_basis3.cols() > 0) s3.noalias() = p.shell_x * p.shell_basis3.transpose();

  const V zrb = variable(rb, kRB), za1 = variable(a1, kA1), zrs = variable(s.col(0), kRS);
  const V zg1 = variable(s.col(1), kG1), zg2 = variable(s.col(2), kG2);
  const V zg11 = variable(s.col(3), kG11), zg12 = variable(s.col(4), kG12), zg22 = variable(s.col(5), kG22);

  // h_a(z, theta-hat + dtheta) = (r_B - r_S) . g_a to second order in (z, dtheta) (Eq. 63); the third
  // derivatives g_abc only enter with their values.
  const J t1 = J::variable(0.0, kTheta), t2 = J::variable(0.0, kTheta + 1);
  const J t11 = 0.5 * t1 * t1, t12 = t1 * t2, t22 = 0.5 * t2 * t2;
  const V rs_at = zrs + t1 * zg1 + t2 * zg2 + t11 * zg11 + t12 * zg12 + t22 * zg22;
  const V g1_at = zg1 + t1 * zg11 + t2 * zg12 + times(t11, s3.col(0)) + times(t12, s3.col(1)) +
                  times(t22, s3.col(2));
  const V g2_at = zg2 + t1 * zg12 + t2 * zg22 + times(t11, s3.col(1)) + times(t12, s3.col(2)) +
                  times(t22, s3.col(3));
  const V D_at = zrb - rs_at;
  const J h[2] = {ad::dot(D_at, g1_at), ad::dot(D_at, g2_at)};

  // Implicit function theorem to second order: h(z, theta(z)) = 0 =>
  //   theta_z = -H^-1 h_z,  H = h_theta = -C (Eq. C3, C4),
  //   theta_zz^b = -(H^-1)_ba [h_a,zz + h_a,ztheta theta_z + theta_z^T h_a,thetaz + theta_z^T h_a,thetatheta theta_z].
  Eigen::Matrix2d H;
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b) H(a, b) = h[a].g[kTheta + b];
  const Eigen::Matrix2d Hinv = H.inverse();
  Eigen::Matrix<double, 2, kZ> hz;
  for (int a = 0; a < 2; ++a) hz.row(a) = h[a].g.head<kZ>().transpose();
  const Eigen::Matrix<double, 2, kZ> theta_z = -Hinv * hz;
  Eigen::Matrix<double, kZ, kZ> q[2];
  for (int a = 0; a < 2; ++a) {
    const auto& hh = h[a].h;
    const Eigen::Matrix<double, kZ, kZ> mixed = hh.block<kZ, 2>(0, kTheta).lazyProduct(theta_z);
    q[a] = hh.topLeftCorner<kZ, kZ>() + mixed + mixed.transpose() +
           theta_z.transpose().lazyProduct(hh.bottomRightCorner<2, 2>() * theta_z);
  }
  J dtheta[2];
  for (int b = 0; b < 2; ++b) {
    dtheta[b].g.head<kZ>() = theta_z.row(b).transpose();
    dtheta[b].h.topLeftCorner<kZ, kZ>() = -(Hinv(b, 0) * q[0] + Hinv(b, 1) * q[1]);
  }

  // The distance vector at the moving closest point, Eq. (62): d-hat = r_B - r_S(theta-hat(z)).
  const J& u = dtheta[0];
  const J& v = dtheta[1];
  const V rs = zrs + u * zg1 + v * zg2 + (0.5 * u * u) * zg11 + (u * v) * zg12 + (0.5 * v * v) * zg22;
  const V D = zrb - rs;
  PairJets out;
  out.d = ad::sqrt(ad::dot(D, D));
  if (!need_angle) {  // RF2: phi(d, 1); cos a only reported, no derivatives needed
    const double tn = a1.dot(ad::to_eigen(D)) / (a1.norm() * out.d.v);
    out.s = J(1.0 - tn * tn);
    return out;
  }
  const J tn = ad::dot(za1, D) / (ad::sqrt(ad::dot(za1, za1)) * out.d);  // t . n (Eq. 70)
  out.s = 1.0 - tn * tn;
  return out;
}

// The pair's control points ("nodes") and how the local quantities depend on them: z block k (3 rows)
// = sum over nodes of coefficient(node, k) x_node, i.e. z = L q with L = (coefficients) (x) I_3. The
// scatter exploits this Kronecker structure (a dense L^T K L would cost ~10x more).
struct Node {
  int dof;                       // first DOF of the node in the pair vector
  int first_block, num_blocks;   // z blocks this node enters: beam 0-1 (r_B, a_1), shell 2-7
  double coefficient[6];
};

std::vector<Node> pair_nodes(const PairPoint& p) {
  const int nb = static_cast<int>(p.beam_basis.cols()), ns = static_cast<int>(p.shell_basis.cols());
  std::vector<Node> nodes(nb + ns);
  for (int i = 0; i < nb; ++i) {
    nodes[i] = Node{4 * i, 0, 2, {p.beam_basis(0, i), p.beam_basis(1, i), 0, 0, 0, 0}};
  }
  for (int a = 0; a < ns; ++a) {
    Node& node = nodes[nb + a];
    node = Node{4 * nb + 3 * a, 2, 6, {}};
    for (int r = 0; r < 6; ++r) node.coefficient[r] = p.shell_basis(r, a);
  }
  return nodes;
}

// residual += L^T g, tangent += L^T K L.
void scatter(const std::vector<Node>& nodes, const Eigen::Matrix<double, kZ, 1>& grad,
             const Eigen::Matrix<double, kZ, kZ>* K, Eigen::VectorXd* residual, Eigen::MatrixXd* tangent) {
  std::vector<Eigen::Matrix<double, 3, kZ>> rows(nodes.size());  // (L^T K) restricted to a node
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const Node& a = nodes[i];
    Eigen::Vector3d r = Eigen::Vector3d::Zero();
    rows[i].setZero();
    for (int k = 0; k < a.num_blocks; ++k) {
      const int z = 3 * (a.first_block + k);
      r += a.coefficient[k] * grad.segment<3>(z);
      if (K != nullptr) rows[i] += a.coefficient[k] * K->middleRows<3>(z);
    }
    if (residual != nullptr) residual->segment<3>(a.dof) += r;
  }
  if (K == nullptr || tangent == nullptr) return;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    for (const Node& b : nodes) {
      Eigen::Matrix3d block = Eigen::Matrix3d::Zero();
      for (int l = 0; l < b.num_blocks; ++l)
        block += b.coefficient[l] * rows[i].middleCols<3>(3 * (b.first_block + l));
      tangent->block<3, 3>(nodes[i].dof, b.dof) += block;
    }
  }
}

void check_sizes(const PairPoint& p, bool need_third) {
  const auto nb = p.beam_basis.cols(), ns = p.shell_basis.cols();
  if (nb == 0 || ns == 0 || p.beam_x.cols() != nb || p.shell_x.cols() != ns)
    throw std::invalid_argument("add_sbs_point: basis and control point counts differ");
  if ((need_third || p.shell_basis3.cols() > 0) && p.shell_basis3.cols() != ns)
    throw std::invalid_argument("add_sbs_point: the exact FF tangent needs shell_basis3 (4 x nS)");
}

}  // namespace

PairResult add_sbs_point(const laws::InteractionLaw& law, Formulation f, FfTangent ff_tangent,
                         const PairPoint& p, double* energy, Eigen::VectorXd* residual,
                         Eigen::MatrixXd* tangent) {
  const bool exact_ff = f == Formulation::FF && ff_tangent == FfTangent::exact && tangent != nullptr;
  check_sizes(p, exact_ff);
  const PairJets jets = pair_jets(p, f != Formulation::RF2);
  const J& d = jets.d;
  const J& s = jets.s;
  if (!(d.v > 0)) throw std::domain_error("add_sbs_point: beam point on the shell mid-surface (d = 0)");
  const double c = std::sqrt(std::max(s.v, 0.0));

  PairResult result;
  result.distance = d.v;
  result.cos_alpha = c;
  const laws::LawValue phi = law.evaluate(d.v, f == Formulation::RF2 ? 1.0 : c);
  result.energy = phi.value;
  // Derivatives with respect to s = c^2 (the law is smooth in s; phi_,s = phi_,c / 2c, Eq. 75's reduced
  // form): phi_s, phi_ds and phi_ss = (phi_cc - 2 phi_s) / 4c^2.
  const double phi_s = 0.5 * phi.reduced_c, phi_ds = 0.5 * phi.reduced_dc;

  const double w = p.weight;
  Eigen::Matrix<double, kZ, 1> grad;
  Eigen::Matrix<double, kZ, kZ> K;
  const auto gd = d.g.head<kZ>(), gs = s.g.head<kZ>();
  const auto Hd = d.h.topLeftCorner<kZ, kZ>(), Hs = s.h.topLeftCorner<kZ, kZ>();
  if (f == Formulation::FF) {
    grad = w * (phi.d_d * gd + phi_s * gs);  // Eq. (78): (f + f_C), f_CB, f_CS in local form
    result.force = phi.d_d * gd.segment<3>(kRB) + phi_s * gs.segment<3>(kRB);
  } else {
    grad = w * phi.d_d * gd;  // Eq. (73)
    result.force = phi.d_d * gd.segment<3>(kRB);
  }
  if (tangent != nullptr) {
    if (f == Formulation::RF2) {
      K = w * (phi.d_dd * gd * gd.transpose() + phi.d_d * Hd);  // App. D
    } else if (f == Formulation::RF1 || !exact_ff) {
      K = w * (gd * (phi.d_dd * gd + phi_ds * gs).transpose() + phi.d_d * Hd);  // App. E
    } else {
      if (!(s.v > 0)) throw std::domain_error("add_sbs_point: exact FF tangent needs cos a > 0");
      const double phi_ss = (phi.d_cc - phi.reduced_c) / (4.0 * s.v);
      const Eigen::Matrix<double, kZ, kZ> mixed = gd * gs.transpose();
      K = w * (phi.d_dd * gd * gd.transpose() + phi_ds * (mixed + mixed.transpose()) +
               phi_ss * gs * gs.transpose() + phi.d_d * Hd + phi_s * Hs);
    }
  }

  if (energy != nullptr) *energy += w * phi.value;
  const Eigen::Index n = 4 * p.beam_basis.cols() + 3 * p.shell_basis.cols();
  if (residual != nullptr) {
    if (residual->size() == 0) residual->setZero(n);
    if (residual->size() != n) throw std::invalid_argument("add_sbs_point: residual size");
  }
  if (tangent != nullptr) {
    if (tangent->size() == 0) tangent->setZero(n, n);
    if (tangent->rows() != n || tangent->cols() != n) throw std::invalid_argument("add_sbs_point: tangent size");
  }
  scatter(pair_nodes(p), grad, tangent != nullptr ? &K : nullptr, residual, tangent);
  return result;
}

}  // namespace fibrane::interaction
