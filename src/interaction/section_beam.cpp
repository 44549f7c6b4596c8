#include "interaction/section_beam.hpp"

#include <cmath>
#include <optional>
#include <stdexcept>

#include "common/jet.hpp"
#include "interaction/symmetric_jet.hpp"

namespace fibrane::interaction {
namespace {

using J = SymmetricJet<15>;
using V = ad::Vec3<J>;

V variable(const Eigen::Vector3d& v, int first) {
  return {J::variable(v.x(), first), J::variable(v.y(), first + 1), J::variable(v.z(), first + 2)};
}
V constant(const Eigen::Vector3d& v) { return {J(v.x()), J(v.y()), J(v.z())}; }
J norm(const V& v) { return sqrt(ad::dot(v, v)); }
V scaled(const J& s, const V& v) { return {s * v.x, s * v.y, s * v.z}; }

// The result where the lower bound d - R_A - R_B of the gap (d from B's axis at its expansion point, which
// must be the closest one) lies beyond the law's cut-off: no derivatives needed. nullopt otherwise.
std::optional<SectionBeamResult> beyond_cutoff(const laws::SectionCylinderLaw& law, const SectionBeamPoint& p) {
  const Eigen::Vector3d t = p.r[1].normalized(), diff = p.x - p.r[0];
  const double d = (diff - diff.dot(t) * t).norm();
  if (!(d - law.radius_a() - law.radius_b() >= law.cutoff_gap() && std::abs(diff.dot(t)) <= 1e-8 * diff.norm()))
    return std::nullopt;
  SectionBeamResult out;
  out.distance = d;
  out.gap = d - law.radius_a() - law.radius_b();
  out.cos_angle = std::abs(p.x_xi.normalized().dot(t));
  return out;
}

// The end taper T(u) of the closest point's arc length to B's nearer end (delta: the closest point's
// parameter offset, half_d2 = delta^2 / 2); 1 where the taper is off.
J end_taper(const EndTaper& taper, const J& delta, const J& half_d2) {
  if (!(taper.length > 0)) return J(1.0);
  const J u = (taper.s + taper.s_xi * delta + taper.s_xixi * half_d2) / taper.length;
  if (u.v <= 0) return J(0.0);
  if (u.v < 1) return u * u * (3.0 - 2.0 * u);
  return J(1.0);
}

}  // namespace

SectionBeamResult section_beam(const laws::SectionCylinderLaw& law, const SectionBeamPoint& p) {
  const double ra = law.radius_a(), rb = law.radius_b();
  if (auto far = beyond_cutoff(law, p)) return *far;
  const V x = variable(p.x, 0), x_xi = variable(p.x_xi, 3);
  const V r0 = variable(p.r[0], 6), r1 = variable(p.r[1], 9), r2 = variable(p.r[2], 12);
  const V r3 = constant(p.r[3]);

  // (S7): the closest point of B's axis moves with all variables.
  const V gap0 = x - r0;
  const J c0 = ad::dot(gap0, r1);
  const J g1 = ad::dot(gap0, r2) - ad::dot(r1, r1);
  const double g2 = -3 * value(ad::dot(r1, r2)) + value(ad::dot(gap0, r3));
  const J delta1 = -(c0 / g1);
  const J delta = -((c0 + 0.5 * g2 * delta1 * delta1) / g1);
  const J half_d2 = 0.5 * delta * delta;
  const J taper = end_taper(p.taper, delta, half_d2);
  const V xb = r0 + scaled(delta, r1) + scaled(half_d2, r2);
  const V tb_raw = r1 + scaled(delta, r2) + scaled(half_d2, r3);
  const V tb = scaled(1.0 / norm(tb_raw), tb_raw);
  const V ta = scaled(1.0 / norm(x_xi), x_xi);

  SectionBeamResult out;
  out.cos_angle = std::abs(value(ad::dot(ta, tb)));
  // (S3): distance from B's axis and the in-section direction towards it.
  const V diff = x - xb;
  const V dp = diff - scaled(ad::dot(diff, tb), tb);
  const J d = norm(dp);
  out.distance = d.v;
  if (!(d.v > 0)) throw std::domain_error("section-beam: the section centre lies on the other fiber's axis");
  out.gap = d.v - ra - rb;  // a lower bound of the gap, reported where the section is beyond the cut-off
  if (out.gap >= law.cutoff_gap()) return out;
  const V n = scaled(1.0 / d, dp);
  const J c = ad::dot(ta, n);
  const J s2 = 1.0 - c * c;
  if (!(s2.v > 1e-12))
    throw std::domain_error("section-beam: the fiber's tangent points at the other fiber's axis");
  const V e = scaled(1.0 / sqrt(s2), n - scaled(c, ta));
  // (S4): the rim point closest to B's axis and the gap's slope into the section.
  const V pe = e - scaled(ad::dot(e, tb), tb);
  const V v = dp - scaled(J(ra), pe);
  const J rho = norm(v);
  const V nu = scaled(1.0 / rho, v);
  const J b = ad::dot(nu, e);
  // (S5): the slope with the finite section's correction, the gap's curvature along the rim; (S6): the
  // gap's minimum along the rim.
  const J g0 = rho - rb;
  const laws::GapValue gs = law.slope_gap(g0.v);
  const J bt = b + chain(g0, gs.f, gs.f_g, gs.f_gg) / (2 * ra);
  const V tau = ad::cross(ta, e);
  const J tt = ad::dot(tb, tau), nt = ad::dot(nu, tau);
  const J a = bt / (2 * ra) + (1.0 - tt * tt - nt * nt) / (2.0 * rho);
  out.slope = bt.v;
  out.curvature = a.v;
  if (!(bt.v > 0) || !(a.v > 0))
    throw std::domain_error("section-beam: the section's rim does not face the other fiber (b or a <= 0)");
  const J g = g0 - nt * nt / (4.0 * a);
  out.gap = g.v;
  out.taper = taper.v;
  if (g.v >= law.cutoff_gap() || taper.v == 0) return out;
  const laws::GapValue f = law.evaluate(g.v);
  const J fg = chain(g, f.f, f.f_g, f.f_gg);
  const J pi = taper * fg / (bt * sqrt(a));  // (S1), times the end taper
  out.active = true;
  out.energy = pi.v;
  out.gradient = pi.gradient();
  out.hessian = pi.hessian();
  return out;
}

SectionBeamResult add_section_beam_point(const laws::SectionCylinderLaw& law,
                                         const Eigen::Matrix<double, 2, Eigen::Dynamic>& basis_a,
                                         const Eigen::Matrix3Xd& x_a,
                                         const Eigen::Matrix<double, 4, Eigen::Dynamic>& basis_b,
                                         const Eigen::Matrix3Xd& x_b, double weight, double* energy,
                                         Eigen::VectorXd* residual, Eigen::MatrixXd* tangent,
                                         const EndTaper& taper) {
  const int na = static_cast<int>(basis_a.cols()), nb = static_cast<int>(basis_b.cols());
  if (x_a.cols() != na || x_b.cols() != nb) throw std::invalid_argument("section-beam: basis and points differ");
  SectionBeamPoint p;
  p.x = x_a * basis_a.row(0).transpose();
  p.x_xi = x_a * basis_a.row(1).transpose();
  for (int k = 0; k < 4; ++k) p.r[k] = x_b * basis_b.row(k).transpose();
  p.taper = taper;
  const SectionBeamResult res = section_beam(law, p);
  if (!res.active) return res;
  const int n = 4 * (na + nb);
  if (residual && residual->size() == 0) residual->setZero(n);
  if (tangent && tangent->size() == 0) tangent->setZero(n, n);
  if ((residual && residual->size() != n) || (tangent && (tangent->rows() != n || tangent->cols() != n)))
    throw std::invalid_argument("section-beam: residual or tangent of the wrong size");
  if (energy) *energy += weight * res.energy;
  // w = B q: control point j of A enters the variable groups x (0) and x_xi (1) with basis_a(0, j),
  // basis_a(1, j); control point j of B the groups r_B, r_B', r_B'' (2, 3, 4) with basis_b(0..2, j).
  // B^T g and B^T H B are formed block by block (3 x 3 per pair of control points).
  const int ncp = na + nb;
  auto coefficient = [&](int cp, int group) {
    if (cp < na) return group < 2 ? basis_a(group, cp) : 0.0;
    return group >= 2 ? basis_b(group - 2, cp - na) : 0.0;
  };
  auto groups = [&](int cp, int& first, int& last) {
    first = cp < na ? 0 : 2;
    last = cp < na ? 2 : 5;
  };
  for (int j = 0; j < ncp; ++j) {
    int g0, g1;
    groups(j, g0, g1);
    if (residual) {
      Eigen::Vector3d r = Eigen::Vector3d::Zero();
      for (int g = g0; g < g1; ++g) r += coefficient(j, g) * res.gradient.segment<3>(3 * g);
      residual->segment<3>(4 * j) += weight * r;
    }
    if (!tangent) continue;
    for (int l = 0; l < ncp; ++l) {
      int h0, h1;
      groups(l, h0, h1);
      Eigen::Matrix3d block = Eigen::Matrix3d::Zero();
      for (int g = g0; g < g1; ++g)
        for (int h = h0; h < h1; ++h)
          block += (coefficient(j, g) * coefficient(l, h)) * res.hessian.block<3, 3>(3 * g, 3 * h);
      tangent->block<3, 3>(4 * j, 4 * l) += weight * block;
    }
  }
  return res;
}

}  // namespace fibrane::interaction
