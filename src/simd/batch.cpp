// The batch kernels, once per instruction set. Each kernel is a struct with its formula on N vector
// lanes (`lanes<N>`, N elements at a time) and per element in scalar code (`scalar`, for the tail
// n mod N and the scalar target). One set of target functions runs any kernel: each has GCC's
// `target` attribute (never a per-file -m flag: an inline function compiled with AVX2 in one file
// could then be picked by the linker for every caller, docs/design.md) and `flatten`, so that the
// generic formulas of the scalar types, instantiated on the compiler's vector types, are inlined
// and compiled for that target; `dispatch` picks the target in use.
#include "dq/simd/batch.hpp"

#include <atomic>
#include <cstring>
#include <limits>
#include <numbers>
#include <type_traits>

#include "dq/convert/matrix.hpp"
#include "dq/core/series.hpp"
#include "dq/interp/rigid.hpp"
#include "dq/interp/rotation.hpp"
#include "lanes.hpp"
#include "records.hpp"

namespace dq::simd {

namespace {

// ---- element access --------------------------------------------------------------------------------

template <class S>
DualQuaternion<S> get(detail::Row8<const S> r, std::size_t i) {
  return {r.rw[i], r.rx[i], r.ry[i], r.rz[i], r.dw[i], r.dx[i], r.dy[i], r.dz[i]};
}
template <class S>
void put(detail::Row8<S> r, std::size_t i, const DualQuaternion<S>& q) {
  r.rw[i] = q.real.w, r.rx[i] = q.real.x, r.ry[i] = q.real.y, r.rz[i] = q.real.z;
  r.dw[i] = q.dual.w, r.dx[i] = q.dual.x, r.dy[i] = q.dual.y, r.dz[i] = q.dual.z;
}
Quaternion<float> get(QuaternionRows<const float> r, std::size_t i) { return {r.w[i], r.x[i], r.y[i], r.z[i]}; }
void put(QuaternionRows<float> r, std::size_t i, const Quaternion<float>& q) { r.w[i] = q.w, r.x[i] = q.x, r.y[i] = q.y, r.z[i] = q.z; }
/// The x, y and z arrays of points or directions (S: float or double, const for reading).
template <class S>
using Coordinates = std::array<S*, 3>;
using Matrices = std::array<float*, 12>;
template <class S>
Vec3<S> get(Coordinates<const S> p, std::size_t i) {
  return {p[0][i], p[1][i], p[2][i]};
}
template <class S>
void put(Coordinates<S> p, std::size_t i, const Vec3<S>& v) {
  p[0][i] = v.x, p[1][i] = v.y, p[2][i] = v.z;
}

#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
using kernels::Lanes;
using kernels::load;
using kernels::load8;
using kernels::load_as;
using kernels::load_records;
using kernels::Points;
using kernels::splat;
using kernels::polynomial;
using kernels::product;
using kernels::store;
using kernels::store8;
using kernels::store_records;

// Coefficients in float: atan(z)/z in z² (for z ≤ tan π/8), cos h and sin h / h in h² (for h ≤ π/2).
constexpr auto kAtanc = detail::series_coefficients<float, 10>([](std::size_t k) { return (k % 2 ? -1.0f : 1.0f) / float(2 * k + 1); });
constexpr auto kCos = detail::series_coefficients<float, 8>([](std::size_t k) {
  return (k % 2 ? -1.0f : 1.0f) * detail::inverse_factorial<float>(2 * k);
});
constexpr auto kSinc = detail::series_coefficients<float, 8>([](std::size_t k) {
  return (k % 2 ? -1.0f : 1.0f) * detail::inverse_factorial<float>(2 * k + 1);
});

template <int N>
[[gnu::always_inline]] inline Quaternion<Lanes<N>> load4(QuaternionRows<const float> r, std::size_t i) {
  return {load<N>(r.w + i), load<N>(r.x + i), load<N>(r.y + i), load<N>(r.z + i)};
}
template <int N>
[[gnu::always_inline]] inline void store4(QuaternionRows<float> r, std::size_t i, const Quaternion<Lanes<N>>& q) {
  store<N>(r.w + i, q.w), store<N>(r.x + i, q.x), store<N>(r.y + i, q.y), store<N>(r.z + i, q.z);
}
template <int N, class S>
[[gnu::always_inline]] inline Vec3<Lanes<N, S>> load3(Coordinates<const S> p, std::size_t i) {
  return {load<N>(p[0] + i), load<N>(p[1] + i), load<N>(p[2] + i)};
}
template <int N, class S>
[[gnu::always_inline]] inline void store3(Coordinates<S> p, std::size_t i, const Vec3<Lanes<N, S>>& v) {
  store<N>(p[0] + i, v.x), store<N>(p[1] + i, v.y), store<N>(p[2] + i, v.z);
}
/// Whether any lane of x is not +0.0 (any bit set): an OR of its 64-bit words, a few instructions.
template <int N>
[[gnu::always_inline]] inline bool any(const Lanes<N>& x) {
  std::uint64_t words[sizeof x.v / 8];
  std::memcpy(words, &x.v, sizeof x.v);
  std::uint64_t r = 0;
  for (const std::uint64_t w : words) r |= w;
  return r != 0;
}

/// The scalar formula of kernel K over [first, last), out of line: for the rare blocks whose
/// inputs a vector formula leaves to it (kept out of the vector loop, whose registers would
/// otherwise be saved around the call on every iteration).
template <class K, class... A>
[[gnu::noinline, gnu::cold]] void scalar_out_of_line(std::size_t first, std::size_t last, A... args) {
  K::scalar(first, last, args...);
}

/// x or −x per lane, by the sign of `sign` (−x where sign < 0: the scalar `s < 0 ? −x : x`).
template <int N>
[[gnu::always_inline]] inline DualQuaternion<Lanes<N>> negate_where_negative(const Lanes<N>& sign, const DualQuaternion<Lanes<N>>& x) {
  const Lanes<N> zero = 0.0f;
  auto q = [&](const Quaternion<Lanes<N>>& p) {
    return Quaternion<Lanes<N>>(select_less(sign, zero, -p.w, p.w), select_less(sign, zero, -p.x, p.x), select_less(sign, zero, -p.y, p.y),
                                select_less(sign, zero, -p.z, p.z));
  };
  return {q(x.real), q(x.dual)};
}

/// The Hamilton product in the order of operations of the four-lane float product that the scalar
/// float types use (detail::hamilton_lanes: (a_w b + a_x b1) + (a_y b2 + a_z b3), with the
/// components of b negated before the sums). Its values are detail::hamilton's but for the sign of
/// some exact zeros: where hamilton computes x − (y − z) with y = z and x = −0 (−0), this computes
/// x + (−y + z) (+0). normalized's rebuilt dual part, whose components cancel exactly when the dual
/// part lies along the real part, is where that shows, so it uses this order, as the scalar does.
template <int N>
[[gnu::always_inline]] inline Quaternion<Lanes<N>> float_product(const Quaternion<Lanes<N>>& a, const Quaternion<Lanes<N>>& b) {
  return {(a.w * b.w + a.x * -b.x) + (a.y * -b.y + a.z * -b.z), (a.w * b.x + a.x * b.w) + (a.y * b.z + a.z * -b.y),
          (a.w * b.y + a.x * -b.z) + (a.y * b.w + a.z * b.x), (a.w * b.z + a.x * b.y) + (a.y * -b.x + a.z * b.w)};
}

/// DualQuaternion::normalized on lanes: r = q_r / |q_r|, d = q_d / |q_r|, k = r · d, and the dual
/// part d − r k, or, where |k| exceeds every component of that (most of d lay along r), the one
/// rebuilt from the translation, (0, vec(d r*)) r: both computed, one selected per lane, with the
/// same operations in the same order as the scalar function (|q_r| = √(q_r · q_r), as
/// Quaternion::norm computes it where q_r · q_r is a normal float). `irregular` is true when a
/// lane needs one of the scalar function's other branches (then the whole block is left to it):
/// q_r · q_r not a normal float (a zero, tiny, huge or non-finite real part: the identity, or a
/// rescaling first), or a non-finite dual part (k not finite), where the scalar choice between the
/// two dual parts depends on how std::max orders NaN.
template <int N>
struct NormalizedLanes {
  DualQuaternion<Lanes<N>> q;
  bool irregular;
};
template <int N>
[[gnu::always_inline]] inline NormalizedLanes<N> normalized_lanes(const DualQuaternion<Lanes<N>>& q) {
  using V = Lanes<N>;
  const V n2 = q.real.squared_norm();
  const V n = sqrt(n2);
  const Quaternion<V> r = q.real / n;
  const Quaternion<V> d = q.dual / n;
  const V k = dot(r, d);
  const Quaternion<V> p = d - r * k;
  const Quaternion<V> rebuilt = float_product(Quaternion<V>::pure(float_product(d, r.conjugate()).vec()), r);
  const V zero = 0.0f;
  auto abs = [&](const V& x) { return select_less(x, zero, -x, x); };
  auto max = [](const V& x, const V& y) { return select_less(x, y, y, x); };
  const V largest = max(max(abs(p.w), abs(p.x)), max(abs(p.y), abs(p.z))), abs_k = abs(k);
  const Quaternion<V> dual(select_less(largest, abs_k, rebuilt.w, p.w), select_less(largest, abs_k, rebuilt.x, p.x),
                           select_less(largest, abs_k, rebuilt.y, p.y), select_less(largest, abs_k, rebuilt.z, p.z));
  // The tests as values that are +0 exactly in the covered lanes and non-zero (or NaN) otherwise:
  // a vector comparison into a lane mask, in a generic function like this one, is split into
  // scalar comparisons before it is inlined into the target's function; selects of values are
  // not. (x − x is +0 for finite x, NaN otherwise; + 0.0f turns a −0 into +0.)
  const V lowest = std::numeric_limits<float>::min(), highest = std::numeric_limits<float>::max();
  const V clamped = select_less(n2, lowest, lowest, select_less(highest, n2, highest, n2));  // NaN stays NaN
  return {{r, dual}, any((clamped - n2) + zero) || any(k - k)};
}

/// Ω/|v| for a rotation (w, v) with w ≥ 0, s = |v| and norm n = √(w² + s²) (1 for a unit one),
/// whose half angle Ω is in [0, π/2] (a w below 0 by rounding takes the second path below, with
/// Ω just above π/2, still right): branch-free, from atan's series at the tangent of half the
/// angle (it then converges to float precision in 10 terms). For Ω ≤ π/4, tan(Ω/2) = s/(n + w) = z
/// and Ω/s = 2 atan(z)/z / (n + w), with no division by s (it tends to 1/w, the limit, as s → 0).
/// For Ω > π/4 the same at the complement π/2 − Ω (whose tangent is w/s): Ω = π/2 − 2 atan(w/(n + s)),
/// and s > n/√2. One division on each path, and the two paths independent.
template <int N>
[[gnu::always_inline]] inline Lanes<N> omega_over_sine(const Lanes<N>& w, const Lanes<N>& s, const Lanes<N>& n) {
  using V = Lanes<N>;
  const V one = 1.0f, two = 2.0f, half_pi = std::numbers::pi_v<float> / 2;
  const V over_nw = one / (n + w), z = s * over_nw;
  const V small_angle = two * polynomial(z * z, kAtanc) * over_nw;  // s < w
  const V zc = w / (n + s);
  const V large_angle = (half_pi - two * zc * polynomial(zc * zc, kAtanc)) / select_less(s, w, one, s);  // (s < w lanes: unused)
  return select_less(s, w, small_angle, large_angle);
}
#endif

// ---- the kernels -----------------------------------------------------------------------------------
// Each names its scalar type (Scalar): the kernels of float and double (S) have N lanes of it on a
// target, as many as its vectors hold.

/// q applied to v: as a point (Rigid: R v + t) or as a direction (R v), for scalars or lanes.
template <bool Rigid, class T>
[[gnu::always_inline]] inline Vec3<T> moved(const DualQuaternion<T>& q, const Vec3<T>& v) {
  if constexpr (Rigid)
    return q.transform_point(v);
  else
    return q.transform_direction(v);
}

template <class S>
struct Compose {
  using Scalar = S;
  static void scalar(std::size_t first, std::size_t last, detail::Row8<const S> a, detail::Row8<const S> b, detail::Row8<S> out) {
    detail::dual_quaternion_product_rows<S>(a, b, out, first, last);
  }
#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
  template <int N>
  [[gnu::always_inline]] static void lanes(std::size_t i, detail::Row8<const S> a, detail::Row8<const S> b, detail::Row8<S> out) {
    store8<N>(out, i, product(load8<N>(a, i), load8<N>(b, i)));
  }
#endif
};

template <class S>
struct Inverse {
  using Scalar = S;
  static void scalar(std::size_t first, std::size_t last, detail::Row8<const S> q, detail::Row8<S> out) {
    for (std::size_t i = first; i < last; ++i) put(out, i, get(q, i).inverse_unit());
  }
#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
  template <int N>
  [[gnu::always_inline]] static void lanes(std::size_t i, detail::Row8<const S> q, detail::Row8<S> out) {
    store8<N>(out, i, load8<N>(q, i).inverse_unit());
  }
#endif
};

/// R p + t (Rigid) or R v for points or directions in component arrays, one transform each.
template <bool Rigid, class S>
struct TransformRows {
  using Scalar = S;
  static void scalar(std::size_t first, std::size_t last, detail::Row8<const S> q, Coordinates<const S> p, Coordinates<S> out) {
    for (std::size_t i = first; i < last; ++i) {
      const DualQuaternion<S> t = get(q, i);
      put(out, i, moved<Rigid>(t, get(p, i)));
    }
  }
#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
  template <int N>
  [[gnu::always_inline]] static void lanes(std::size_t i, detail::Row8<const S> q, Coordinates<const S> p, Coordinates<S> out) {
    const DualQuaternion<Lanes<N, S>> t = load8<N>(q, i);  // a direction reads the real part only
    store3<N>(out, i, moved<Rigid>(t, load3<N>(p, i)));
  }
#endif
};

/// One transform for every point or direction (Rigid: R p + t; else R v), the points one after
/// another (x, y, z) in and out.
template <bool Rigid, class S>
struct TransformEach {
  using Scalar = S;
  static void scalar(std::size_t first, std::size_t last, DualQuaternion<S> q, const Vec3<S>* in, Vec3<S>* out) {
    for (std::size_t i = first; i < last; ++i) out[i] = moved<Rigid>(q, in[i]);
  }
#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
  template <int N>
  [[gnu::always_inline]] static void lanes(std::size_t i, DualQuaternion<S> q, const Vec3<S>* in, Vec3<S>* out) {
    using L = Lanes<N, S>;
    const DualQuaternion<L> b{Quaternion<L>(splat<N>(q.real.w), splat<N>(q.real.x), splat<N>(q.real.y), splat<N>(q.real.z)),
                              Quaternion<L>(splat<N>(q.dual.w), splat<N>(q.dual.x), splat<N>(q.dual.y), splat<N>(q.dual.z))};
    kernels::vector_of<S, N> p[3];
    Points<N, S>::load(&in[i].x, p);  // N points, 3 N values (Vec3<S> is three of them)
    const Vec3<L> v{p[0], p[1], p[2]};
    const Vec3<L> r = moved<Rigid>(b, v);
    Points<N, S>::store(r.x.v, r.y.v, r.z.v, &out[i].x);
  }
#endif
};

// Arrays of structures in and out: the dual quaternions one after another (eight values each), the
// points too (three each), loaded per lane and transposed in registers (records.hpp), with no
// conversion pass to component arrays. For float and double (S).

#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
/// Lane j of N dual quaternions from element i + j of an array of them, and back.
template <int N, class S>
[[gnu::always_inline]] inline DualQuaternion<Lanes<N, S>> load_dual_quaternions(const DualQuaternion<S>* q, std::size_t i) {
  kernels::vector_of<S, N> c[8];
  load_records<N, 8>([&](int j) __attribute__((always_inline)) { return &q[i + static_cast<std::size_t>(j)].real.w; }, c);
  return kernels::dual_quaternion_of<N, S>(c);
}
template <int N, class S>
[[gnu::always_inline]] inline void store_dual_quaternions(const DualQuaternion<Lanes<N, S>>& x, DualQuaternion<S>* q, std::size_t i) {
  kernels::vector_of<S, N> c[8];
  kernels::components_of(x, c);
  store_records<N, 8>(c, [&](int j) __attribute__((always_inline)) { return &q[i + static_cast<std::size_t>(j)].real.w; });
}
#endif

template <class S>
struct ComposeRecords {
  using Scalar = S;
  static constexpr bool unfused_rest = true;  // batch_product, in float too: the generic formula, which GCC fuses
  static void scalar(std::size_t first, std::size_t last, const DualQuaternion<S>* a, const DualQuaternion<S>* b, DualQuaternion<S>* out) {
    for (std::size_t i = first; i < last; ++i) out[i] = detail::batch_product(a[i], b[i]);
  }
#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
  template <int N>
  [[gnu::always_inline]] static void lanes(std::size_t i, const DualQuaternion<S>* a, const DualQuaternion<S>* b, DualQuaternion<S>* out) {
    store_dual_quaternions<N>(product(load_dual_quaternions<N>(a, i), load_dual_quaternions<N>(b, i)), out, i);
  }
#endif
};

template <class S>
struct InverseRecords {
  using Scalar = S;
  static void scalar(std::size_t first, std::size_t last, const DualQuaternion<S>* q, DualQuaternion<S>* out) {
    for (std::size_t i = first; i < last; ++i) out[i] = q[i].inverse_unit();
  }
#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
  template <int N>
  [[gnu::always_inline]] static void lanes(std::size_t i, const DualQuaternion<S>* q, DualQuaternion<S>* out) {
    store_dual_quaternions<N>(load_dual_quaternions<N>(q, i).inverse_unit(), out, i);
  }
#endif
};

/// R p + t (Rigid) or R v, each point with its own transform.
template <bool Rigid, class S>
struct TransformRecords {
  using Scalar = S;
  static void scalar(std::size_t first, std::size_t last, const DualQuaternion<S>* q, const Vec3<S>* p, Vec3<S>* out) {
    for (std::size_t i = first; i < last; ++i) out[i] = moved<Rigid>(q[i], p[i]);
  }
#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
  template <int N>
  [[gnu::always_inline]] static void lanes(std::size_t i, const DualQuaternion<S>* q, const Vec3<S>* p, Vec3<S>* out) {
    using L = Lanes<N, S>;
    kernels::vector_of<S, N> c[3];
    Points<N, S>::load(&p[i].x, c);
    const Vec3<L> v{c[0], c[1], c[2]};
    const DualQuaternion<L> t = load_dual_quaternions<N>(q, i);
    const Vec3<L> r = moved<Rigid>(t, v);
    Points<N, S>::store(r.x.v, r.y.v, r.z.v, &out[i].x);
  }
#endif
};

/// to_mat34, stored column-major as Mat34::m: out[c · 3 + r] is row r of column c.
struct ToMatrices {
  using Scalar = float;
  static void scalar(std::size_t first, std::size_t last, ConstRows q, Matrices out) {
    for (std::size_t i = first; i < last; ++i) {
      const Mat34<float> m = to_mat34(get(q, i));
      for (std::size_t k = 0; k < 12; ++k) out[k][i] = m.m[k];
    }
  }
#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
  template <int N>
  [[gnu::always_inline]] static void lanes(std::size_t i, ConstRows q, Matrices out) {
    const Mat34<Lanes<N>> m = to_mat34(load8<N>(q, i));
    // Unrolled, so that each column is stored from its register. As a loop (GCC 12 kept it for
    // AVX2), the matrix went to the stack and each store became a copy from there in 16-byte
    // pieces: AVX2 ran behind SSE2.
#pragma GCC unroll 12
    for (std::size_t k = 0; k < 12; ++k) store<N>(out[k] + i, m.m[k]);
  }
#endif
};

/// DualQuaternion::normalized. Blocks with a lane that normalized_lanes does not cover (zero, tiny,
/// huge or non-finite input) run the scalar function (element by element, so in place too).
struct Normalize {
  using Scalar = float;
  static void scalar(std::size_t first, std::size_t last, ConstRows q, Rows out) {
    for (std::size_t i = first; i < last; ++i) put(out, i, get(q, i).normalized());
  }
#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
  template <int N>
  [[gnu::always_inline]] static void lanes(std::size_t i, ConstRows q, Rows out) {
    const NormalizedLanes<N> r = normalized_lanes(load8<N>(q, i));
    if (r.irregular) [[unlikely]]
      return scalar_out_of_line<Normalize>(i, i + N, q, out);
    store8<N>(out, i, r.q);
  }
#endif
};

/// dq::dlb(a, b, t): ((1 − t) a + t b) with b's sign aligned to a's, normalized, returned with
/// a's sign. Branch-free but for the blocks with a lane that normalized_lanes does not cover, which
/// run dq::dlb itself.
struct Dlb {
  using Scalar = float;
  static void scalar(std::size_t first, std::size_t last, ConstRows a, ConstRows b, float t, Rows out) {
    for (std::size_t i = first; i < last; ++i) put(out, i, dq::dlb(get(a, i), get(b, i), t));
  }
#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
  template <int N>
  [[gnu::always_inline]] static void lanes(std::size_t i, ConstRows a, ConstRows b, float t, Rows out) {
    using V = Lanes<N>;
    const DualQuaternion<V> qa = load8<N>(a, i), qb = load8<N>(b, i);
    const V wb = select_less(dot(qa.real, qb.real), V(0.0f), splat<N>(-t), splat<N>(t));  // t = −0 as the scalar blend has it
    const NormalizedLanes<N> blend = normalized_lanes(qa * splat<N>(1.0f - t) + qb * wb);
    if (blend.irregular) [[unlikely]]
      return scalar_out_of_line<Dlb>(i, i + N, a, b, t, out);
    store8<N>(out, i, negate_where_negative(dot(blend.q.real, qa.real), blend.q));
  }
#endif
};

struct Slerp {
  using Scalar = float;
  static void scalar(std::size_t first, std::size_t last, QuaternionRows<const float> a, QuaternionRows<const float> b, float t,
                     QuaternionRows<float> out) {
    for (std::size_t i = first; i < last; ++i) put(out, i, dq::slerp(get(a, i), get(b, i), t));
  }
#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
  /// slerp for t in [0, 1], branch-free: the shortest arc's relative rotation r = (w, v) has
  /// w ≥ 0, so its half angle Ω ∈ [0, π/2]; Ω/|v| from omega_over_sine, and cos and sinc of
  /// tΩ ≤ π/2 from 8 terms of their series.
  template <int N>
  [[gnu::always_inline]] static void lanes(std::size_t i, QuaternionRows<const float> a, QuaternionRows<const float> b, float t,
                                           QuaternionRows<float> out) {
    using V = Lanes<N>;
    const V tt = t, one = 1.0f, zero = 0.0f;
    Quaternion<V> qa = load4<N>(a, i);
    const Quaternion<V> qb = load4<N>(b, i);
    // The arc from the inputs' own a · b, the sum dq::slerp takes its sign from (for inputs unit
    // to rounding): at an exact tie (a · b = 0) both take b's arc as given. (From a normalized
    // first, the tie's products no longer cancel exactly, and the sign of the rounding chose.)
    const V sign = select_less(dot(qa, qb), zero, -one, one);
    // The relative rotation from a and b as given, not normalized: only its direction matters
    // (omega_over_sine takes its norm, and v's length cancels in u), so the inputs'
    // normalization is off the chain, a's for the last product only.
    const Quaternion<V> r = detail::hamilton(qa.conjugate(), qb * sign);
    qa = qa * (one / sqrt(dot(qa, qa)));
    const Vec3<V> v = r.vec();
    const Vec3<V> u = v * (omega_over_sine(r.w, sqrt(dot(v, v)), sqrt(dot(r, r))) * tt);
    const V h2 = dot(u, u);
    const Quaternion<V> e(polynomial(h2, kCos), u * polynomial(h2, kSinc));
    store4<N>(out, i, detail::hamilton(qa, e));
  }
#endif
};

/// Screw linear interpolation, dq::sclerp(a, b, t), for t in [0, 1], branch-free. The relative
/// motion d = a* b on the shortest path (negated where its real part's w < 0, as dq::sclerp
/// chooses); below, p = (w, v) is its real part scaled to unit (the code scales only what needs it):
/// w = cos Ω, |v| = sin Ω with the half angle Ω ∈ [0, π/2], and its translation τ = 2 vec(q_d p*).
/// Its screw motion at t, d^t:
///  - rotation p^t = (cos tΩ, v (Ω/|v|) t sinc tΩ), from the series in (tΩ)² as slerp's;
///  - translation τ(t) = t τ∥ + κ Rot_u(φ) τ⊥, with τ∥ = (τ · u) u along the axis u = v/|v| and
///    τ⊥ = τ − τ∥ across it: the part across is (I − R_t)c for the point c of the screw axis, and
///    (I − R_t)(I − R)⁻¹ restricted to the plane ⊥ u is the rotation by φ = (t − 1)Ω about u
///    scaled by κ = sin tΩ / sin Ω = t sinc(tΩ) (Ω/|v|) (bounded: Ω ≤ π/2). cos φ and sin φ come
///    from cos tΩ, sin tΩ and (w, |v|) = (cos Ω, sin Ω) by the angle difference, without a series.
/// At Ω = 0 (identical rotations, pure translations) u is set to 0 and τ(t) = t τ exactly as the
/// limit; for |v| tiny but not 0, u's direction is as good as v's and the result does not depend
/// on it to first order (t − κ cos φ = O(Ω²), sin φ = O(Ω)). Then a d^t, renormalized as dq::sclerp
/// does.
struct Sclerp {
  using Scalar = float;
  static void scalar(std::size_t first, std::size_t last, ConstRows a, ConstRows b, float t, Rows out) {
    for (std::size_t i = first; i < last; ++i) put(out, i, dq::sclerp(get(a, i), get(b, i), t));
  }
#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
  template <int N>
  [[gnu::always_inline]] static void lanes(std::size_t i, ConstRows a, ConstRows b, float t, Rows out) {
    using V = Lanes<N>;
    const V tt = t, one = 1.0f, zero = 0.0f;
    const DualQuaternion<V> qa = load8<N>(a, i);
    DualQuaternion<V> d = product(qa.conjugate(), load8<N>(b, i));
    d = negate_where_negative(d.real.w, d);
    // Ω/|v| from d as it is, its norm n entering omega_over_sine (so the normalization is off
    // the chain, as in slerp): v·(Ω/|v|) and |v|·(Ω/|v|) do not depend on n. What needs the
    // unit motion, cos Ω, sin Ω and the translation, takes d scaled by 1/n.
    const V n = sqrt(dot(d.real, d.real));
    const Vec3<V> v = d.real.vec();
    const V s = sqrt(dot(v, v));
    const V omega_over_s = omega_over_sine(d.real.w, s, n);
    const V over_n = one / n;
    const V w = d.real.w * over_n, sin_omega = s * over_n;
    // The rotation p^t, and h = tΩ.
    const V scale = omega_over_s * tt;
    const Vec3<V> vt = v * scale;
    const V h2 = dot(vt, vt);
    const V cos_h = polynomial(h2, kCos), sinc_h = polynomial(h2, kSinc);
    const V sin_h = (s * scale) * sinc_h;
    const Quaternion<V> rotation(cos_h, vt * sinc_h);
    // The translation τ(t).
    const Vec3<V> tau = (d * over_n).translation();
    const Vec3<V> u = v / select_less(zero, s, s, one);
    const V along = dot(tau, u);
    const Vec3<V> across = tau - u * along;
    const V cos_phi = cos_h * w + sin_h * sin_omega, sin_phi = sin_h * w - cos_h * sin_omega;
    const V kappa = (tt * sinc_h) * (omega_over_s * n);  // Ω/sin Ω = n Ω/|v|
    const Vec3<V> tau_t = u * (along * tt) + (across * cos_phi + cross(u, across) * sin_phi) * kappa;
    const DualQuaternion<V> motion = DualQuaternion<V>::from_rotation_translation(rotation, tau_t);
    // Renormalized as dq::sclerp does: the real part divided by its norm, the dual part's component
    // along it removed (the regular path of DualQuaternion::normalized; the product of unit inputs
    // needs no other, and this is not bit-identical to dq::sclerp anyway).
    const DualQuaternion<V> m = product(qa, motion);
    const V norm_m = sqrt(m.real.squared_norm());
    const Quaternion<V> r = m.real / norm_m, dual = m.dual / norm_m;
    store8<N>(out, i, DualQuaternion<V>(r, dual - r * dot(r, dual)));
  }
#endif
};

// ---- layout conversions: arrays of structures (C values of S an element) and C component arrays ---

/// out[c][i] = element i's value c.
template <std::size_t C, class S>
struct ToRows {
  using Scalar = S;
  static void scalar(std::size_t first, std::size_t last, const S* in, std::array<S*, C> out) {
    for (std::size_t i = first; i < last; ++i)
      for (std::size_t c = 0; c < C; ++c) std::memcpy(out[c] + i, in + C * i + c, sizeof(S));
  }
#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
  template <int N>
  [[gnu::always_inline]] static void lanes(std::size_t i, const S* in, std::array<S*, C> out) {
    kernels::vector_of<S, N> x[C];
    if constexpr (C == 3)
      Points<N, S>::load(in + 3 * i, x);
    else
      load_records<N, C>([&](int j) __attribute__((always_inline)) { return in + C * (i + static_cast<std::size_t>(j)); }, x);
#pragma GCC unroll 8  // rolled, GCC 12 kept x and the array starts in memory (AVX2: 0.54 × SSE2's speed)
    for (std::size_t c = 0; c < C; ++c) std::memcpy(out[c] + i, &x[c], sizeof x[c]);
  }
#endif
};

/// Element i's value c = in[c][i].
template <std::size_t C, class S>
struct FromRows {
  using Scalar = S;
  static void scalar(std::size_t first, std::size_t last, std::array<const S*, C> in, S* out) {
    for (std::size_t i = first; i < last; ++i)
      for (std::size_t c = 0; c < C; ++c) std::memcpy(out + C * i + c, in[c] + i, sizeof(S));
  }
#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
  template <int N>
  [[gnu::always_inline]] static void lanes(std::size_t i, std::array<const S*, C> in, S* out) {
    kernels::vector_of<S, N> x[C];
#pragma GCC unroll 8
    for (std::size_t c = 0; c < C; ++c) x[c] = load_as<kernels::vector_of<S, N>>(in[c] + i);
    if constexpr (C == 3)
      Points<N, S>::store(x[0], x[1], x[2], out + 3 * i);
    else
      store_records<N, C>(x, [&](int j) __attribute__((always_inline)) { return out + C * (i + static_cast<std::size_t>(j)); });
  }
#endif
};

// ---- dispatch --------------------------------------------------------------------------------------

#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
/// Kernel K over the whole vectors of N lanes in n elements; returns the elements done.
template <int N, class K, class... A>
[[gnu::always_inline]] inline std::size_t run_lanes(std::size_t n, A... args) {
  std::size_t i = 0;
  for (; i + N <= n; i += N) K::template lanes<N>(i, args...);
  return i;
}
// One function per instruction set, for any kernel: `width` floats a vector, so half as many
// doubles.
#define DQKIT_TARGET(name, width, attribute)                                                   \
  template <class K, class... A>                                                               \
  [[gnu::target(attribute), gnu::flatten]] std::size_t run_##name(std::size_t n, A... args) { \
    return run_lanes<width * 4 / static_cast<int>(sizeof(typename K::Scalar)), K>(n, args...); \
  }
DQKIT_TARGET(sse2, 4, "sse2")
DQKIT_TARGET(sse42, 4, "sse4.2")
DQKIT_TARGET(avx2, 8, "avx2")
DQKIT_TARGET(avx512, 16, "avx512f")
#undef DQKIT_TARGET

Target detect() noexcept {
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f")) return Target::avx512;
  if (__builtin_cpu_supports("avx2")) return Target::avx2;
  if (__builtin_cpu_supports("sse4.2")) return Target::sse42;
  return Target::sse2;  // part of every x86-64 CPU
}
#else
Target detect() noexcept { return Target::scalar; }
#endif

std::atomic<Target>& active() {
  static std::atomic<Target> t{detect()};
  return t;
}

/// Whether kernel K's elements left to its scalar formula run in scalar_rest: the kernels in double,
/// and those whose float formula is the generic one (`unfused_rest`). The other float kernels'
/// scalar formulas are the scalar types' four-lane forms, written with vector operations, which
/// are not fused; they run as they are (through scalar_rest, in a trial, the float scalar target
/// ran 1.3 to 5.6 times slower).
template <class K>
constexpr bool kRestUnfused = std::is_same_v<typename K::Scalar, double> || requires { requires K::unfused_rest; };

/// Elements [first, n) by kernel K's scalar formula: the tail after the whole vectors, or every
/// element on the scalar target. Out of line and without GCC's vectorizers (DQKIT_NOT_VECTORIZED),
/// so that in a build with FMA the elements left to it keep the bits of those on the lanes: GCC 12
/// fuses the generic scalar product (detail::batch_product) into vfmaddsub despite
/// -ffp-contract=off (docs/design.md). With -mavx2 -mfma, ComposeRecords' loop of products had 18
/// fused instructions, from the loop vectorizer (without the SLP vectorizer alone, still 18), and
/// its elements past the whole vectors differed from the lanes' in float; with both vectorizers
/// off, none.
template <class K, class... A>
[[gnu::noinline, DQKIT_NOT_VECTORIZED]] void scalar_rest(std::size_t first, std::size_t n, A... args) {
  K::scalar(first, n, args...);
}

/// Kernel K over n elements on `target`'s function.
template <class K, class... A>
void dispatch(Target target, std::size_t n, A... args) {
  std::size_t done = 0;
  switch (target) {
#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
    case Target::avx512: done = run_avx512<K>(n, args...); break;
    case Target::avx2: done = run_avx2<K>(n, args...); break;
    case Target::sse42: done = run_sse42<K>(n, args...); break;
    case Target::sse2: done = run_sse2<K>(n, args...); break;
#endif
    default: break;
  }
  if (done == n) return;
  if constexpr (kRestUnfused<K>)
    scalar_rest<K>(done, n, args...);
  else
    K::scalar(done, n, args...);
}

/// The target for the kernels whose polynomials cover t ∈ [0, 1] (a NaN t runs the scalar
/// function too).
Target target_for(float t) noexcept {
  const bool in_range = t >= 0.0f && t <= 1.0f;
  return in_range ? active().load(std::memory_order_relaxed) : Target::scalar;
}

}  // namespace

Target best_target() noexcept {
  static const Target t = detect();
  return t;
}
Target current_target() noexcept { return active().load(std::memory_order_relaxed); }
Target use_target(Target t) noexcept {
  const Target chosen = static_cast<int>(t) < static_cast<int>(best_target()) ? t : best_target();
  active().store(chosen);
  return chosen;
}
std::string_view to_string(Target t) noexcept {
  switch (t) {
    case Target::scalar: return "scalar";
    case Target::sse2: return "SSE2";
    case Target::sse42: return "SSE4.2";
    case Target::avx2: return "AVX2";
    case Target::avx512: return "AVX-512";
  }
  return "?";
}

void compose(ConstRows a, ConstRows b, Rows out, std::size_t n) { dispatch<Compose<float>>(current_target(), n, a, b, out); }
void inverse(ConstRows q, Rows out, std::size_t n) { dispatch<Inverse<float>>(current_target(), n, q, out); }
void normalize(ConstRows q, Rows out, std::size_t n) { dispatch<Normalize>(current_target(), n, q, out); }
void transform_points(ConstRows q, std::array<const float*, 3> p, std::array<float*, 3> out, std::size_t n) {
  dispatch<TransformRows<true, float>>(current_target(), n, q, p, out);
}
void transform_directions(ConstRows q, std::array<const float*, 3> v, std::array<float*, 3> out, std::size_t n) {
  dispatch<TransformRows<false, float>>(current_target(), n, q, v, out);
}
void slerp(QuaternionRows<const float> a, QuaternionRows<const float> b, float t, QuaternionRows<float> out, std::size_t n) {
  dispatch<Slerp>(target_for(t), n, a, b, t, out);
}
void to_matrices(ConstRows q, std::array<float*, 12> out, std::size_t n) { dispatch<ToMatrices>(current_target(), n, q, out); }
void dlb(ConstRows a, ConstRows b, float t, Rows out, std::size_t n) { dispatch<Dlb>(current_target(), n, a, b, t, out); }
void sclerp(ConstRows a, ConstRows b, float t, Rows out, std::size_t n) { dispatch<Sclerp>(target_for(t), n, a, b, t, out); }

void compose(ConstRowsD a, ConstRowsD b, RowsD out, std::size_t n) { dispatch<Compose<double>>(current_target(), n, a, b, out); }
void inverse(ConstRowsD q, RowsD out, std::size_t n) { dispatch<Inverse<double>>(current_target(), n, q, out); }
void transform_points(ConstRowsD q, std::array<const double*, 3> p, std::array<double*, 3> out, std::size_t n) {
  dispatch<TransformRows<true, double>>(current_target(), n, q, p, out);
}
void transform_directions(ConstRowsD q, std::array<const double*, 3> v, std::array<double*, 3> out, std::size_t n) {
  dispatch<TransformRows<false, double>>(current_target(), n, q, v, out);
}

namespace {
/// Whether `out` is `in` or does not overlap it (element by element in place, or apart).
template <class A, class B>
bool same_or_apart(std::span<A> in, std::span<B> out) {
  return static_cast<const void*>(in.data()) == static_cast<const void*>(out.data()) || !overlaps(in, out);
}
template <class S>
void compose_records(std::span<const DualQuaternion<S>> a, std::span<const DualQuaternion<S>> b, std::span<DualQuaternion<S>> out) {
  DQ_PRECONDITION(a.size() == out.size() && b.size() == out.size(), "simd::compose: a, b and out differ in size");
  DQ_PRECONDITION(same_or_apart(a, out) && same_or_apart(b, out), "simd::compose: out overlaps a or b without being it");
  dispatch<ComposeRecords<S>>(current_target(), out.size(), a.data(), b.data(), out.data());
}
template <class S>
void inverse_records(std::span<const DualQuaternion<S>> q, std::span<DualQuaternion<S>> out) {
  DQ_PRECONDITION(q.size() == out.size(), "simd::inverse: q and out differ in size");
  DQ_PRECONDITION(same_or_apart(q, out), "simd::inverse: out overlaps q without being it");
  dispatch<InverseRecords<S>>(current_target(), out.size(), q.data(), out.data());
}
template <bool Rigid, class S>
void transform_records(std::span<const DualQuaternion<S>> q, std::span<const Vec3<S>> p, std::span<Vec3<S>> out) {
  DQ_PRECONDITION(q.size() == out.size() && p.size() == out.size(), "simd::transform_points/directions: q, p and out differ in size");
  DQ_PRECONDITION(same_or_apart(p, out) && !overlaps(q, out), "simd::transform_points/directions: out overlaps q, or p without being it");
  dispatch<TransformRecords<Rigid, S>>(current_target(), out.size(), q.data(), p.data(), out.data());
}
}  // namespace

void compose(std::span<const DualQuaternion<float>> a, std::span<const DualQuaternion<float>> b, std::span<DualQuaternion<float>> out) {
  compose_records(a, b, out);
}
void compose(std::span<const DualQuaternion<double>> a, std::span<const DualQuaternion<double>> b, std::span<DualQuaternion<double>> out) {
  compose_records(a, b, out);
}
void inverse(std::span<const DualQuaternion<float>> q, std::span<DualQuaternion<float>> out) { inverse_records(q, out); }
void inverse(std::span<const DualQuaternion<double>> q, std::span<DualQuaternion<double>> out) { inverse_records(q, out); }
void transform_points(std::span<const DualQuaternion<float>> q, std::span<const Vec3<float>> p, std::span<Vec3<float>> out) {
  transform_records<true>(q, p, out);
}
void transform_points(std::span<const DualQuaternion<double>> q, std::span<const Vec3<double>> p, std::span<Vec3<double>> out) {
  transform_records<true>(q, p, out);
}
void transform_directions(std::span<const DualQuaternion<float>> q, std::span<const Vec3<float>> v, std::span<Vec3<float>> out) {
  transform_records<false>(q, v, out);
}
void transform_directions(std::span<const DualQuaternion<double>> q, std::span<const Vec3<double>> v, std::span<Vec3<double>> out) {
  transform_records<false>(q, v, out);
}

namespace {
// Elements read and written as the values they are made of (their components, in order).
template <class S>
constexpr bool kMadeOfScalars = sizeof(DualQuaternion<S>) == 8 * sizeof(S) && std::is_trivially_copyable_v<DualQuaternion<S>> &&
                                sizeof(Quaternion<S>) == 4 * sizeof(S) && std::is_trivially_copyable_v<Quaternion<S>> &&
                                sizeof(Vec3<S>) == 3 * sizeof(S) && std::is_trivially_copyable_v<Vec3<S>>;
static_assert(kMadeOfScalars<float> && kMadeOfScalars<double>);
/// The values of type S that the elements are made of.
template <class S, class E>
const S* scalars_of(std::span<const E> e) {
  return reinterpret_cast<const S*>(e.data());
}
template <class S, class E>
S* scalars_of(std::span<E> e) {
  return reinterpret_cast<S*>(e.data());
}

template <class S>
void dual_quaternions_to_rows(std::span<const DualQuaternion<S>> in, detail::Row8<S> out) {
  dispatch<ToRows<8, S>>(current_target(), in.size(), scalars_of<S>(in), std::array<S*, 8>{out.rw, out.rx, out.ry, out.rz, out.dw, out.dx, out.dy, out.dz});
}
template <class S>
void dual_quaternions_from_rows(detail::Row8<const S> in, std::span<DualQuaternion<S>> out) {
  dispatch<FromRows<8, S>>(current_target(), out.size(), std::array<const S*, 8>{in.rw, in.rx, in.ry, in.rz, in.dw, in.dx, in.dy, in.dz},
                           scalars_of<S>(out));
}
template <bool Rigid, class S>
void transform_each(const DualQuaternion<S>& q, std::span<const Vec3<S>> in, std::span<Vec3<S>> out) {
  DQ_PRECONDITION(out.size() == in.size(), Rigid ? "simd::transform_points: out and in differ in size"
                                                 : "simd::transform_directions: out and in differ in size");
  DQ_PRECONDITION(same_or_apart(in, out), Rigid ? "simd::transform_points: out overlaps in without being it"
                                                : "simd::transform_directions: out overlaps in without being it");
  dispatch<TransformEach<Rigid, S>>(current_target(), in.size(), q, in.data(), out.data());
}
}  // namespace

void to_rows(std::span<const DualQuaternion<float>> in, Rows out) { dual_quaternions_to_rows(in, out); }
void from_rows(ConstRows in, std::span<DualQuaternion<float>> out) { dual_quaternions_from_rows(in, out); }
void to_rows(std::span<const DualQuaternion<double>> in, RowsD out) { dual_quaternions_to_rows(in, out); }
void from_rows(ConstRowsD in, std::span<DualQuaternion<double>> out) { dual_quaternions_from_rows(in, out); }
void to_rows(std::span<const Quaternion<float>> in, QuaternionRows<float> out) {
  dispatch<ToRows<4, float>>(current_target(), in.size(), scalars_of<float>(in), std::array<float*, 4>{out.w, out.x, out.y, out.z});
}
void from_rows(QuaternionRows<const float> in, std::span<Quaternion<float>> out) {
  dispatch<FromRows<4, float>>(current_target(), out.size(), std::array<const float*, 4>{in.w, in.x, in.y, in.z}, scalars_of<float>(out));
}
void to_rows(std::span<const Vec3<float>> in, std::array<float*, 3> out) { dispatch<ToRows<3, float>>(current_target(), in.size(), scalars_of<float>(in), out); }
void from_rows(std::array<const float*, 3> in, std::span<Vec3<float>> out) {
  dispatch<FromRows<3, float>>(current_target(), out.size(), in, scalars_of<float>(out));
}
void to_rows(std::span<const Vec3<double>> in, std::array<double*, 3> out) {
  dispatch<ToRows<3, double>>(current_target(), in.size(), scalars_of<double>(in), out);
}
void from_rows(std::array<const double*, 3> in, std::span<Vec3<double>> out) {
  dispatch<FromRows<3, double>>(current_target(), out.size(), in, scalars_of<double>(out));
}
void transform_points(const DualQuaternion<float>& q, std::span<const Vec3<float>> in, std::span<Vec3<float>> out) { transform_each<true>(q, in, out); }
void transform_directions(const DualQuaternion<float>& q, std::span<const Vec3<float>> in, std::span<Vec3<float>> out) {
  transform_each<false>(q, in, out);
}
void transform_points(const DualQuaternion<double>& q, std::span<const Vec3<double>> in, std::span<Vec3<double>> out) {
  transform_each<true>(q, in, out);
}
void transform_directions(const DualQuaternion<double>& q, std::span<const Vec3<double>> in, std::span<Vec3<double>> out) {
  transform_each<false>(q, in, out);
}

void run(const ForwardKinematicsJob<float>& job) {
  DQ_PRECONDITION(job.validate().ok(), "simd::run on a job that does not validate");
  job.run_rows([](ConstRows a, ConstRows b, Rows out, std::size_t first, std::size_t last) {
    compose({a.rw + first, a.rx + first, a.ry + first, a.rz + first, a.dw + first, a.dx + first, a.dy + first, a.dz + first},
            {b.rw + first, b.rx + first, b.ry + first, b.rz + first, b.dw + first, b.dx + first, b.dy + first, b.dz + first},
            {out.rw + first, out.rx + first, out.ry + first, out.rz + first, out.dw + first, out.dx + first, out.dy + first,
             out.dz + first},
            last - first);
  });
}

}  // namespace dq::simd
