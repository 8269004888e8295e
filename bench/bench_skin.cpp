// Skinning at the memory limit (issue 12): dqkit's LBS, DQS and CoR batch jobs (the kernel of the
// instruction set chosen at run time) on one and two threads, positions and normals, against the
// plain per-vertex GLM code users write (glm::mat4 LBS, glm::dualquat DQS, glm::quat CoR; arrays of
// structures) in the same binary, and STREAM's triad measured in the same run as the roof; and
// DQS's bytes moved with no arithmetic (skin_streams), the most the memory allows its streams;
// and each method on one thread with each instruction set the CPU has forced (dqkit_skinning_on_target);
// small DQS jobs on one and two threads (dqkit_skinning_small_jobs), many jobs run one by one or
// in one call (dqkit_skinning_many_jobs), and DQS into rows against arrays converted to rows
// (dqkit_skinning_rows).
//
// The skin: at least 2^20 vertices and at least four times the last-level cache in bytes (read
// from the CPU), 4 influences each, 64 bones with random rigid binds and poses. Every GLM variant
// is checked once, outside the timing, against dqkit's result for the same method.
// Counters: vertices_per_s; bytes_per_second (the bytes a vertex moves: positions, normals, slot
// bones and weights in, positions and normals out, CoR's centres; write-allocate reads not counted,
// as for the triad); roofline = bytes_per_second ÷ the triad's, same thread count.
//   build/release/bench/bench_skin --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
// In L2 (4,096 vertices are 328 KB; 16,384 are 1.31 MB, more than a 1 MB L2):
//   DQKIT_BENCH_SKIN_VERTICES=4096 build/release/bench/bench_skin --benchmark_filter='dqkit'
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtx/dual_quaternion.hpp>
#include <glm/gtx/norm.hpp>
#include <random>
#include <thread>
#include <vector>

#include "dq/convert/matrix.hpp"
#include "dq/simd/batch.hpp"
#include "dq/skin/skinning.hpp"
#include "dq/util/component_arrays.hpp"
#include "machine.hpp"

namespace {

using namespace dq;

constexpr std::uint32_t kBones = 64;
constexpr std::size_t kInfluences = 4;

/// Bytes a vertex moves: positions and normals in (24), slot bones and weights (8 per slot), positions and
/// normals out (24), and for CoR the centre (12).
std::size_t bytes_per_vertex(SkinningMethod m) { return 24 + 8 * kInfluences + 24 + (m == SkinningMethod::cor ? 12 : 0); }

/// The skin's size: DQKIT_BENCH_SKIN_VERTICES if set (a positive count, rounded up to a multiple of
/// 16; a skin that fits in L2 times the kernels' instructions alone), else the size above.
std::size_t vertex_count() {
  if (const char* text = std::getenv("DQKIT_BENCH_SKIN_VERTICES")) {
    char* end = nullptr;
    const unsigned long long n = std::strtoull(text, &end, 10);
    if (end == text || *end != '\0' || n == 0 || n > (std::size_t{1} << 32)) {
      std::fprintf(stderr, "bench_skin: DQKIT_BENCH_SKIN_VERTICES must be a count from 1 to 2^32, not '%s'\n", text);
      std::exit(2);
    }
    return (static_cast<std::size_t>(n) + 15) / 16 * 16;
  }
  const std::size_t cache = 4 * bench::last_level_cache_bytes() / bytes_per_vertex(SkinningMethod::dqs);
  return (std::max<std::size_t>(std::size_t{1} << 20, cache) + 15) / 16 * 16;
}

double& triad_bandwidth(unsigned threads) {  // bytes/s, measured in main before the cases
  static double b[3] = {};
  return b[std::min(threads, 2u)];
}

struct Fixture {
  std::size_t n = vertex_count();
  Skin skin;  // built in the constructor
  std::vector<DualQuaternion<double>> pose;
  SkinPalette palette{kBones};
  // GLM's side: the same skin (dqkit's canonical influence order, so the same pivot) as arrays of structures.
  std::vector<glm::vec3> positions, normals, centers;
  std::vector<glm::uvec4> joints;
  std::vector<glm::vec4> weights;
  std::vector<glm::mat4> matrices;
  std::vector<glm::fdualquat> dual_quaternions;
  std::vector<glm::quat> rotations;

  Fixture() {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    auto rigid = [&] {
      const Quaternion<double> q = Quaternion<double>(u(rng), u(rng), u(rng), u(rng)).normalized();
      return DualQuaternion<double>::from_rotation_translation(q, {u(rng), u(rng), u(rng)});
    };
    RawSkin raw;
    raw.influence_offsets.push_back(0);
    // Bones drawn once per run of kRun vertices, as neighbouring vertices of a real mesh share
    // theirs; weights per vertex. (With bones drawn per vertex, the sign tests of GLM's DQS and CoR
    // loops became coin flips, mispredicted branches that a real skin does not cause.)
    constexpr std::size_t kRun = 64;
    std::uint32_t bones[kInfluences];
    for (std::size_t v = 0; v < n; ++v) {
      raw.positions.push_back({float(u(rng)), float(u(rng)), float(u(rng))});
      raw.normals.push_back(normalized(Vec3<float>{float(u(rng)), float(u(rng)), float(u(rng)) + 2}));
      if (v % kRun == 0)
        for (auto& b : bones) b = static_cast<std::uint32_t>(rng() % kBones);
      float w[kInfluences], sum = 0;
      for (float& x : w) sum += (x = float(u(rng)) + 1.1f);
      for (std::size_t k = 0; k < kInfluences; ++k) raw.influences.push_back({bones[k], w[k] / sum});
      raw.influence_offsets.push_back(static_cast<std::uint32_t>(raw.influences.size()));
    }
    std::vector<DualQuaternion<double>> bind(kBones);
    for (auto& b : bind) {
      b = rigid();
      raw.inverse_bind.push_back(to_mat4(b.conjugate()));
    }
    // No triangles: every vertex is its own centre of rotation (the work per vertex is the same).
    skin = *build_skin(raw);
    pose.resize(kBones);
    for (auto& p : pose) p = rigid();
    update_palette(skin, pose, palette);
    for (std::size_t v = 0; v < n; ++v) {
      positions.emplace_back(skin.px()[v], skin.py()[v], skin.pz()[v]);
      normals.emplace_back(skin.nx()[v], skin.ny()[v], skin.nz()[v]);
      centers.emplace_back(skin.cx()[v], skin.cy()[v], skin.cz()[v]);
      glm::uvec4 j;
      glm::vec4 w;
      for (std::size_t k = 0; k < kInfluences; ++k) j[int(k)] = skin.slot_bones(k)[v], w[int(k)] = skin.slot_weights(k)[v];
      joints.push_back(j);
      weights.push_back(w);
    }
    for (std::uint32_t b = 0; b < kBones; ++b) {
      const DualQuaternion<double> k = pose[b] * bind[b].conjugate();
      const Mat4<double> m = to_mat4(k);
      glm::mat4 g;
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) g[c][r] = float(m(r, c));
      matrices.push_back(g);
      dual_quaternions.emplace_back(glm::quat(float(k.real.w), float(k.real.x), float(k.real.y), float(k.real.z)),
                                    glm::quat(float(k.dual.w), float(k.dual.x), float(k.dual.y), float(k.dual.z)));
      rotations.push_back(dual_quaternions.back().real);
    }
  }
};

Fixture& fixture() {
  static Fixture f;
  return f;
}

/// dqkit's output: positions and normals, six arrays in one ComponentArrays (aligned to cache lines
/// and skewed, as the skin's arrays are: no two of the kernel's streams share their cache sets).
struct Output {
  ComponentArrays<float, 6> c;
  explicit Output(std::size_t n) : c(n) {}
  SkinnedVertices view() { return {c[0], c[1], c[2], c[3], c[4], c[5], {}, {}, {}}; }
};

void report(benchmark::State& state, SkinningMethod method, unsigned threads) {
  const double vertices = static_cast<double>(state.iterations()) * static_cast<double>(fixture().n);
  state.counters["vertices_per_s"] = benchmark::Counter(vertices, benchmark::Counter::kIsRate);
  const double bytes = vertices * static_cast<double>(bytes_per_vertex(method));
  state.SetBytesProcessed(static_cast<std::int64_t>(bytes));
  if (triad_bandwidth(threads) > 0) state.counters["roofline"] = benchmark::Counter(bytes / triad_bandwidth(threads), benchmark::Counter::kIsRate);
}

void time_skinning(benchmark::State& state, SkinningMethod method, unsigned threads) {
  Fixture& f = fixture();
  Output out(f.n);
  SkinningThreads pool(threads);
  state.SetLabel(std::string(simd::to_string(simd::current_target())));
  for (auto _ : state) {
    if (!pool.run({&f.skin, &f.palette, method, out.view(), 0, f.n})) state.SkipWithError("job does not validate");
    benchmark::DoNotOptimize(out.c[0].data());
    benchmark::ClobberMemory();
  }
  report(state, method, threads);
}
void dqkit_skinning(benchmark::State& state, SkinningMethod method) { time_skinning(state, method, static_cast<unsigned>(state.range(0))); }
/// DQS jobs of the skin's first `vertices` vertices (in cache after the first iteration) on a pool
/// of one and of two threads: what handing parts of a small job to a worker costs (docs/skinning.md,
/// "Threads").
void dqkit_skinning_small_jobs(benchmark::State& state) {
  Fixture& f = fixture();
  const std::size_t n = std::min(f.n, static_cast<std::size_t>(state.range(0)));
  Output out(n);
  SkinningThreads pool(static_cast<unsigned>(state.range(1)));
  for (auto _ : state) {
    if (!pool.run({&f.skin, &f.palette, SkinningMethod::dqs, out.view(), 0, n})) state.SkipWithError("job does not validate");
    benchmark::DoNotOptimize(out.c[0].data());
    benchmark::ClobberMemory();
  }
  state.counters["vertices_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()) * static_cast<double>(n), benchmark::Counter::kIsRate);
}
/// The skin's first 65,536 vertices (in cache) as `jobs` DQS jobs of equal size (the meshes of a
/// model), on a pool of one and of two threads: one run() per job, or one run() for them all, whose
/// parts the threads claim across the jobs (docs/skinning.md, "Threads").
void dqkit_skinning_many_jobs(benchmark::State& state) {
  Fixture& f = fixture();
  const std::size_t n = std::min<std::size_t>(f.n, 65536), count = static_cast<std::size_t>(state.range(0));
  Output out(n);
  std::vector<SkinningJob> jobs;
  for (std::size_t k = 0; k < count; ++k) jobs.push_back({&f.skin, &f.palette, SkinningMethod::dqs, out.view(), k * n / count, (k + 1) * n / count - k * n / count});
  SkinningThreads pool(static_cast<unsigned>(state.range(1)));
  const bool together = state.range(2) != 0;
  for (auto _ : state) {
    if (together) {
      if (!pool.run(jobs)) state.SkipWithError("jobs do not validate");
    } else {
      for (const SkinningJob& job : jobs)
        if (!pool.run(job)) state.SkipWithError("job does not validate");
    }
    benchmark::DoNotOptimize(out.c[0].data());
    benchmark::ClobberMemory();
  }
  state.counters["vertices_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()) * static_cast<double>(n), benchmark::Counter::kIsRate);
}
/// DQS's positions and normals wanted as rows (x, y, z a vertex: a NumPy (V, 3) array, a GPU vertex
/// buffer), from the whole skin: written as rows by the job (rows:1), or written as arrays and
/// then converted by dq::simd::from_rows on the calling thread (rows:0), the way to rows without
/// the rows output. The two are checked once, outside the timing, to agree bit for bit.
void dqkit_skinning_rows(benchmark::State& state) {
  Fixture& f = fixture();
  static_assert(sizeof(Vec3<float>) == 3 * sizeof(float));
  std::vector<Vec3<float>> positions(f.n), normals(f.n);
  const auto floats = [](std::vector<Vec3<float>>& v) { return std::span<float>(reinterpret_cast<float*>(v.data()), 3 * v.size()); };
  const SkinnedVertices as_rows{.positions = floats(positions), .normals = floats(normals)};
  Output arrays(f.n);
  SkinningThreads pool(static_cast<unsigned>(state.range(0)));
  const auto frame = [&](bool rows) {
    if (rows) return pool.run({&f.skin, &f.palette, SkinningMethod::dqs, as_rows, 0, f.n});
    const Status s = pool.run({&f.skin, &f.palette, SkinningMethod::dqs, arrays.view(), 0, f.n});
    simd::from_rows({arrays.c[0].data(), arrays.c[1].data(), arrays.c[2].data()}, positions);
    simd::from_rows({arrays.c[3].data(), arrays.c[4].data(), arrays.c[5].data()}, normals);
    return s;
  };
  const bool rows = state.range(1) != 0;
  if (!frame(!rows)) state.SkipWithError("job does not validate");
  const std::vector<Vec3<float>> expected_positions = positions, expected_normals = normals;
  if (!frame(rows)) state.SkipWithError("job does not validate");
  if (std::memcmp(positions.data(), expected_positions.data(), 12 * f.n) != 0 || std::memcmp(normals.data(), expected_normals.data(), 12 * f.n) != 0)
    state.SkipWithError("rows and arrays differ");
  state.SetLabel(std::string(simd::to_string(simd::current_target())));
  for (auto _ : state) {
    frame(rows);
    benchmark::DoNotOptimize(positions.data());
    benchmark::ClobberMemory();
  }
  state.counters["vertices_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()) * static_cast<double>(f.n), benchmark::Counter::kIsRate);
}
/// One thread with the instruction set forced (simd::ScopedTarget): what each target brings, in one
/// run. Registered in main for every target this CPU has.
void dqkit_skinning_on_target(benchmark::State& state, SkinningMethod method, simd::Target target) {
  const simd::ScopedTarget scope(target);
  time_skinning(state, method, 1);
}

// ---- the memory side alone ----------------------------------------------------------------------

/// DQS's traffic without its arithmetic: per vertex the 14 values it reads (position, normal, four
/// slot bones and weights) in and 6 out, 80 bytes, prefetched as the kernels prefetch (every stream,
/// once per cache line, kPrefetchAhead = 128 vertices ahead: src/skin/skinning.cpp). The values are
/// combined by exclusive or, one integer operation each. What share of the triad this reaches is
/// the most a kernel with the same streams and the same prefetching can reach (docs/skinning.md,
/// "The memory side").
/// `separate`: the skin's own arrays and six output arrays, the twenty streams the kernels read and
/// write. `interleaved`: the skin's values copied into blocks of 16 vertices (AoSoA: each block's
/// 14 × 16 values in, then 6 × 16 out), one stream in and one out.
enum class StreamLayout { separate, interleaved };

using Lanes = std::uint32_t __attribute__((vector_size(16)));
constexpr std::size_t kStreamsIn = 14, kStreamsOut = 6, kBlock = 16;

template <StreamLayout layout>
void skin_streams(benchmark::State& state) {
  constexpr std::size_t ahead = 128;  // the kernels' kPrefetchAhead
  constexpr bool interleaved = layout == StreamLayout::interleaved;
  Fixture& f = fixture();
  const std::size_t n = f.n;
  // The skin's input streams as 32-bit values (the floats by their bits).
  const std::uint32_t* skin_in[kStreamsIn];
  auto bits = [](std::span<const float> x) { return reinterpret_cast<const std::uint32_t*>(x.data()); };
  const std::span<const float> coordinates[] = {f.skin.px(), f.skin.py(), f.skin.pz(), f.skin.nx(), f.skin.ny(), f.skin.nz()};
  for (std::size_t c = 0; c < std::size(coordinates); ++c) skin_in[c] = bits(coordinates[c]);
  for (std::size_t k = 0; k < kInfluences; ++k) skin_in[6 + k] = f.skin.slot_bones(k).data(), skin_in[10 + k] = bits(f.skin.slot_weights(k));
  ComponentArrays<std::uint32_t, kStreamsOut> out(interleaved ? 0 : n);
  ComponentArrays<std::uint32_t, 1> blocks_in(interleaved ? kStreamsIn * n : 0), blocks_out(interleaved ? kStreamsOut * n : 0);
  // Stream c's values of the 16 vertices from v (a multiple of 16): in a block of `streams` streams,
  // or in the stream's own array.
  auto at_block = [](std::uint32_t* blocks, std::size_t streams, std::size_t c, std::size_t v) { return blocks + streams * v + kBlock * c; };
  auto in_at = [&](std::size_t c, std::size_t v) -> const std::uint32_t* {
    return interleaved ? at_block(blocks_in[0].data(), kStreamsIn, c, v) : skin_in[c] + v;
  };
  auto out_at = [&](std::size_t k, std::size_t v) {
    return interleaved ? at_block(blocks_out[0].data(), kStreamsOut, k, v) : out[k].data() + v;
  };
  if (interleaved)
    for (std::size_t v = 0; v < n; v += kBlock)
      for (std::size_t c = 0; c < kStreamsIn; ++c) std::copy_n(skin_in[c] + v, kBlock, at_block(blocks_in[0].data(), kStreamsIn, c, v));
  for (auto _ : state) {
    for (std::size_t v = 0; v < n; v += kBlock) {
      if (v + ahead < n) {
        for (std::size_t c = 0; c < kStreamsIn; ++c) __builtin_prefetch(in_at(c, v + ahead), 0, 3);
        for (std::size_t k = 0; k < kStreamsOut; ++k) __builtin_prefetch(out_at(k, v + ahead), 1, 3);
      }
      for (std::size_t q = 0; q < kBlock; q += 4) {
        Lanes o[kStreamsOut] = {};
        for (std::size_t c = 0; c < kStreamsIn; ++c) {
          Lanes x;
          std::memcpy(&x, in_at(c, v) + q, sizeof x);
          o[c % kStreamsOut] ^= x;
        }
        for (std::size_t k = 0; k < kStreamsOut; ++k) std::memcpy(out_at(k, v) + q, &o[k], sizeof o[k]);
      }
    }
    benchmark::DoNotOptimize(interleaved ? blocks_out[0].data() : out[0].data());
    benchmark::ClobberMemory();
  }
  report(state, SkinningMethod::dqs, 1);
}

// ---- plain per-vertex GLM ------------------------------------------------------------------

/// LBS's blended matrix at vertex v, as glm_lbs_range computes it. Always inlined: GCC 12 kept it
/// out of line, a call per vertex returning the matrix through memory.
[[gnu::always_inline]] inline glm::mat4 lbs_matrix(const Fixture& f, std::size_t v) {
  const glm::uvec4 j = f.joints[v];
  const glm::vec4 w = f.weights[v];
  return f.matrices[j.x] * w.x + f.matrices[j.y] * w.y + f.matrices[j.z] * w.z + f.matrices[j.w] * w.w;
}

void glm_lbs_range(const Fixture& f, std::vector<glm::vec3>& p, std::vector<glm::vec3>& n, std::size_t b, std::size_t e) {
  for (std::size_t v = b; v < e; ++v) {
    const glm::mat4 m = lbs_matrix(f, v);
    p[v] = glm::vec3(m * glm::vec4(f.positions[v], 1));
    n[v] = glm::normalize(glm::transpose(glm::inverse(glm::mat3(m))) * f.normals[v]);
  }
}

void glm_dqs_range(const Fixture& f, std::vector<glm::vec3>& p, std::vector<glm::vec3>& n, std::size_t b, std::size_t e) {
  for (std::size_t v = b; v < e; ++v) {
    const glm::uvec4 j = f.joints[v];
    const glm::vec4 w = f.weights[v];
    const glm::fdualquat& q0 = f.dual_quaternions[j.x];
    glm::fdualquat blend = q0 * w.x;
    for (int k = 1; k < 4; ++k) {
      const glm::fdualquat& q = f.dual_quaternions[j[k]];
      blend = blend + q * (glm::dot(q.real, q0.real) < 0 ? -w[k] : w[k]);
    }
    blend = glm::normalize(blend);
    const glm::mat3x4 m = glm::mat3x4_cast(blend);  // rows are the transform's rows
    const glm::vec4 x(f.positions[v], 1);
    p[v] = glm::vec3(glm::dot(m[0], x), glm::dot(m[1], x), glm::dot(m[2], x));
    n[v] = blend.real * f.normals[v];
  }
}

void glm_cor_range(const Fixture& f, std::vector<glm::vec3>& p, std::vector<glm::vec3>& n, std::size_t b, std::size_t e) {
  for (std::size_t v = b; v < e; ++v) {
    const glm::uvec4 j = f.joints[v];
    const glm::vec4 w = f.weights[v];
    const glm::quat& q0 = f.rotations[j.x];
    glm::quat q = q0 * w.x;
    for (int k = 1; k < 4; ++k) {
      const glm::quat& r = f.rotations[j[k]];
      q = q + r * (glm::dot(r, q0) < 0 ? -w[k] : w[k]);
    }
    q = glm::normalize(q);
    const glm::mat4 m = lbs_matrix(f, v);
    const glm::vec3 c = f.centers[v];
    p[v] = q * (f.positions[v] - c) + glm::vec3(m * glm::vec4(c, 1));
    n[v] = q * f.normals[v];
  }
}

/// Whether GLM's positions and normals are dqkit's for the same method (float rounding apart).
/// LBS normals: GLM's inverse transpose and dqkit's cofactor matrix differ by the factor det, so
/// they point opposite ways where a blend of rotations has a negative determinant.
bool same_result(const Fixture& f, SkinningMethod method, const std::vector<glm::vec3>& p, const std::vector<glm::vec3>& n) {
  Output out(f.n);
  SkinningThreads pool(1);
  if (!pool.run({&f.skin, &f.palette, method, out.view(), 0, f.n})) return false;
  for (std::size_t v = 0; v < f.n; ++v) {
    const glm::vec3 dp(out.c[0][v], out.c[1][v], out.c[2][v]), dn(out.c[3][v], out.c[4][v], out.c[5][v]);
    const float det = method == SkinningMethod::lbs ? glm::determinant(glm::mat3(lbs_matrix(f, v))) : 1.0f;
    const float sign = det < 0 ? -1.0f : 1.0f;
    // Where the LBS blend is nearly singular (it collapses there), the normal's direction rests on
    // the rounding of both codes: one vertex in 26.6 million (det -1.2e-6) differed by 1.1e-4. Only
    // the position is compared there.
    const bool normal_defined = std::abs(det) >= 1e-3f;
    // Coordinates up to about 4 (|p| ≤ √3, translations ≤ √3 twice); normals unit.
    if (!(glm::length(dp - p[v]) <= 1e-4f && (!normal_defined || glm::length(dn - sign * n[v]) <= 1e-4f))) return false;
  }
  return true;
}

template <void (*Range)(const Fixture&, std::vector<glm::vec3>&, std::vector<glm::vec3>&, std::size_t, std::size_t)>
void glm_skinning(benchmark::State& state, SkinningMethod method) {
  const Fixture& f = fixture();
  std::vector<glm::vec3> p(f.n), n(f.n);
  const auto threads = static_cast<unsigned>(state.range(0));
  for (auto _ : state) {
    if (threads == 1) {
      Range(f, p, n, 0, f.n);
    } else {
      // One extra thread started per frame (what a plain implementation does).
      std::jthread other([&] { Range(f, p, n, f.n / 2, f.n); });
      Range(f, p, n, 0, f.n / 2);
    }
    benchmark::DoNotOptimize(p.data());
    benchmark::ClobberMemory();
  }
  if (!same_result(f, method, p, n)) state.SkipWithError("GLM and dqkit disagree");
  report(state, method, threads);
}

void glm_lbs(benchmark::State& s) { glm_skinning<glm_lbs_range>(s, SkinningMethod::lbs); }
void glm_dqs(benchmark::State& s) { glm_skinning<glm_dqs_range>(s, SkinningMethod::dqs); }
void glm_cor(benchmark::State& s) { glm_skinning<glm_cor_range>(s, SkinningMethod::cor); }

}  // namespace

BENCHMARK(dq::bench::Triad)->Name("Triad")->Arg(1)->Arg(2)->UseRealTime();
BENCHMARK_CAPTURE(dqkit_skinning, lbs, SkinningMethod::lbs)->Arg(1)->Arg(2)->UseRealTime();
BENCHMARK_CAPTURE(dqkit_skinning, dqs, SkinningMethod::dqs)->Arg(1)->Arg(2)->UseRealTime();
BENCHMARK_CAPTURE(dqkit_skinning, cor, SkinningMethod::cor)->Arg(1)->Arg(2)->UseRealTime();
BENCHMARK(dqkit_skinning_many_jobs)->Name("dqkit_skinning_many_jobs/dqs")->ArgNames({"jobs", "threads", "together"})->ArgsProduct({{4, 16, 64}, {1, 2}, {0, 1}})->UseRealTime();
BENCHMARK(dqkit_skinning_rows)->Name("dqkit_skinning_rows/dqs")->ArgNames({"threads", "rows"})->ArgsProduct({{1, 2}, {0, 1}})->UseRealTime();
BENCHMARK(dqkit_skinning_small_jobs)->Name("dqkit_skinning_small_jobs/dqs")->ArgsProduct({{1024, 2048, 4096, 8192, 16384, 65536}, {1, 2}})->UseRealTime();
BENCHMARK(skin_streams<StreamLayout::separate>)->Name("skin_streams/separate")->UseRealTime();
BENCHMARK(skin_streams<StreamLayout::interleaved>)->Name("skin_streams/interleaved")->UseRealTime();
BENCHMARK(glm_lbs)->Arg(1)->Arg(2)->UseRealTime();
BENCHMARK(glm_dqs)->Arg(1)->Arg(2)->UseRealTime();
BENCHMARK(glm_cor)->Arg(1)->Arg(2)->UseRealTime();

int main(int argc, char** argv) {
  benchmark::AddCustomContext("cpu_model", dq::bench::cpu_model());
  dq::bench::add_cache_context();
  benchmark::AddCustomContext("simd_target", std::string(dq::simd::to_string(dq::simd::best_target())));
  benchmark::AddCustomContext("vertices", std::to_string(vertex_count()));
  benchmark::Initialize(&argc, argv);
  for (const auto& [name, method] : {std::pair{"lbs", SkinningMethod::lbs}, {"dqs", SkinningMethod::dqs}, {"cor", SkinningMethod::cor}})
    for (dq::simd::Target target : dq::simd::available_targets())
      benchmark::RegisterBenchmark(("dqkit_skinning_on_target/" + std::string(name) + "/" + std::string(dq::simd::to_string(target))).c_str(),
                                   dqkit_skinning_on_target, method, target)
          ->UseRealTime();
  for (unsigned t : {1u, 2u}) {
    triad_bandwidth(t) = dq::bench::measure_bandwidth(dq::bench::Stream::triad, t);
    benchmark::AddCustomContext("triad_GBps_" + std::to_string(t) + "thread", std::to_string(triad_bandwidth(t) / 1e9));
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
