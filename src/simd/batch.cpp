// The batch kernels, once per instruction set. Each target's kernel is a function with GCC's
// `target` attribute (never a per-file -m flag: an inline function compiled with AVX2 in one file
// could then be picked by the linker for every caller, docs/design.md) and `flatten`, so that the
// generic formulas of the scalar types, instantiated on the compiler's vector types, are inlined
// and compiled for that target.
#include "dq/simd/batch.hpp"

#include <atomic>
#include <cstring>
#include <numbers>

#include "dq/core/series.hpp"
#include "dq/interp/rotation.hpp"
#include "lanes.hpp"

namespace dq::simd {

namespace {

#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
using kernels::Lanes;
using kernels::load;
using kernels::polynomial;
using kernels::store;

// Coefficients in float: atan(z)/z in z² (for z ≤ tan π/8), cos h and sin h / h in h² (for h ≤ π/2).
constexpr auto kAtanc = detail::series_coefficients<float, 10>([](std::size_t k) { return (k % 2 ? -1.0f : 1.0f) / float(2 * k + 1); });
constexpr auto kCos = detail::series_coefficients<float, 8>([](std::size_t k) {
  return (k % 2 ? -1.0f : 1.0f) * detail::inverse_factorial<float>(2 * k);
});
constexpr auto kSinc = detail::series_coefficients<float, 8>([](std::size_t k) {
  return (k % 2 ? -1.0f : 1.0f) * detail::inverse_factorial<float>(2 * k + 1);
});

template <int N>
[[gnu::always_inline]] inline DualQuaternion<Lanes<N>> load8(ConstRows r, std::size_t i) {
  return {Quaternion<Lanes<N>>(load<N>(r.rw + i), load<N>(r.rx + i), load<N>(r.ry + i), load<N>(r.rz + i)),
          Quaternion<Lanes<N>>(load<N>(r.dw + i), load<N>(r.dx + i), load<N>(r.dy + i), load<N>(r.dz + i))};
}

/// The kernels for vectors of N lanes; the tail (n mod N) runs the scalar formula.
template <int N>
struct Kernels {
  using V = Lanes<N>;
  /// slerp for t in [0, 1], branch-free: the shortest arc's relative rotation r = (w, v) has
  /// w ≥ 0, so its half angle Ω ∈ [0, π/2]; Ω/|v| from atan with one argument halving (the series
  /// then converges to float precision in 10 terms), and cos and sinc of tΩ ≤ π/2 from 8 terms.
  /// Near w = 0 (Ω near π/2) Ω/|v| = (π/2 − atan(w/|v|))/|v|; near |v| = 0 it tends to 1/w, with no
  /// division by |v|.
  [[gnu::always_inline]] static void slerp(QuaternionRows<const float> a, QuaternionRows<const float> b, float t,
                                           QuaternionRows<float> out, std::size_t n) {
    std::size_t i = 0;
    const V tt = t, one = 1.0f, zero = 0.0f, half_pi = std::numbers::pi_v<float> / 2;
    for (; i + N <= n; i += N) {
      Quaternion<V> qa(load<N>(a.w + i), load<N>(a.x + i), load<N>(a.y + i), load<N>(a.z + i));
      const Quaternion<V> qb(load<N>(b.w + i), load<N>(b.x + i), load<N>(b.y + i), load<N>(b.z + i));
      qa = qa * (one / sqrt(dot(qa, qa)));
      const V sign = select_less(dot(qa, qb), zero, -one, one);
      Quaternion<V> r = detail::hamilton(qa.conjugate(), qb * sign);
      r = r * (one / sqrt(dot(r, r)));
      const Vec3<V> v = r.vec();
      const V s = sqrt(dot(v, v));
      // atan(z)/z for z ∈ [0, 1] through z' = z / (1 + √(1 + z²)) ≤ tan π/8: atan z = 2 atan z'.
      auto atanc = [&](V z) {
        const V d = one + sqrt(one + z * z), zh = z / d;
        return V(2.0f) * polynomial(zh * zh, kAtanc) / d;
      };
      const V small_angle = atanc(s / r.w) / r.w;                        // w ≥ s: Ω = atan(s/w)
      const V z = r.w / select_less(s, r.w, one, s);                     // (s < w lanes: unused)
      const V large_angle = (half_pi - z * atanc(z)) / select_less(s, r.w, one, s);
      const V omega_over_s = select_less(s, r.w, small_angle, large_angle);
      const Vec3<V> u = v * (omega_over_s * tt);
      const V h2 = dot(u, u);
      const Quaternion<V> e(polynomial(h2, kCos), u * polynomial(h2, kSinc));
      const Quaternion<V> result = detail::hamilton(qa, e);
      store<N>(out.w + i, result.w), store<N>(out.x + i, result.x), store<N>(out.y + i, result.y), store<N>(out.z + i, result.z);
    }
    for (; i < n; ++i) {
      const Quaternion<float> q = dq::slerp(Quaternion<float>(a.w[i], a.x[i], a.y[i], a.z[i]), Quaternion<float>(b.w[i], b.x[i], b.y[i], b.z[i]), t);
      out.w[i] = q.w, out.x[i] = q.x, out.y[i] = q.y, out.z[i] = q.z;
    }
  }
  [[gnu::always_inline]] static void compose(ConstRows a, ConstRows b, Rows out, std::size_t n) {
    std::size_t i = 0;
    for (; i + N <= n; i += N) {
      const DualQuaternion<V> p = detail::dual_product(load8<N>(a, i), load8<N>(b, i),
                                                       [](const Quaternion<V>& l, const Quaternion<V>& r) { return detail::hamilton(l, r); });
      store<N>(out.rw + i, p.real.w), store<N>(out.rx + i, p.real.x), store<N>(out.ry + i, p.real.y), store<N>(out.rz + i, p.real.z);
      store<N>(out.dw + i, p.dual.w), store<N>(out.dx + i, p.dual.x), store<N>(out.dy + i, p.dual.y), store<N>(out.dz + i, p.dual.z);
    }
    if (i < n) detail::dual_quaternion_product_rows<float>(a, b, out, i, n);
  }
  [[gnu::always_inline]] static void transform_points(ConstRows q, std::array<const float*, 3> p, std::array<float*, 3> out,
                                                      std::size_t n) {
    std::size_t i = 0;
    for (; i + N <= n; i += N) {
      const Vec3<V> r = load8<N>(q, i).transform_point({load<N>(p[0] + i), load<N>(p[1] + i), load<N>(p[2] + i)});
      store<N>(out[0] + i, r.x), store<N>(out[1] + i, r.y), store<N>(out[2] + i, r.z);
    }
    for (; i < n; ++i) {
      const DualQuaternion<float> d{q.rw[i], q.rx[i], q.ry[i], q.rz[i], q.dw[i], q.dx[i], q.dy[i], q.dz[i]};
      const Vec3<float> r = d.transform_point({p[0][i], p[1][i], p[2][i]});
      out[0][i] = r.x, out[1][i] = r.y, out[2][i] = r.z;
    }
  }
};

#define DQKIT_TARGET_KERNELS(name, lanes, attribute)                                                                    \
  [[gnu::target(attribute), gnu::flatten]] void compose_##name(ConstRows a, ConstRows b, Rows out, std::size_t n) {     \
    Kernels<lanes>::compose(a, b, out, n);                                                                              \
  }                                                                                                                     \
  [[gnu::target(attribute), gnu::flatten]] void slerp_##name(QuaternionRows<const float> a, QuaternionRows<const float> b, float t, \
                                                             QuaternionRows<float> out, std::size_t n) {                \
    Kernels<lanes>::slerp(a, b, t, out, n);                                                                             \
  }                                                                                                                     \
  [[gnu::target(attribute), gnu::flatten]] void transform_points_##name(ConstRows q, std::array<const float*, 3> p,     \
                                                                        std::array<float*, 3> out, std::size_t n) {     \
    Kernels<lanes>::transform_points(q, p, out, n);                                                                     \
  }
DQKIT_TARGET_KERNELS(sse2, 4, "sse2")
DQKIT_TARGET_KERNELS(avx2, 8, "avx2")
DQKIT_TARGET_KERNELS(avx512, 16, "avx512f")
#undef DQKIT_TARGET_KERNELS

Target detect() noexcept {
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f")) return Target::avx512;
  if (__builtin_cpu_supports("avx2")) return Target::avx2;
  return Target::sse2;  // part of every x86-64 CPU
}
#else
Target detect() noexcept { return Target::scalar; }
#endif

std::atomic<Target>& active() {
  static std::atomic<Target> t{detect()};
  return t;
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
    case Target::avx2: return "AVX2";
    case Target::avx512: return "AVX-512";
  }
  return "?";
}

void compose(ConstRows a, ConstRows b, Rows out, std::size_t n) {
  switch (current_target()) {
#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
    case Target::avx512: return compose_avx512(a, b, out, n);
    case Target::avx2: return compose_avx2(a, b, out, n);
    case Target::sse2: return compose_sse2(a, b, out, n);
#endif
    default: return detail::dual_quaternion_product_rows<float>(a, b, out, 0, n);
  }
}

void transform_points(ConstRows q, std::array<const float*, 3> p, std::array<float*, 3> out, std::size_t n) {
  switch (current_target()) {
#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
    case Target::avx512: return transform_points_avx512(q, p, out, n);
    case Target::avx2: return transform_points_avx2(q, p, out, n);
    case Target::sse2: return transform_points_sse2(q, p, out, n);
#endif
    default:
      for (std::size_t i = 0; i < n; ++i) {
        const DualQuaternion<float> d{q.rw[i], q.rx[i], q.ry[i], q.rz[i], q.dw[i], q.dx[i], q.dy[i], q.dz[i]};
        const Vec3<float> r = d.transform_point({p[0][i], p[1][i], p[2][i]});
        out[0][i] = r.x, out[1][i] = r.y, out[2][i] = r.z;
      }
  }
}

void slerp(QuaternionRows<const float> a, QuaternionRows<const float> b, float t, QuaternionRows<float> out, std::size_t n) {
  const bool in_range = t >= 0.0f && t <= 1.0f;  // the polynomials' range (NaN t: dq::slerp too)
  switch (in_range ? current_target() : Target::scalar) {
#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
    case Target::avx512: return slerp_avx512(a, b, t, out, n);
    case Target::avx2: return slerp_avx2(a, b, t, out, n);
    case Target::sse2: return slerp_sse2(a, b, t, out, n);
#endif
    default:
      for (std::size_t i = 0; i < n; ++i) {
        const Quaternion<float> q = dq::slerp(Quaternion<float>(a.w[i], a.x[i], a.y[i], a.z[i]), Quaternion<float>(b.w[i], b.x[i], b.y[i], b.z[i]), t);
        out.w[i] = q.w, out.x[i] = q.x, out.y[i] = q.y, out.z[i] = q.z;
      }
  }
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
