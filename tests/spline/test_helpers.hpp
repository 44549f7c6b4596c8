#pragma once
// Shared fixtures for the spline tests: reproducible random rational geometries.
#include <random>
#include <vector>

#include "spline/curve.hpp"
#include "spline/surface.hpp"

namespace fibrane::spline::testing {

inline std::vector<Eigen::Vector3d> random_points(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> coord(-1.0, 1.0);
  std::vector<Eigen::Vector3d> points(n);
  for (auto& x : points) x = Eigen::Vector3d(coord(rng), coord(rng), coord(rng));
  return points;
}

inline std::vector<double> random_weights(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> weight(0.5, 2.0);
  std::vector<double> w(n);
  for (double& x : w) x = weight(rng);
  return w;
}

// Cubic with a double interior knot (C1 there) and simple knots elsewhere, on [-1, 2].
inline KnotVector sample_knots_cubic() { return KnotVector(3, {-1, -1, -1, -1, 0, 0.5, 0.5, 1.2, 2, 2, 2, 2}); }
inline KnotVector sample_knots_quadratic() { return KnotVector(2, {0, 0, 0, 0.3, 0.7, 0.7, 1, 1, 1}); }

inline NurbsCurve random_curve(std::mt19937& rng, bool rational) {
  KnotVector kv = sample_knots_cubic();
  const int n = kv.num_basis();
  return NurbsCurve(kv, random_points(rng, n), rational ? random_weights(rng, n) : std::vector<double>{});
}

inline NurbsSurface random_surface(std::mt19937& rng, bool rational) {
  KnotVector ku = sample_knots_quadratic();
  KnotVector kv = sample_knots_cubic();
  const int n = ku.num_basis() * kv.num_basis();
  return NurbsSurface(ku, kv, random_points(rng, n), rational ? random_weights(rng, n) : std::vector<double>{});
}

// A parameter in [a, b] at least `margin` away from every knot (so finite differences stay on one
// polynomial piece).
inline double param_away_from_knots(std::mt19937& rng, const KnotVector& kv, double margin) {
  std::uniform_real_distribution<double> dist(kv.front(), kv.back());
  for (;;) {
    const double u = dist(rng);
    bool ok = true;
    for (double k : kv.knots()) ok = ok && std::abs(u - k) > margin;
    if (ok) return u;
  }
}

}  // namespace fibrane::spline::testing
