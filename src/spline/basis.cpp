#include "spline/basis.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace fibrane::spline {

// Method: build the triangle of lower-degree values N_{i,q}(u), q = 0..p, on the span by Cox-de Boor,
//   N_{i,q} = (u - t_i)/(t_{i+q} - t_i) N_{i,q-1} + (t_{i+q+1} - u)/(t_{i+q+1} - t_{i+1}) N_{i+1,q-1},
// then apply the derivative recursion k times,
//   d^k N_{i,q} = q [ d^{k-1} N_{i,q-1} / (t_{i+q} - t_i) - d^{k-1} N_{i+1,q-1} / (t_{i+q+1} - t_{i+1}) ],
// with 0/0 := 0 (a zero-length support term vanishes).
// Storage: level q holds q+1 values for functions i = span - q + j, j = 0..q.
Eigen::MatrixXd bspline_basis_derivs(const KnotVector& kv, int span, double u, int n_deriv) {
  Eigen::MatrixXd result;
  bspline_basis_derivs(kv, span, u, n_deriv, result);
  return result;
}

void bspline_basis_derivs(const KnotVector& kv, int span, double u, int n_deriv, Eigen::MatrixXd& result) {
  const int p = kv.degree();
  if (n_deriv < 0) throw std::invalid_argument("bspline_basis_derivs: n_deriv must be >= 0");
  if (span < p || span >= kv.num_basis())
    throw std::invalid_argument("bspline_basis_derivs: span " + std::to_string(span) + " out of range");
  const std::vector<double>& t = kv.knots();
  auto ratio = [](double num, double den) { return den != 0.0 ? num / den : 0.0; };
  // Three triangular tables of the levels q = 0..p, level q's q + 1 entries from q (q + 1) / 2 on: the
  // values, and the (k-1)-th and k-th derivatives. On the stack up to degree 21, so that the element
  // loops that call this on many threads do not meet at the allocator.
  const int tri = (p + 1) * (p + 2) / 2;
  constexpr int kStack = 256;
  std::array<double, 3 * kStack> stack;
  std::vector<double> heap;
  double* tables = stack.data();
  if (tri > kStack) {
    heap.resize(3 * static_cast<std::size_t>(tri));
    tables = heap.data();
  }
  double* values = tables;
  double* prev = tables + tri;
  double* cur = tables + 2 * tri;
  const auto at = [](double* level, int q, int j) -> double& { return level[q * (q + 1) / 2 + j]; };

  // at(values, q, j) = N_{span-q+j, q}(u)
  at(values, 0, 0) = 1.0;
  for (int q = 1; q <= p; ++q) {
    for (int j = 0; j <= q; ++j) {
      const int i = span - q + j;
      // N_{i,q-1} sits at index j-1 of level q-1, N_{i+1,q-1} at index j.
      const double left = j >= 1 ? at(values, q - 1, j - 1) : 0.0;
      const double right = j <= q - 1 ? at(values, q - 1, j) : 0.0;
      at(values, q, j) = ratio(u - t[i], t[i + q] - t[i]) * left +
                         ratio(t[i + q + 1] - u, t[i + q + 1] - t[i + 1]) * right;
    }
  }

  result.setZero(n_deriv + 1, p + 1);
  for (int j = 0; j <= p; ++j) result(0, j) = at(values, p, j);
  // prev: the (k-1)-th derivatives per level; only levels q >= k-1 are meaningful.
  std::copy(values, values + tri, prev);
  for (int k = 1; k <= std::min(n_deriv, p); ++k) {
    for (int q = k; q <= p; ++q) {
      for (int j = 0; j <= q; ++j) {
        const int i = span - q + j;
        const double left = j >= 1 ? at(prev, q - 1, j - 1) : 0.0;
        const double right = j <= q - 1 ? at(prev, q - 1, j) : 0.0;
        at(cur, q, j) = q * (ratio(left, t[i + q] - t[i]) - ratio(right, t[i + q + 1] - t[i + 1]));
      }
    }
    for (int j = 0; j <= p; ++j) result(k, j) = at(cur, p, j);
    std::swap(prev, cur);
  }
}

}  // namespace fibrane::spline
