// Small fixed-size matrices, column-major, acting on column vectors (v' = M v).
//
// Mat3 is a rotation, Mat4 a homogeneous rigid transform (rotation upper-left, translation in the
// last column), Mat34 the top three rows of a Mat4. Storage m[c * R + r] matches glTF, OpenGL,
// GLM and Eigen's default, so `data()` can be handed to them directly.
#pragma once

#include <array>
#include <cstddef>
#include <ostream>

#include "dq/core/vec3.hpp"

namespace dq {

template <class T, int R, int C>
struct Mat {
  static constexpr int rows = R;
  static constexpr int cols = C;
  std::array<T, static_cast<std::size_t>(R * C)> m{};  ///< column-major

  static constexpr std::size_t index(int r, int c) noexcept { return static_cast<std::size_t>(c * R + r); }
  constexpr T& operator()(int r, int c) noexcept { return m[index(r, c)]; }
  constexpr const T& operator()(int r, int c) const noexcept { return m[index(r, c)]; }
  constexpr T* data() noexcept { return m.data(); }
  constexpr const T* data() const noexcept { return m.data(); }

  /// The identity (ones on the main diagonal, also for non-square shapes).
  static constexpr Mat identity() noexcept {
    Mat out;
    for (int i = 0; i < (R < C ? R : C); ++i) out(i, i) = T(1);
    return out;
  }
  /// Builds from values listed row by row, as a matrix is written on paper.
  template <class... A>
  static constexpr Mat from_rows(const A&... values) noexcept {
    static_assert(sizeof...(A) == static_cast<std::size_t>(R * C));
    const std::array<T, sizeof...(A)> v{T(values)...};
    Mat out;
    for (int r = 0; r < R; ++r)
      for (int c = 0; c < C; ++c) out(r, c) = v[static_cast<std::size_t>(r * C + c)];
    return out;
  }

  friend constexpr bool operator==(const Mat& a, const Mat& b) noexcept { return a.m == b.m; }
  friend constexpr Mat operator+(const Mat& a, const Mat& b) noexcept {
    Mat out;
    for (std::size_t i = 0; i < a.m.size(); ++i) out.m[i] = a.m[i] + b.m[i];
    return out;
  }
  friend constexpr Mat operator-(const Mat& a, const Mat& b) noexcept {
    Mat out;
    for (std::size_t i = 0; i < a.m.size(); ++i) out.m[i] = a.m[i] - b.m[i];
    return out;
  }
  friend constexpr Mat operator*(const Mat& a, const T& s) noexcept {
    Mat out;
    for (std::size_t i = 0; i < a.m.size(); ++i) out.m[i] = a.m[i] * s;
    return out;
  }
  friend constexpr Mat operator*(const T& s, const Mat& a) noexcept { return a * s; }

  friend std::ostream& operator<<(std::ostream& os, const Mat& a) {
    for (int r = 0; r < R; ++r) {
      os << (r == 0 ? "[" : " ");
      for (int c = 0; c < C; ++c) os << a(r, c) << (c + 1 < C ? ", " : "");
      os << (r + 1 < R ? "\n" : "]");
    }
    return os;
  }
};

template <class T>
using Mat3 = Mat<T, 3, 3>;
template <class T>
using Mat34 = Mat<T, 3, 4>;
template <class T>
using Mat4 = Mat<T, 4, 4>;

/// The matrix product (R×K)(K×C).
template <class T, int R, int K, int C>
constexpr Mat<T, R, C> operator*(const Mat<T, R, K>& a, const Mat<T, K, C>& b) noexcept {
  Mat<T, R, C> out;
  for (int c = 0; c < C; ++c)
    for (int r = 0; r < R; ++r) {
      T s = a(r, 0) * b(0, c);
      for (int k = 1; k < K; ++k) s += a(r, k) * b(k, c);
      out(r, c) = s;
    }
  return out;
}

template <class T, int R, int C>
constexpr Mat<T, C, R> transpose(const Mat<T, R, C>& a) noexcept {
  Mat<T, C, R> out;
  for (int r = 0; r < R; ++r)
    for (int c = 0; c < C; ++c) out(c, r) = a(r, c);
  return out;
}

/// M v for a 3x3 matrix.
template <class T>
constexpr Vec3<T> operator*(const Mat3<T>& a, const Vec3<T>& v) noexcept {
  return {a(0, 0) * v.x + a(0, 1) * v.y + a(0, 2) * v.z, a(1, 0) * v.x + a(1, 1) * v.y + a(1, 2) * v.z,
          a(2, 0) * v.x + a(2, 1) * v.y + a(2, 2) * v.z};
}

/// The composition of two affine 3x4 transforms, a ∘ b (b first), with the implicit last row
/// (0 0 0 1): 36 multiplications and 27 additions instead of a full 4x4 product.
template <class T>
constexpr Mat34<T> compose(const Mat34<T>& a, const Mat34<T>& b) noexcept {
  Mat34<T> out;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 3; ++r) out(r, c) = a(r, 0) * b(0, c) + a(r, 1) * b(1, c) + a(r, 2) * b(2, c);
  for (int r = 0; r < 3; ++r) out(r, 3) += a(r, 3);
  return out;
}

/// Transforms a point (w = 1) by a homogeneous 4x4 matrix assumed affine (last row 0 0 0 1).
template <class T>
constexpr Vec3<T> transform_point(const Mat4<T>& a, const Vec3<T>& p) noexcept {
  return {a(0, 0) * p.x + a(0, 1) * p.y + a(0, 2) * p.z + a(0, 3),
          a(1, 0) * p.x + a(1, 1) * p.y + a(1, 2) * p.z + a(1, 3),
          a(2, 0) * p.x + a(2, 1) * p.y + a(2, 2) * p.z + a(2, 3)};
}
template <class T>
constexpr Vec3<T> transform_point(const Mat34<T>& a, const Vec3<T>& p) noexcept {
  return {a(0, 0) * p.x + a(0, 1) * p.y + a(0, 2) * p.z + a(0, 3),
          a(1, 0) * p.x + a(1, 1) * p.y + a(1, 2) * p.z + a(1, 3),
          a(2, 0) * p.x + a(2, 1) * p.y + a(2, 2) * p.z + a(2, 3)};
}

}  // namespace dq
