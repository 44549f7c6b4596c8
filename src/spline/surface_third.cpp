#include "spline/surface_third.hpp"

#include <array>

#include "spline/basis.hpp"

namespace fibrane::spline {

SurfaceBasis3 basis3(const NurbsSurface& surface, double u, double v) {
  return basis3_in(surface, surface.knots(0).find_span(u), surface.knots(1).find_span(v), u, v);
}

SurfaceBasis3 basis3_in(const NurbsSurface& surface, int span_u, int span_v, double u, double v) {
  const int p = surface.degree(0), q = surface.degree(1);
  const Eigen::MatrixXd nu = bspline_basis_derivs(surface.knots(0), span_u, u, 3);
  const Eigen::MatrixXd nv = bspline_basis_derivs(surface.knots(1), span_v, v, 3);
  const int count = (p + 1) * (q + 1);
  // a[k][l] = d^(k+l)/du^k dv^l of the weighted products w N_i(u) M_j(v), k + l <= 3.
  std::array<std::array<Eigen::RowVectorXd, 4>, 4> a, r;
  std::array<std::array<double, 4>, 4> w{};
  SurfaceBasis3 result;
  result.indices.resize(count);
  for (int k = 0; k <= 3; ++k)
    for (int l = 0; k + l <= 3; ++l) a[k][l].resize(count);
  for (int j = 0; j <= q; ++j) {
    for (int i = 0; i <= p; ++i) {
      const int local = i + (p + 1) * j;
      const int global = surface.index(span_u - p + i, span_v - q + j);
      result.indices[local] = global;
      const double weight = surface.weights()[global];
      for (int k = 0; k <= 3; ++k)
        for (int l = 0; k + l <= 3; ++l) a[k][l][local] = weight * nu(k, i) * nv(l, j);
    }
  }
  for (int k = 0; k <= 3; ++k)
    for (int l = 0; k + l <= 3; ++l) w[k][l] = a[k][l].sum();
  // R = A / W  =>  A^(k,l) = sum_{i<=k, j<=l} C(k,i) C(l,j) R^(i,j) W^(k-i,l-j) (Leibniz rule),
  // solved for R^(k,l) in order of increasing total degree.
  constexpr int binom[4][4] = {{1, 0, 0, 0}, {1, 1, 0, 0}, {1, 2, 1, 0}, {1, 3, 3, 1}};
  for (int total = 0; total <= 3; ++total) {
    for (int k = total; k >= 0; --k) {
      const int l = total - k;
      Eigen::RowVectorXd acc = a[k][l];
      for (int i = 0; i <= k; ++i)
        for (int j = 0; j <= l; ++j)
          if (i != k || j != l) acc -= binom[k][i] * binom[l][j] * w[k - i][l - j] * r[i][j];
      r[k][l] = acc / w[0][0];
    }
  }
  result.R.resize(4, count);
  result.R.row(0) = r[3][0];
  result.R.row(1) = r[2][1];
  result.R.row(2) = r[1][2];
  result.R.row(3) = r[0][3];
  return result;
}

}  // namespace fibrane::spline
