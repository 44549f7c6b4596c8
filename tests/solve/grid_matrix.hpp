#pragma once
// Test matrices for the linear solvers: a 5-point Laplacian on an m x m grid plus `shift` * I and an upwind
// convection part of strength `convection` (unsymmetric when > 0), with the diagonal scaled by random factors
// 1 + noise * U(-1, 1) (seeded: a sequence of nearby matrices of one pattern).
#include <random>
#include <vector>

#include <Eigen/SparseCore>

namespace fibrane::solve {

inline Eigen::SparseMatrix<double> grid_matrix(int m, double shift, double convection, double noise = 0.0,
                                               unsigned seed = 1) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Eigen::Triplet<double>> t;
  auto id = [m](int i, int j) { return i * m + j; };
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) {
      const double scale = noise > 0 ? 1.0 + noise * u(rng) : 1.0;
      t.emplace_back(id(i, j), id(i, j), (4.0 + shift + convection) * scale);
      if (i > 0) t.emplace_back(id(i, j), id(i - 1, j), -1.0 - convection);
      if (i + 1 < m) t.emplace_back(id(i, j), id(i + 1, j), -1.0);
      if (j > 0) t.emplace_back(id(i, j), id(i, j - 1), -1.0);
      if (j + 1 < m) t.emplace_back(id(i, j), id(i, j + 1), -1.0);
    }
  Eigen::SparseMatrix<double> a(m * m, m * m);
  a.setFromTriplets(t.begin(), t.end());
  return a;
}

}  // namespace fibrane::solve
