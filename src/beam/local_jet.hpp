#pragma once
// Second-order forward differentiation for the beam point kernel.
//
// The beam energy density at a quadrature point depends on the element DOFs only through 8 local
// quantities w = [a_1 (3), a_1,1 (3), phi, phi_,1] which are LINEAR in the DOFs. A Jet carries a value
// together with its exact gradient and Hessian with respect to w, so the residual and the consistent
// tangent follow exactly from the closed-form energy (Eqs. 32-43) as B^T g and B^T H B (B = dw/dq).
// This replaces transcribing the long (and typo-prone) App. B expressions; every block is verified
// against finite differences in tests/beam.
#include <Eigen/Core>
#include <cmath>

namespace fibrane::beam::detail {

constexpr int kLocalVars = 8;

struct Jet {
  using Grad = Eigen::Matrix<double, kLocalVars, 1>;
  using Hess = Eigen::Matrix<double, kLocalVars, kLocalVars>;
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
inline Jet chain(const Jet& a, double f, double df, double ddf) {
  Jet r(f);
  r.g = df * a.g;
  r.h = df * a.h + ddf * a.g * a.g.transpose();
  return r;
}

inline Jet operator-(const Jet& a) { return chain(a, -a.v, -1.0, 0.0); }
inline Jet operator+(const Jet& a, const Jet& b) {
  Jet r(a.v + b.v);
  r.g = a.g + b.g;
  r.h = a.h + b.h;
  return r;
}
inline Jet operator-(const Jet& a, const Jet& b) {
  Jet r(a.v - b.v);
  r.g = a.g - b.g;
  r.h = a.h - b.h;
  return r;
}
inline Jet operator*(const Jet& a, const Jet& b) {
  Jet r(a.v * b.v);
  r.g = a.v * b.g + b.v * a.g;
  const Jet::Hess cross = a.g * b.g.transpose();
  r.h = a.v * b.h + b.v * a.h + cross + cross.transpose();
  return r;
}
inline Jet operator+(const Jet& a, double b) {
  Jet r = a;
  r.v += b;
  return r;
}
inline Jet operator+(double a, const Jet& b) { return b + a; }
inline Jet operator-(const Jet& a, double b) { return a + (-b); }
inline Jet operator-(double a, const Jet& b) { return (-b) + a; }
inline Jet operator*(const Jet& a, double b) {
  Jet r(a.v * b);
  r.g = b * a.g;
  r.h = b * a.h;
  return r;
}
inline Jet operator*(double a, const Jet& b) { return b * a; }
inline Jet reciprocal(const Jet& a) {
  const double inv = 1.0 / a.v;
  return chain(a, inv, -inv * inv, 2.0 * inv * inv * inv);
}
inline Jet operator/(const Jet& a, const Jet& b) { return a * reciprocal(b); }
inline Jet operator/(const Jet& a, double b) { return a * (1.0 / b); }
inline Jet operator/(double a, const Jet& b) { return a * reciprocal(b); }

inline Jet sqrt(const Jet& a) {
  const double s = std::sqrt(a.v);
  return chain(a, s, 0.5 / s, -0.25 / (s * a.v));
}
inline Jet sin(const Jet& a) { return chain(a, std::sin(a.v), std::cos(a.v), -std::sin(a.v)); }
inline Jet cos(const Jet& a) { return chain(a, std::cos(a.v), -std::sin(a.v), -std::cos(a.v)); }

// Plain-double versions, so templated code can call sqrt/sin/cos unqualified for both scalar types.
inline double sqrt(double a) { return std::sqrt(a); }
inline double sin(double a) { return std::sin(a); }
inline double cos(double a) { return std::cos(a); }

inline double value(double a) { return a; }
inline double value(const Jet& a) { return a.v; }

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

}  // namespace fibrane::beam::detail
