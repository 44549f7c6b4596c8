#pragma once
// Second-order forward automatic differentiation over N local variables.
//
// A Jet<N> carries a value together with its exact gradient and Hessian with respect to N local
// quantities. Kernels whose energy depends on the DOFs only through a few quantities that are LINEAR in
// the DOFs (w = B q) get the residual and the consistent tangent exactly as B^T g and B^T H B.
// Used by the beam point kernel (N = 8) and the beam-shell interaction kernel. Arithmetic is truncated at
// second order, which is exact for gradients and Hessians.
#include <Eigen/Core>
#include <cmath>

namespace fibrane::ad {

template <int N>
struct Jet {
  using Grad = Eigen::Matrix<double, N, 1>;
  using Hess = Eigen::Matrix<double, N, N>;
  double v = 0.0;
  Grad g = Grad::Zero();
  Hess h = Hess::Zero();

  Jet() = default;
  Jet(double value) : v(value) {}  // NOLINT: constants convert implicitly, as plain doubles would
  static Jet variable(double value, int index) {
    Jet j(value);
    j.g[index] = 1.0;
    return j;
  }
};

// f(a) with f' and f'' given: chain rule to second order.
template <int N>
Jet<N> chain(const Jet<N>& a, double f, double df, double ddf) {
  Jet<N> r(f);
  r.g = df * a.g;
  r.h = df * a.h + ddf * a.g * a.g.transpose();
  return r;
}

template <int N>
Jet<N> operator-(const Jet<N>& a) {
  return chain(a, -a.v, -1.0, 0.0);
}
template <int N>
Jet<N> operator+(const Jet<N>& a, const Jet<N>& b) {
  Jet<N> r(a.v + b.v);
  r.g = a.g + b.g;
  r.h = a.h + b.h;
  return r;
}
template <int N>
Jet<N> operator-(const Jet<N>& a, const Jet<N>& b) {
  Jet<N> r(a.v - b.v);
  r.g = a.g - b.g;
  r.h = a.h - b.h;
  return r;
}
template <int N>
Jet<N> operator*(const Jet<N>& a, const Jet<N>& b) {
  Jet<N> r(a.v * b.v);
  r.g = a.v * b.g + b.v * a.g;
  const typename Jet<N>::Hess cross = a.g * b.g.transpose();
  r.h = a.v * b.h + b.v * a.h + cross + cross.transpose();
  return r;
}
template <int N>
Jet<N> operator+(const Jet<N>& a, double b) {
  Jet<N> r = a;
  r.v += b;
  return r;
}
template <int N>
Jet<N> operator+(double a, const Jet<N>& b) {
  return b + a;
}
template <int N>
Jet<N> operator-(const Jet<N>& a, double b) {
  return a + (-b);
}
template <int N>
Jet<N> operator-(double a, const Jet<N>& b) {
  return (-b) + a;
}
template <int N>
Jet<N> operator*(const Jet<N>& a, double b) {
  Jet<N> r(a.v * b);
  r.g = b * a.g;
  r.h = b * a.h;
  return r;
}
template <int N>
Jet<N> operator*(double a, const Jet<N>& b) {
  return b * a;
}
template <int N>
Jet<N> reciprocal(const Jet<N>& a) {
  const double inv = 1.0 / a.v;
  return chain(a, inv, -inv * inv, 2.0 * inv * inv * inv);
}
template <int N>
Jet<N> operator/(const Jet<N>& a, const Jet<N>& b) {
  return a * reciprocal(b);
}
template <int N>
Jet<N> operator/(const Jet<N>& a, double b) {
  return a * (1.0 / b);
}
template <int N>
Jet<N> operator/(double a, const Jet<N>& b) {
  return a * reciprocal(b);
}

template <int N>
Jet<N> sqrt(const Jet<N>& a) {
  const double s = std::sqrt(a.v);
  return chain(a, s, 0.5 / s, -0.25 / (s * a.v));
}
template <int N>
Jet<N> sin(const Jet<N>& a) {
  return chain(a, std::sin(a.v), std::cos(a.v), -std::sin(a.v));
}
template <int N>
Jet<N> cos(const Jet<N>& a) {
  return chain(a, std::cos(a.v), -std::sin(a.v), -std::cos(a.v));
}

// Plain-double versions, so templated code can call sqrt/sin/cos unqualified for both scalar types.
inline double sqrt(double a) { return std::sqrt(a); }
inline double sin(double a) { return std::sin(a); }
inline double cos(double a) { return std::cos(a); }

inline double value(double a) { return a; }
template <int N>
double value(const Jet<N>& a) {
  return a.v;
}

// Minimal 3-vector over double or Jet (Eigen's custom-scalar machinery would be heavier than this).
template <class S>
struct Vec3 {
  S x, y, z;
};

template <class S>
Vec3<S> to_vec3(const Eigen::Vector3d& v) {
  return {S(v.x()), S(v.y()), S(v.z())};
}
template <class S>
Eigen::Vector3d to_eigen(const Vec3<S>& v) {
  return {value(v.x), value(v.y), value(v.z)};
}

template <class A, class B>
auto operator+(const Vec3<A>& a, const Vec3<B>& b) {
  return Vec3<decltype(a.x + b.x)>{a.x + b.x, a.y + b.y, a.z + b.z};
}
template <class A, class B>
auto operator-(const Vec3<A>& a, const Vec3<B>& b) {
  return Vec3<decltype(a.x - b.x)>{a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class A, class B>
auto operator*(const A& s, const Vec3<B>& v) {
  return Vec3<decltype(s * v.x)>{s * v.x, s * v.y, s * v.z};
}
template <class A, class B>
auto dot(const Vec3<A>& a, const Vec3<B>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class A, class B>
auto cross(const Vec3<A>& a, const Vec3<B>& b) {
  return Vec3<decltype(a.x * b.x)>{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

}  // namespace fibrane::ad
