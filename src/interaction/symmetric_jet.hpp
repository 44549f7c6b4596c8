#pragma once
// Second-order forward AD over N variables with the Hessian stored as its upper triangle: the same
// arithmetic as common/jet.hpp (exact gradients and Hessians, truncated at second order), at about half
// the cost per operation, for kernels whose cost is the jet arithmetic (interaction/section_beam.cpp).
#include <Eigen/Core>
#include <array>
#include <cmath>

namespace fibrane::interaction {

// A value with its gradient and the upper triangle of its Hessian (row-major, i <= j).
template <int N>
struct SymmetricJet {
  static constexpr int kPacked = N * (N + 1) / 2;
  double v = 0;
  std::array<double, N> g{};
  std::array<double, kPacked> h{};

  SymmetricJet() = default;
  SymmetricJet(double value) : v(value) {}  // NOLINT: constants convert implicitly, as plain doubles would
  static SymmetricJet variable(double value, int index) {
    SymmetricJet j(value);
    j.g[static_cast<std::size_t>(index)] = 1.0;
    return j;
  }
  Eigen::Matrix<double, N, 1> gradient() const { return Eigen::Map<const Eigen::Matrix<double, N, 1>>(g.data()); }
  Eigen::Matrix<double, N, N> hessian() const {
    Eigen::Matrix<double, N, N> out;
    int k = 0;
    for (int i = 0; i < N; ++i)
      for (int j = i; j < N; ++j) out(i, j) = out(j, i) = h[static_cast<std::size_t>(k++)];
    return out;
  }
};

// f(a) with f' and f'' given.
template <int N>
SymmetricJet<N> chain(const SymmetricJet<N>& a, double f, double df, double ddf) {
  SymmetricJet<N> r(f);
  for (int i = 0; i < N; ++i) r.g[i] = df * a.g[i];
  int k = 0;
  for (int i = 0; i < N; ++i) {
    const double gi = ddf * a.g[i];
    for (int j = i; j < N; ++j, ++k) r.h[k] = df * a.h[k] + gi * a.g[j];
  }
  return r;
}

template <int N>
SymmetricJet<N> operator+(const SymmetricJet<N>& a, const SymmetricJet<N>& b) {
  SymmetricJet<N> r(a.v + b.v);
  for (int i = 0; i < N; ++i) r.g[i] = a.g[i] + b.g[i];
  for (int k = 0; k < SymmetricJet<N>::kPacked; ++k) r.h[k] = a.h[k] + b.h[k];
  return r;
}
template <int N>
SymmetricJet<N> operator-(const SymmetricJet<N>& a) {
  return chain(a, -a.v, -1.0, 0.0);
}
template <int N>
SymmetricJet<N> operator-(const SymmetricJet<N>& a, const SymmetricJet<N>& b) {
  SymmetricJet<N> r(a.v - b.v);
  for (int i = 0; i < N; ++i) r.g[i] = a.g[i] - b.g[i];
  for (int k = 0; k < SymmetricJet<N>::kPacked; ++k) r.h[k] = a.h[k] - b.h[k];
  return r;
}
template <int N>
SymmetricJet<N> operator*(const SymmetricJet<N>& a, const SymmetricJet<N>& b) {
  SymmetricJet<N> r(a.v * b.v);
  for (int i = 0; i < N; ++i) r.g[i] = a.v * b.g[i] + b.v * a.g[i];
  int k = 0;
  for (int i = 0; i < N; ++i)
    for (int j = i; j < N; ++j, ++k) r.h[k] = a.v * b.h[k] + b.v * a.h[k] + a.g[i] * b.g[j] + b.g[i] * a.g[j];
  return r;
}
template <int N>
SymmetricJet<N> operator+(const SymmetricJet<N>& a, double b) {
  SymmetricJet<N> r = a;
  r.v += b;
  return r;
}
template <int N>
SymmetricJet<N> operator+(double a, const SymmetricJet<N>& b) {
  return b + a;
}
template <int N>
SymmetricJet<N> operator-(const SymmetricJet<N>& a, double b) {
  return a + (-b);
}
template <int N>
SymmetricJet<N> operator-(double a, const SymmetricJet<N>& b) {
  return (-b) + a;
}
template <int N>
SymmetricJet<N> operator*(const SymmetricJet<N>& a, double b) {
  return chain(a, a.v * b, b, 0.0);
}
template <int N>
SymmetricJet<N> operator*(double a, const SymmetricJet<N>& b) {
  return b * a;
}
template <int N>
SymmetricJet<N> reciprocal(const SymmetricJet<N>& a) {
  const double inv = 1.0 / a.v;
  return chain(a, inv, -inv * inv, 2.0 * inv * inv * inv);
}
template <int N>
SymmetricJet<N> operator/(const SymmetricJet<N>& a, const SymmetricJet<N>& b) {
  return a * reciprocal(b);
}
template <int N>
SymmetricJet<N> operator/(const SymmetricJet<N>& a, double b) {
  return a * (1.0 / b);
}
template <int N>
SymmetricJet<N> operator/(double a, const SymmetricJet<N>& b) {
  return a * reciprocal(b);
}
template <int N>
SymmetricJet<N> sqrt(const SymmetricJet<N>& a) {
  const double s = std::sqrt(a.v);
  return chain(a, s, 0.5 / s, -0.25 / (s * a.v));
}
template <int N>
double value(const SymmetricJet<N>& a) {
  return a.v;
}

}  // namespace fibrane::interaction
