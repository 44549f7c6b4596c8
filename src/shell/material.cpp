// St. Venant-Kirchhoff section (Eqs. 25, 26, 29), the SVK section factory and the registry of materials.
#include "shell/material.hpp"

#include <cmath>
#include <stdexcept>

namespace fibrane::shell {

ShellSection ShellSection::svk(double young, double poisson, double thickness) {
  return {thickness, std::make_shared<const SvkMaterial>(young, poisson)};
}

Eigen::Matrix3d plane_stress_matrix(double young, double poisson, const Eigen::Matrix2d& Ginv) {
  const double factor = young / (1.0 - poisson * poisson);
  const double shear = 0.5 * (1.0 - poisson);
  // Voigt index -> tensor index pair: 0 -> 11, 1 -> 22, 2 -> 12.
  constexpr int first[3] = {0, 1, 0};
  constexpr int second[3] = {0, 1, 1};
  Eigen::Matrix3d D;
  for (int i = 0; i < 3; ++i) {
    const int a = first[i], b = second[i];
    for (int j = 0; j < 3; ++j) {
      const int c = first[j], d = second[j];
      D(i, j) = factor * (poisson * Ginv(a, b) * Ginv(c, d) +
                          shear * (Ginv(a, c) * Ginv(b, d) + Ginv(a, d) * Ginv(b, c)));
    }
  }
  return D;
}

SvkMaterial::SvkMaterial(double young, double poisson) : young_(young), poisson_(poisson) {
  if (!(young > 0.0) || !(poisson > -1.0 && poisson < 0.5))
    throw std::invalid_argument("SvkMaterial: needs young > 0 and -1 < poisson < 0.5");
}

SectionResponse SvkMaterial::respond(const SurfaceMetric& ref, const SurfaceMetric& cur, double h,
                                     bool tangent) const {
  const Eigen::Matrix3d D = plane_stress_matrix(young_, poisson_, ref.inverse_metric);
  const Eigen::Matrix3d Dm = h * D;                   // membrane stiffness, Eq. 29
  const Eigen::Matrix3d Db = (h * h * h / 12.0) * D;  // bending stiffness, Eq. 29
  const Eigen::Vector3d e = membrane_strain(cur, ref);
  const Eigen::Vector3d k = curvature_change(cur, ref);
  SectionResponse r;
  r.N = Dm * e;
  r.M = Db * k;
  // Energy density (h/2) E:C:E + (h^3/24) K:C:K (Eq. 25 integrated through the thickness).
  r.energy = 0.5 * (e.dot(r.N) + k.dot(r.M));
  if (tangent) {
    r.dN_de = Dm;
    r.dM_dk = Db;
  }
  return r;
}

namespace {

// thickness_points: an integer from 1 to 20, default kDefaultThicknessPoints.
int read_thickness_points(const Parameters& p) {
  if (!p.has("thickness_points")) return kDefaultThicknessPoints;
  const double n = p.in_range("thickness_points", 1.0, 20.0, false, false);
  if (n != std::floor(n)) p.fail("thickness_points", "an integer from 1 to 20");
  return static_cast<int>(n);
}

std::shared_ptr<const ShellMaterial> make_svk(const Parameters& p) {
  p.reject_unknown({"young", "poisson"});
  return std::make_shared<const SvkMaterial>(p.positive("young"), p.in_range("poisson", -1.0, 0.5, true, true));
}

std::shared_ptr<const ShellMaterial> make_neo_hookean(const Parameters& p) {
  p.reject_unknown({"young", "poisson", "thickness_points"});
  const double young = p.positive("young");
  const double poisson = p.in_range("poisson", 0.0, 0.5, false, true);
  return std::make_shared<const NeoHookeanMaterial>(young, poisson, read_thickness_points(p));
}

// shear_modulus mu, or young E with mu = E / 3 (nu = 1/2); not both.
std::shared_ptr<const ShellMaterial> make_incompressible(const Parameters& p) {
  p.reject_unknown({"shear_modulus", "young", "thickness_points"});
  if (p.has("shear_modulus") && p.has("young"))
    p.fail("young", "either shear_modulus or young (mu = young / 3), not both");
  const double mu = p.has("young") ? p.positive("young") / 3.0 : p.positive("shear_modulus");
  return std::make_shared<const IncompressibleNeoHookeanMaterial>(mu, read_thickness_points(p));
}

Registry<std::shared_ptr<const ShellMaterial>> build_registry() {
  Registry<std::shared_ptr<const ShellMaterial>> r;
  r.add("svk", "St. Venant-Kirchhoff, plane stress (Eq. 26): young, poisson", make_svk);
  r.add("neo_hookean", "compressible neo-Hookean through the thickness: young, poisson, thickness_points",
        make_neo_hookean);
  r.add("neo_hookean_incompressible", "incompressible neo-Hookean: shear_modulus (or young), thickness_points",
        make_incompressible);
  return r;
}

}  // namespace

const Registry<std::shared_ptr<const ShellMaterial>>& material_registry() {
  static const Registry<std::shared_ptr<const ShellMaterial>> registry = build_registry();
  return registry;
}

}  // namespace fibrane::shell
