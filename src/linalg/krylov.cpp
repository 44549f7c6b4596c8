#include "linalg/krylov.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <omp.h>

namespace fibrane::solve {

namespace {

double true_relative_residual(const VectorOperator& a, const Eigen::VectorXd& b, const Eigen::VectorXd& x,
                              double b_norm) {
  Eigen::VectorXd ax;
  a(x, ax);
  return (b - ax).norm() / b_norm;
}

// A zero right-hand side: x = 0, no iteration.
bool solved_trivially(double b_norm, Eigen::Index n, KrylovResult& res) {
  if (b_norm != 0) return false;
  res.x.setZero(n);
  res.converged = true;
  return true;
}

}  // namespace

KrylovResult preconditioned_cg(const VectorOperator& a, const VectorOperator& m_inverse, const Eigen::VectorXd& b,
                               const Eigen::VectorXd& x0, double tolerance, int max_iterations) {
  KrylovResult res;
  const double b_norm = b.norm();
  if (solved_trivially(b_norm, b.size(), res)) return res;
  res.x = x0;
  Eigen::VectorXd r, z, p, ap;
  a(res.x, ap);
  r = b - ap;
  double r_norm = r.norm();
  double rz_old = 0;
  for (; r_norm > tolerance * b_norm && res.iterations < max_iterations; ++res.iterations) {
    m_inverse(r, z);
    const double rz = r.dot(z);
    if (res.iterations == 0) p = z;
    else p = z + (rz / rz_old) * p;
    rz_old = rz;
    a(p, ap);
    const double curvature = p.dot(ap);
    if (!(curvature > 0) || !(rz > 0)) {
      res.breakdown = true;
      break;
    }
    const double alpha = rz / curvature;
    res.x += alpha * p;
    r -= alpha * ap;
    r_norm = r.norm();
  }
  res.relative_residual = true_relative_residual(a, b, res.x, b_norm);
  res.converged = !res.breakdown && res.relative_residual <= tolerance;
  return res;
}

KrylovResult preconditioned_gmres(const VectorOperator& a, const VectorOperator& m_inverse, const Eigen::VectorXd& b,
                                  const Eigen::VectorXd& x0, double tolerance, int max_iterations, int restart) {
  KrylovResult res;
  const double b_norm = b.norm();
  if (solved_trivially(b_norm, b.size(), res)) return res;
  res.x = x0;
  const Eigen::Index n = b.size();
  const int m = std::max(1, restart);
  Eigen::MatrixXd v(n, m + 1);   // Krylov basis
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(m + 1, m);
  Eigen::VectorXd cs(m), sn(m), g(m + 1), w, z, ax;
  a(res.x, ax);
  Eigen::VectorXd r = b - ax;
  double r_norm = r.norm();
  while (r_norm > tolerance * b_norm && res.iterations < max_iterations) {
    v.col(0) = r / r_norm;
    g.setZero();
    g(0) = r_norm;
    h.setZero();
    int k = 0;
    for (; k < m && res.iterations < max_iterations; ++k) {
      m_inverse(v.col(k), z);
      a(z, w);
      ++res.iterations;
      for (int pass = 0; pass < 2; ++pass)  // modified Gram-Schmidt, twice
        for (int i = 0; i <= k; ++i) {
          const double hik = v.col(i).dot(w);
          h(i, k) += hik;
          w -= hik * v.col(i);
        }
      h(k + 1, k) = w.norm();
      if (h(k + 1, k) > 0) v.col(k + 1) = w / h(k + 1, k);
      for (int i = 0; i < k; ++i) {  // earlier rotations on the new column
        const double t = cs(i) * h(i, k) + sn(i) * h(i + 1, k);
        h(i + 1, k) = -sn(i) * h(i, k) + cs(i) * h(i + 1, k);
        h(i, k) = t;
      }
      const double denom = std::hypot(h(k, k), h(k + 1, k));
      cs(k) = denom > 0 ? h(k, k) / denom : 1.0;
      sn(k) = denom > 0 ? h(k + 1, k) / denom : 0.0;
      h(k, k) = denom;
      h(k + 1, k) = 0;
      g(k + 1) = -sn(k) * g(k);
      g(k) = cs(k) * g(k);
      if (std::abs(g(k + 1)) <= tolerance * b_norm || h(k, k) == 0) {
        ++k;
        break;
      }
    }
    // x += M^-1 V_k y, with H_k y = g_k (upper triangular).
    const Eigen::VectorXd y =
        h.topLeftCorner(k, k).triangularView<Eigen::Upper>().solve(g.head(k));
    m_inverse(v.leftCols(k) * y, z);
    const Eigen::VectorXd x_new = res.x + z;
    a(x_new, ax);
    const Eigen::VectorXd r_new = b - ax;
    const double new_norm = r_new.norm();
    // The recurrence's residual is exact only in exact arithmetic: with a preconditioner far from A^-1
    // (an approximate factor of an ill-conditioned matrix) the true residual can be larger. GMRES then
    // keeps the better iterate and stops; the caller sees converged = false.
    if (!(new_norm < r_norm)) break;
    res.x = x_new;
    r = r_new;
    r_norm = new_norm;
  }
  res.relative_residual = r_norm / b_norm;
  res.converged = std::isfinite(res.relative_residual) && res.relative_residual <= tolerance;
  return res;
}

void parallel_multiply(const Eigen::SparseMatrix<double>& a, const Eigen::VectorXd& x, Eigen::VectorXd& y) {
  const Eigen::Index n = a.rows(), columns = a.outerSize();
  const int threads = a.nonZeros() > 200000 ? omp_get_max_threads() : 1;
  y.setZero(n);
  if (threads <= 1) {
    y.noalias() = a * x;
    return;
  }
  std::vector<Eigen::VectorXd> partial(static_cast<size_t>(threads - 1));
  const int* outer = a.outerIndexPtr();
  const int* inner = a.innerIndexPtr();
  const double* values = a.valuePtr();
#pragma omp parallel num_threads(threads)
  {
    const int id = omp_get_thread_num(), count = omp_get_num_threads();
    Eigen::VectorXd* out = &y;
    if (id > 0) {
      partial[static_cast<size_t>(id - 1)].setZero(n);
      out = &partial[static_cast<size_t>(id - 1)];
    }
    // Thread `id` takes the columns that start in its share [from, to) of the non-zeros.
    const long nnz = a.nonZeros();
    const long from = nnz * id / count, to = nnz * (id + 1) / count;
    Eigen::Index j = std::lower_bound(outer, outer + columns, static_cast<int>(from)) - outer;
    if (id == 0) j = 0;
    for (; j < columns && (outer[j] < to || (id == count - 1)); ++j) {
      const double xj = x[j];
      double* o = out->data();
      for (int k = outer[j]; k < outer[j + 1]; ++k) o[inner[k]] += values[k] * xj;
    }
  }
  for (const Eigen::VectorXd& p : partial)
    if (p.size() == n) y += p;
}

}  // namespace fibrane::solve
