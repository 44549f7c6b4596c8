#pragma once
// Test matrices for the linear solvers: a 5-point Laplacian on an m x m grid plus `shift` * I and an upwind
// convection part of strength `convection` (unsymmetric when > 0), with the diagonal scaled by random factors
// 1 + noise * U(-1, 1) (seeded: a sequence of nearby matrices of one pattern).
#include <cmath>
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

// A 7-point Laplacian on an m x m x m grid plus `shift` * I, the diagonal scaled as grid_matrix's by
// 1 + 0.3 U(-1, 1): SPD for shift > 6 / 0.7 - 6 = 2.57 (Gershgorin: diagonal >= 0.7 (6 + shift) > 6, the
// off-diagonal row sum); its nested-dissection factor has dense separator blocks of ~m^2 rows.
inline Eigen::SparseMatrix<double> grid_matrix_3d(int m, double shift, unsigned seed = 1) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Eigen::Triplet<double>> t;
  auto id = [m](int i, int j, int k) { return (i * m + j) * m + k; };
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j)
      for (int k = 0; k < m; ++k) {
        t.emplace_back(id(i, j, k), id(i, j, k), (6.0 + shift) * (1.0 + 0.3 * u(rng)));
        for (int axis = 0; axis < 3; ++axis)
          for (const int step : {-1, 1}) {
            int n[3] = {i, j, k};
            n[axis] += step;
            if (n[axis] >= 0 && n[axis] < m) t.emplace_back(id(i, j, k), id(n[0], n[1], n[2]), -1.0);
          }
      }
  Eigen::SparseMatrix<double> a(m * m * m, m * m * m);
  a.setFromTriplets(t.begin(), t.end());
  return a;
}

// The negative eigenvalues of grid_matrix(m, shift, 0): 4 - 2 cos(pi i / (m + 1)) - 2 cos(pi j / (m + 1)) + shift
// for i, j = 1 ... m.
inline int grid_negative_eigenvalues(int m, double shift) {
  const double pi = std::acos(-1.0);
  int negative = 0;
  for (int i = 1; i <= m; ++i)
    for (int j = 1; j <= m; ++j)
      negative += 4 - 2 * std::cos(pi * i / (m + 1)) - 2 * std::cos(pi * j / (m + 1)) + shift < 0;
  return negative;
}

}  // namespace fibrane::solve
