#pragma once
// Shared test geometry for the interaction tests: refined exact NURBS patches and a random doubly
// curved B-spline patch.
#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <vector>

#include "spline/knot_vector.hpp"
#include "spline/shapes.hpp"
#include "spline/surface.hpp"

namespace fibrane::interaction::test {

// Cylinder R = 2, length 4, theta in [0.3, 1.5]; cubic, C1 across the 4 x 3 new knots (the rational
// quadratic arc is elevated exactly).
inline spline::NurbsSurface cylinder() {
  spline::NurbsSurface s = spline::make_cylinder_patch(2.0, 4.0, 0.3, 1.5);
  s.refine(0, 3, 1, 4);
  s.refine(1, 3, 2, 3);
  return s;
}

// Sphere R = 1.5, longitude [0.2, 1.6], latitude [-0.6, 0.8] (away from the poles), quadratic C1 x 5.
inline spline::NurbsSurface sphere() {
  spline::NurbsSurface s = spline::make_sphere_patch(1.5, 0.2, 1.6, -0.6, 0.8);
  s.refine(0, 2, 1, 5);
  s.refine(1, 2, 1, 5);
  return s;
}

// Bicubic B-spline on [0,1]^2 with n x n elements over the square [0,4]^2; heights: a smooth saddle-like
// bump plus random noise, so both principal curvatures vary.
inline spline::NurbsSurface random_patch(int n, unsigned seed, int degree = 3) {
  const spline::KnotVector kv = spline::KnotVector::open_uniform(degree, n, degree - 1);
  const int m = kv.num_basis();
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> noise(-0.15, 0.15);
  std::vector<Eigen::Vector3d> points;
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < m; ++i) {
      const double x = 4.0 * i / (m - 1), y = 4.0 * j / (m - 1);
      points.emplace_back(x + noise(gen), y + noise(gen),
                          0.4 * std::sin(0.9 * x) * std::cos(0.7 * y) + 0.1 * x * y / 4 + noise(gen));
    }
  }
  return spline::NurbsSurface(kv, kv, points);
}

// Unit normal g1 x g2 / |g1 x g2| of `s` at (u, v).
inline Eigen::Vector3d unit_normal(const spline::NurbsSurface& s, double u, double v) {
  const spline::SurfaceBasis b = s.basis(u, v);
  Eigen::Vector3d g1 = Eigen::Vector3d::Zero(), g2 = Eigen::Vector3d::Zero();
  for (std::size_t a = 0; a < b.indices.size(); ++a) {
    g1 += b.R(1, a) * s.control_points()[b.indices[a]];
    g2 += b.R(2, a) * s.control_points()[b.indices[a]];
  }
  return g1.cross(g2).normalized();
}

}  // namespace fibrane::interaction::test
