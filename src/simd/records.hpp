// Records of C floats (a bone's palette entry, a dual quaternion of an array of structures), or of
// C doubles (a dual quaternion of a frame, for the frames' kernel in double), moved
// into and out of C component vectors of N lanes, one record per lane: whole-record loads and
// stores, and transposes with shuffles (no gathers or scatters); and points (x, y, z) one after
// another, to and from three coordinate vectors. Used by the skinning kernels
// (src/skin/skinning.cpp), the layout conversions of src/simd/batch.cpp and the forward kinematics
// of frames of src/simd/pose_blocks.cpp. Private to dqkit.
#pragma once

#include <cstring>
#include <type_traits>
#include <utility>

#include "vector_types.hpp"

#if DQKIT_VECTOR_EXTENSIONS && defined(__x86_64__)
namespace dq::kernels {

// Shuffles within each 128-bit block (unpcklps, unpckhps, movlhps, movhlps per block).
#define DQKIT_IN_BLOCKS(name, i0, i1, i2, i3)                                                                              \
  [[gnu::always_inline]] inline float4 name(float4 a, float4 b) { return __builtin_shufflevector(a, b, i0, i1, i2, i3); } \
  [[gnu::always_inline]] inline float8 name(float8 a, float8 b) {                                                        \
    return __builtin_shufflevector(a, b, i0 + (i0 < 4 ? 0 : 4), i1 + (i1 < 4 ? 0 : 4), i2 + (i2 < 4 ? 0 : 4), i3 + (i3 < 4 ? 0 : 4), \
                                   i0 + (i0 < 4 ? 4 : 8), i1 + (i1 < 4 ? 4 : 8), i2 + (i2 < 4 ? 4 : 8), i3 + (i3 < 4 ? 4 : 8)); \
  }                                                                                                                      \
  [[gnu::always_inline]] inline float16 name(float16 a, float16 b) {                                                     \
    return __builtin_shufflevector(a, b, i0 + (i0 < 4 ? 0 : 12), i1 + (i1 < 4 ? 0 : 12), i2 + (i2 < 4 ? 0 : 12), i3 + (i3 < 4 ? 0 : 12), \
                                   i0 + (i0 < 4 ? 4 : 16), i1 + (i1 < 4 ? 4 : 16), i2 + (i2 < 4 ? 4 : 16), i3 + (i3 < 4 ? 4 : 16), \
                                   i0 + (i0 < 4 ? 8 : 20), i1 + (i1 < 4 ? 8 : 20), i2 + (i2 < 4 ? 8 : 20), i3 + (i3 < 4 ? 8 : 20), \
                                   i0 + (i0 < 4 ? 12 : 24), i1 + (i1 < 4 ? 12 : 24), i2 + (i2 < 4 ? 12 : 24), i3 + (i3 < 4 ? 12 : 24)); \
  }
DQKIT_IN_BLOCKS(unpack_low, 0, 4, 1, 5)
DQKIT_IN_BLOCKS(unpack_high, 2, 6, 3, 7)
DQKIT_IN_BLOCKS(low_halves, 0, 1, 4, 5)
DQKIT_IN_BLOCKS(high_halves, 2, 3, 6, 7)
#undef DQKIT_IN_BLOCKS

/// Transposes four rows within each 128-bit block: out[c] block g holds component c of the four
/// rows' block g. Its own inverse.
template <class F>
[[gnu::always_inline]] inline void transpose4_in_blocks(const F* r, F* out) {
  const F t0 = unpack_low(r[0], r[1]), t1 = unpack_high(r[0], r[1]), t2 = unpack_low(r[2], r[3]), t3 = unpack_high(r[2], r[3]);
  out[0] = low_halves(t0, t2), out[1] = high_halves(t0, t2), out[2] = low_halves(t1, t3), out[3] = high_halves(t1, t3);
}

/// Rows of eight (N = 8, 16: row j holds lane j's record, and lane j + 8's in its upper half) and
/// component vectors, after transpose4_in_blocks: x[c] and x[c + 4] (c < 4) exchange their blocks
/// so that each holds lanes 0-3 | 4-7 (| 8-11 | 12-15) of one component. Its own inverse.
template <class F>
[[gnu::always_inline]] inline void regroup_blocks(F* x) {
  for (int c = 0; c < 4; ++c) {
    const F a = x[c], b = x[c + 4];
    if constexpr (sizeof(F) == 32) {
      x[c] = __builtin_shufflevector(a, b, 0, 1, 2, 3, 8, 9, 10, 11);
      x[c + 4] = __builtin_shufflevector(a, b, 4, 5, 6, 7, 12, 13, 14, 15);
    } else {
      x[c] = __builtin_shufflevector(a, b, 0, 1, 2, 3, 16, 17, 18, 19, 8, 9, 10, 11, 24, 25, 26, 27);
      x[c + 4] = __builtin_shufflevector(a, b, 4, 5, 6, 7, 20, 21, 22, 23, 12, 13, 14, 15, 28, 29, 30, 31);
    }
  }
}

/// N points as three coordinate vectors (x, y, z) and as 3 N values of S (float, or double) one
/// point after another (x0 y0 z0 x1 ...), in three whole-vector loads or stores: each vector of one
/// form is two two-source shuffles of the other form's three (`vpermt2ps` with AVX-512). In the
/// arrays of points of docs/performance.md ("Arrays of structures in and out") this moved points
/// 1.5-2.7 times as fast as the records' transpose.
template <int N, class S = float>
struct Points {
  using V = vector_of<S, N>;
  /// Interleaved vector o's lane e holds coordinate (N o + e) % 3 of point (N o + e) / 3.
  template <int O>
  struct Interleaved {
    static constexpr int source(int e) { return (N * O + e) % 3; }
    static constexpr int lane(int e) { return (N * O + e) / 3; }
  };
  /// Coordinate C's lane e is interleaved vector (3 e + C) / N's lane (3 e + C) % N.
  template <int C>
  struct Coordinate {
    static constexpr int source(int e) { return (3 * e + C) / N; }
    static constexpr int lane(int e) { return (3 * e + C) % N; }
  };
  /// The first shuffle's index for lane e: from a or b, or for a lane that c fills, a neighbour's
  /// index (a repeated lane makes a simpler shuffle than an arbitrary one).
  template <class Map>
  static constexpr int from_a_or_b(int e) {
    for (int d = 0; d < N; ++d)
      for (int f : {e - d, e + d})
        if (f >= 0 && f < N && Map::source(f) != 2) return Map::source(f) == 1 ? N + Map::lane(f) : Map::lane(f);
    return 0;
  }
  /// Lane e of the result: lane Map::lane(e) of the vector Map::source(e) of (a, b, c).
  template <class Map, int... E>
  [[gnu::always_inline]] static V pick(V a, V b, V c, std::integer_sequence<int, E...>) {
    const V ab = __builtin_shufflevector(a, b, from_a_or_b<Map>(E)...);
    return __builtin_shufflevector(ab, c, (Map::source(E) == 2 ? N + Map::lane(E) : E)...);
  }
  [[gnu::always_inline]] static void store(V x, V y, V z, S* out) {
    V r0, r1, r2;
    if constexpr (N == 4 && std::is_same_v<S, float>) {
      // Written as shuffles of two lanes from each source (`shufps`, `unpcklps`), which SSE2 has:
      // GCC 12 compiles pick's general shuffles for SSE2 into sequences slower than a transpose.
      const float4 d = __builtin_shufflevector(x, y, 2, 6, 3, 7);  // x2 y2 x3 y3
      r0 = __builtin_shufflevector(__builtin_shufflevector(x, y, 0, 4, 1, 5), __builtin_shufflevector(z, x, 0, 0, 5, 5), 0, 1, 4, 6);
      r1 = __builtin_shufflevector(__builtin_shufflevector(y, z, 1, 1, 5, 5), d, 0, 2, 4, 5);
      r2 = __builtin_shufflevector(__builtin_shufflevector(z, d, 2, 2, 6, 6), __builtin_shufflevector(d, z, 3, 3, 7, 7), 0, 2, 4, 6);
    } else {
      constexpr auto lanes = std::make_integer_sequence<int, N>{};
      r0 = pick<Interleaved<0>>(x, y, z, lanes), r1 = pick<Interleaved<1>>(x, y, z, lanes), r2 = pick<Interleaved<2>>(x, y, z, lanes);
    }
    // One store each (an array of three, copied whole, left a second copy on the stack).
    std::memcpy(out, &r0, sizeof r0), std::memcpy(out + N, &r1, sizeof r1), std::memcpy(out + 2 * N, &r2, sizeof r2);
  }
  [[gnu::always_inline]] static void load(const S* in, V* xyz) {
    const V a = load_as<V>(in), b = load_as<V>(in + N), c = load_as<V>(in + 2 * N);
    if constexpr (N == 4 && std::is_same_v<S, float>) {  // a = x0 y0 z0 x1, b = y1 z1 x2 y2, c = z2 x3 y3 z3; shuffles of store's kind
      xyz[0] = __builtin_shufflevector(__builtin_shufflevector(a, a, 0, 3, 0, 3), __builtin_shufflevector(b, c, 2, 2, 5, 5), 0, 1, 4, 6);
      xyz[1] = __builtin_shufflevector(__builtin_shufflevector(a, b, 1, 1, 4, 4), __builtin_shufflevector(b, c, 3, 3, 6, 6), 0, 2, 4, 6);
      xyz[2] = __builtin_shufflevector(__builtin_shufflevector(a, b, 2, 2, 5, 5), __builtin_shufflevector(c, c, 0, 3, 0, 3), 0, 2, 4, 5);
    } else {
      constexpr auto lanes = std::make_integer_sequence<int, N>{};
      xyz[0] = pick<Coordinate<0>>(a, b, c, lanes), xyz[1] = pick<Coordinate<1>>(a, b, c, lanes), xyz[2] = pick<Coordinate<2>>(a, b, c, lanes);
    }
  }
};

/// Blocks of four floats joined into one vector, lowest first.
[[gnu::always_inline]] inline float8 join(float4 a, float4 b) { return __builtin_shufflevector(a, b, 0, 1, 2, 3, 4, 5, 6, 7); }
[[gnu::always_inline]] inline float16 join(float8 a, float8 b) {
  return __builtin_shufflevector(a, b, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
}
/// Block g (four floats) of x.
template <class F>
[[gnu::always_inline]] inline float4 block(const F& x, int g) {
  float4 b;
  std::memcpy(&b, reinterpret_cast<const char*>(&x) + 16 * g, sizeof b);
  return b;
}

/// The eight floats of `low` below the eight at `high`: with GCC, one `vinsertf64x4` from memory
/// (its join of two loaded halves is a third instruction, a shuffle).
[[gnu::always_inline]] inline float16 halves(float8 low, const float* high) {
#if defined(__clang__)
  return join(low, load_as<float8>(high));
#else
  float16 r;
  const float16 wide = __builtin_shufflevector(low, low, 0, 1, 2, 3, 4, 5, 6, 7, -1, -1, -1, -1, -1, -1, -1, -1);
  asm("vinsertf64x4 $1, %2, %1, %0" : "=v"(r) : "v"(wide), "m"(*reinterpret_cast<const float8*>(high)));
  return r;
#endif
}

/// out[c] lane j = record(j)[c] for c < C (C = 4 or 8) and j < N (N = 4, 8, 16): one load of
/// the record's C floats per lane (in blocks of four), then a transpose. `record(j)` gives lane j's
/// record.
template <int N, int C, class Record>
[[gnu::always_inline]] inline void load_records(Record record, vec<N>* out) {
  static_assert(C == 4 || C == 8);
  using V = vec<N>;
  if constexpr (C == 4 || N == 4) {
    // Rows of four: lane j's record (or half of it) in block j / 4 of row j % 4.
    for (int half = 0; half < C / 4; ++half) {
      V r[4], t[4];
      for (int j = 0; j < 4; ++j) {
        const int o = 4 * half;
        if constexpr (N == 4)
          r[j] = load_as<float4>(record(j) + o);
        else if constexpr (N == 8)
          r[j] = join(load_as<float4>(record(j) + o), load_as<float4>(record(j + 4) + o));
        else
          r[j] = join(join(load_as<float4>(record(j) + o), load_as<float4>(record(j + 4) + o)),
                      join(load_as<float4>(record(j + 8) + o), load_as<float4>(record(j + 12) + o)));
      }
      transpose4_in_blocks(r, t);
      for (int c = 0; c < 4; ++c) out[4 * half + c] = t[c];
    }
  } else {
    // Eight components, N = 8 or 16: row j holds the records of lanes j (and j + 8), whose two
    // blocks are components 0-3 and 4-7; transposed in blocks, then blocks regrouped across rows.
    V r[8];
    for (int j = 0; j < 8; ++j) {
      if constexpr (N == 8)
        r[j] = load_as<float8>(record(j));
      else
        r[j] = halves(load_as<float8>(record(j)), record(j + 8));
    }
    transpose4_in_blocks(r, out);
    transpose4_in_blocks(r + 4, out + 4);
    regroup_blocks(out);
  }
}

/// The inverse of load_records: record(j)[c] = in[c] lane j for c < C and j < N, each record
/// written whole (in blocks of four floats) and nothing else written.
template <int N, int C, class Record>
[[gnu::always_inline]] inline void store_records(const vec<N>* in, Record record) {
  static_assert(C == 4 || C == 8);
  using V = vec<N>;
  if constexpr (C == 4 || N == 4) {
    for (int half = 0; half < C / 4; ++half) {
      V c4[4], r[4];
      for (int c = 0; c < 4; ++c) c4[c] = in[4 * half + c];
      transpose4_in_blocks(c4, r);
#pragma GCC unroll 4
      for (int j = 0; j < 4; ++j)
#pragma GCC unroll 4
        for (int g = 0; g < N / 4; ++g) {
          const float4 b = block(r[j], g);
          std::memcpy(record(j + 4 * g) + 4 * half, &b, sizeof b);
        }
    }
  } else {
    V u[8], r[8];
    for (int c = 0; c < 8; ++c) u[c] = in[c];
    regroup_blocks(u);
    transpose4_in_blocks(u, r);
    transpose4_in_blocks(u + 4, r + 4);
#pragma GCC unroll 8  // rolled, GCC 12 copied the records through the stack in 16-byte pieces
    for (int j = 0; j < 8; ++j) {
      if constexpr (N == 8) {
        std::memcpy(record(j), &r[j], sizeof r[j]);
      } else {
        const float8 low = __builtin_shufflevector(r[j], r[j], 0, 1, 2, 3, 4, 5, 6, 7);
        const float8 high = __builtin_shufflevector(r[j], r[j], 8, 9, 10, 11, 12, 13, 14, 15);
        std::memcpy(record(j), &low, sizeof low);
        std::memcpy(record(j + 8), &high, sizeof high);
      }
    }
  }
}

/// Transposes N rows of N doubles (N = 2, 4, 8) in place: log₂ N stages, the stage of bit B
/// exchanging bit B of the row index with bit B of the column index (rows i and i + B, for each i
/// without bit B). Its own inverse.
template <int N, int B = 1>
[[gnu::always_inline]] inline void transpose_square(vector_of<double, N>* r) {
  if constexpr (B < N) {
    using V = vector_of<double, N>;
    [r]<int... E>(std::integer_sequence<int, E...>) __attribute__((always_inline)) {
#pragma GCC unroll 8
      for (int i = 0; i < N; ++i)
        if (!(i & B)) {
          const V a = r[i], b = r[i | B];
          r[i] = __builtin_shufflevector(a, b, ((E & B) ? N + (E ^ B) : E)...);
          r[i | B] = __builtin_shufflevector(a, b, ((E & B) ? N + E : (E ^ B))...);
        }
    }(std::make_integer_sequence<int, N>{});
    transpose_square<N, 2 * B>(r);
  }
}

/// load_records for records of C doubles (C a multiple of N): per group of N components, one load
/// per lane and a square transpose.
template <int N, int C, class Record>
[[gnu::always_inline]] inline void load_records(Record record, vector_of<double, N>* out) {
  static_assert(C % N == 0);
  for (int g = 0; g < C / N; ++g) {
    vector_of<double, N> r[static_cast<std::size_t>(N)];
#pragma GCC unroll 8
    for (int j = 0; j < N; ++j) r[j] = load_as<vector_of<double, N>>(record(j) + g * N);
    transpose_square<N>(r);
    for (int c = 0; c < N; ++c) out[g * N + c] = r[c];
  }
}

/// The inverse of that load_records: each record written whole, and nothing else.
template <int N, int C, class Record>
[[gnu::always_inline]] inline void store_records(const vector_of<double, N>* in, Record record) {
  static_assert(C % N == 0);
  for (int g = 0; g < C / N; ++g) {
    vector_of<double, N> r[static_cast<std::size_t>(N)];
    for (int c = 0; c < N; ++c) r[c] = in[g * N + c];
    transpose_square<N>(r);
#pragma GCC unroll 8
    for (int j = 0; j < N; ++j) std::memcpy(record(j) + g * N, &r[j], sizeof r[j]);
  }
}

}  // namespace dq::kernels
#endif
