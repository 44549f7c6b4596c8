#include "spline/basis.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

namespace fibrane::spline {

// Method: build the triangle of lower-degree values N_{i,q}(u), q = 0..p, on the span by Cox-de Boor,
//   N_{i,q} = (u - t_i)/(t_{i+q} - t_i) N_{i,q-1} + (t_{i+q+1} - u)/(t_{i+q+1} - t_{i+1}) N_{i+1,q-1},
// then apply the derivative recursion k times,
//   d^k N_{i,q} = q [ d^{k-1} N_{i,q-1} / (t_{i+q} - t_i) - d^{k-1} N_{i+1,q-1} / (t_{i+q+1} - t_{i+1}) ],
// with 0/0 := 0 (a zero-length support term vanishes).
// Storage: level q holds q+1 values for functions i = span - q + j, j = 0..q.
Eigen::MatrixXd bspline_basis_derivs(const KnotVector& kv, int span, double u, int n_deriv) {
  const int p = kv.degree();
  if (n_deriv < 0) throw std::invalid_argument("bspline_basis_derivs: n_deriv must be >= 0");
  if (span < p || span >= kv.num_basis())
    throw std::invalid_argument("bspline_basis_derivs: span " + std::to_string(span) + " out of range");
  const std::vector<double>& t = kv.knots();
  auto ratio = [](double num, double den) { return den != 0.0 ? num / den : 0.0; };

  // values[q][j] = N_{span-q+j, q}(u)
  std::vector<std::vector<double>> values(p + 1);
  values[0] = {1.0};
  for (int q = 1; q <= p; ++q) {
    values[q].assign(q + 1, 0.0);
    for (int j = 0; j <= q; ++j) {
      const int i = span - q + j;
      // N_{i,q-1} sits at index j-1 of level q-1, N_{i+1,q-1} at index j.
      const double left = j >= 1 ? values[q - 1][j - 1] : 0.0;
      const double right = j <= q - 1 ? values[q - 1][j] : 0.0;
      values[q][j] = ratio(u - t[i], t[i + q] - t[i]) * left +
                     ratio(t[i + q + 1] - u, t[i + q + 1] - t[i + 1]) * right;
    }
  }

  Eigen::MatrixXd result = Eigen::MatrixXd::Zero(n_deriv + 1, p + 1);
  for (int j = 0; j <= p; ++j) result(0, j) = values[p][j];
  // prev[q] = (k-1)-th derivatives at level q; only levels q >= k-1 are meaningful.
  std::vector<std::vector<double>> prev = values;
  for (int k = 1; k <= std::min(n_deriv, p); ++k) {
    std::vector<std::vector<double>> cur(p + 1);
    for (int q = k; q <= p; ++q) {
      cur[q].assign(q + 1, 0.0);
      for (int j = 0; j <= q; ++j) {
        const int i = span - q + j;
        const double left = j >= 1 ? prev[q - 1][j - 1] : 0.0;
        const double right = j <= q - 1 ? prev[q - 1][j] : 0.0;
        cur[q][j] = q * (ratio(left, t[i + q] - t[i]) - ratio(right, t[i + q + 1] - t[i + 1]));
      }
    }
    for (int j = 0; j <= p; ++j) result(k, j) = cur[p][j];
    prev = std::move(cur);
  }
  return result;
}

}  // namespace fibrane::spline
