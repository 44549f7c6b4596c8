#pragma once
// Test helpers for the shell materials: every registered material built from its parameters, and
// midsurface metrics built directly from prescribed fundamental forms, so that a material can be probed
// at chosen strains (e, k) without a patch.
#include <Eigen/Dense>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "common/parameters.hpp"
#include "shell/material.hpp"

namespace fibrane::shell::testing {

// A material with its registry name, for test output.
struct NamedMaterial {
  std::string name;
  std::shared_ptr<const ShellMaterial> material;
};

// The three registered materials with comparable stiffness (E = 1000; nu = 0.3, or 0.5 for the
// incompressible one), built through material_registry().
inline std::vector<NamedMaterial> all_materials() {
  const auto& registry = material_registry();
  return {
      {"svk", registry.make("svk", MapParameters("svk", {{"young", 1000.0}, {"poisson", 0.3}}))},
      {"neo_hookean", registry.make("neo_hookean", MapParameters("nh", {{"young", 1000.0}, {"poisson", 0.3}}))},
      {"neo_hookean_incompressible",
       registry.make("neo_hookean_incompressible", MapParameters("nhi", {{"shear_modulus", 1000.0 / 3.0}}))},
  };
}

// The metric of a point with first fundamental form `metric` = (g11, g22, g12) and second fundamental form
// `curvature` = (b11, b22, b12): the fields a ShellMaterial reads.
inline SurfaceMetric metric_from_forms(const Eigen::Vector3d& metric, const Eigen::Vector3d& curvature) {
  SurfaceMetric m;
  m.metric = metric;
  m.curvature = curvature;
  const double det = metric[0] * metric[1] - metric[2] * metric[2];
  m.area_jacobian = std::sqrt(det);
  m.inverse_metric << metric[1] / det, -metric[2] / det, -metric[2] / det, metric[0] / det;
  return m;
}

// The current metric with Voigt strains e = (E11, E22, 2E12), k = (K11, K22, 2K12) from `ref` (Eqs. 17, 18).
inline SurfaceMetric strained(const SurfaceMetric& ref, const Eigen::Vector3d& e, const Eigen::Vector3d& k) {
  const Eigen::Vector3d metric = ref.metric + Eigen::Vector3d(2.0 * e[0], 2.0 * e[1], e[2]);
  const Eigen::Vector3d curvature = ref.curvature + Eigen::Vector3d(k[0], k[1], 0.5 * k[2]);
  return metric_from_forms(metric, curvature);
}

// A skewed, curved reference point: G_ab with |G_1| != |G_2| and G_12 != 0, B_ab of size ~1.
inline SurfaceMetric random_reference(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  const Eigen::Vector3d metric(1.5 + u(rng), 0.8 + u(rng), 0.4 + u(rng));
  const Eigen::Vector3d curvature(0.7 + u(rng), -0.4 + u(rng), 0.3 + u(rng));
  return metric_from_forms(metric, curvature);
}

// A random Voigt vector with entries uniform in [-amplitude, amplitude].
inline Eigen::Vector3d random_voigt(double amplitude, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  return {u(rng), u(rng), u(rng)};
}

}  // namespace fibrane::shell::testing
