// A minimal 3-vector over any dqkit scalar (float, double, Dual, HyperDual, ...).
#pragma once

#include <cmath>
#include <ostream>

#include "dq/core/scalar.hpp"

namespace dq {

template <class T>
struct Vec3 {
  T x{}, y{}, z{};

  constexpr Vec3() noexcept = default;
  constexpr Vec3(const T& x_, const T& y_, const T& z_) noexcept : x(x_), y(y_), z(z_) {}

  constexpr const T& operator[](int i) const noexcept { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr T& operator[](int i) noexcept { return i == 0 ? x : (i == 1 ? y : z); }

  /// The same vector in another scalar type (each component converted with static_cast).
  template <class U>
  constexpr Vec3<U> cast() const noexcept {
    return {static_cast<U>(x), static_cast<U>(y), static_cast<U>(z)};
  }

  constexpr Vec3& operator+=(const Vec3& o) noexcept { x += o.x; y += o.y; z += o.z; return *this; }
  constexpr Vec3& operator-=(const Vec3& o) noexcept { x -= o.x; y -= o.y; z -= o.z; return *this; }
  constexpr Vec3& operator*=(const T& s) noexcept { x *= s; y *= s; z *= s; return *this; }

  friend constexpr Vec3 operator-(const Vec3& a) noexcept { return {-a.x, -a.y, -a.z}; }
  friend constexpr Vec3 operator+(const Vec3& a, const Vec3& b) noexcept { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
  friend constexpr Vec3 operator-(const Vec3& a, const Vec3& b) noexcept { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
  friend constexpr Vec3 operator*(const Vec3& a, const T& s) noexcept { return {a.x * s, a.y * s, a.z * s}; }
  friend constexpr Vec3 operator*(const T& s, const Vec3& a) noexcept { return {s * a.x, s * a.y, s * a.z}; }
  friend constexpr Vec3 operator/(const Vec3& a, const T& s) noexcept { return {a.x / s, a.y / s, a.z / s}; }
  /// Exact, component-wise equality.
  friend constexpr bool operator==(const Vec3& a, const Vec3& b) noexcept {
    return a.x == b.x && a.y == b.y && a.z == b.z;
  }

  friend std::ostream& operator<<(std::ostream& os, const Vec3& v) {
    return os << '(' << v.x << ", " << v.y << ", " << v.z << ')';
  }
};

template <class T>
constexpr T dot(const Vec3<T>& a, const Vec3<T>& b) noexcept {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class T>
constexpr Vec3<T> cross(const Vec3<T>& a, const Vec3<T>& b) noexcept {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class T>
constexpr T squared_norm(const Vec3<T>& a) noexcept {
  return dot(a, a);
}
/// Euclidean length, computed without overflow or underflow for huge or tiny components.
template <class T>
T norm(const Vec3<T>& a) {
  using std::hypot;
  return hypot(hypot(a.x, a.y), a.z);
}
/// a/|a|; the zero vector is returned unchanged (there is no direction to keep).
template <class T>
Vec3<T> normalized(const Vec3<T>& a) {
  const T n = norm(a);
  return n > T(0) ? a / n : a;
}
/// A unit vector orthogonal to a (a ≠ 0), built from a's smallest component for stability.
template <class T>
Vec3<T> any_orthogonal(const Vec3<T>& a) {
  using std::abs;
  const T ax = abs(a.x), ay = abs(a.y), az = abs(a.z);
  Vec3<T> e = (ax <= ay && ax <= az) ? Vec3<T>{T(1), T(0), T(0)}
              : (ay <= az)           ? Vec3<T>{T(0), T(1), T(0)}
                                     : Vec3<T>{T(0), T(0), T(1)};
  return normalized(cross(a, e));
}

}  // namespace dq
