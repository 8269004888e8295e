// Skinning: the skin contract (validation, normalization, canonical order), LBS / DQS / CoR
// against independent computations (Kavan's formula through matrices, the glTF 2.0 skinning
// formula on simple_skin.gltf read by tinygltf, Assimp's own node matrices), invariances (order
// of influences, sign of bone dual quaternions), threads, the scale policy and the file formats.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <thread>
#include <cstdlib>
#include <new>
#include <cfenv>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <sched.h>
#include <functional>
#include <limits>
#include <numeric>
#include <utility>

#include "dq/anim/forward_kinematics.hpp"
#include "dq/convert/matrix.hpp"
#include "dq/simd/batch.hpp"
#include "dq/skin/scene_skin.hpp"
#include "dq/skin/shapes.hpp"
#include "dq/skin/skinning.hpp"
#include "simd_targets.hpp"
#include "support.hpp"

#if defined(DQKIT_TEST_IMPORT)
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <tiny_gltf.h>

#include <map>

#include "dq/io/scene.hpp"
#include "models.hpp"
#endif

// Allocations counted while `counting` is set (to show that a frame allocates nothing). GCC
// inlines these replacements into callers and then mistakes the matching malloc/free for a mismatch.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
namespace {
std::atomic<bool> counting{false};
std::atomic<long> allocations{0};
}  // namespace
void* operator new(std::size_t n) {
  if (counting) ++allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace dq {
namespace {

using test::Random;

// The kernels compute in float. A skinned coordinate is a short sum of products of quantities of
// the model's size S (about 20 roundings, each ≤ ½ ulp of S), so results that agree in exact
// arithmetic agree to 64 float epsilons of S; double references are exact to that scale.
float position_tolerance(float size) { return 64 * FLT_EPSILON * size; }

struct Output {
  std::vector<float> px, py, pz, nx, ny, nz, tx, ty, tz;
  explicit Output(std::size_t n) : px(n), py(n), pz(n), nx(n), ny(n), nz(n), tx(n), ty(n), tz(n) {}
  SkinnedVertices view(bool normals, bool tangents) {
    SkinnedVertices v{.px = px, .py = py, .pz = pz};
    if (normals) v.nx = nx, v.ny = ny, v.nz = nz;
    if (tangents) v.tx = tx, v.ty = ty, v.tz = tz;
    return v;
  }
  /// Every element of every array set to x (a sentinel that a job must not overwrite).
  void fill(float x) {
    for (auto part : parts) std::fill((this->*part).begin(), (this->*part).end(), x);
  }
  Vec3<float> p(std::size_t v) const { return {px[v], py[v], pz[v]}; }
  Vec3<float> n(std::size_t v) const { return {nx[v], ny[v], nz[v]}; }
  Vec3<float> t(std::size_t v) const { return {tx[v], ty[v], tz[v]}; }
  static constexpr std::vector<float> Output::*parts[] = {&Output::px, &Output::py, &Output::pz, &Output::nx, &Output::ny,
                                                          &Output::nz, &Output::tx, &Output::ty, &Output::tz};
};

/// On `threads` threads with parts of 16 vertices and more, so that small skins are split too.
Output run(const Skin& skin, std::span<const DualQuaternion<double>> world, SkinningMethod method, unsigned threads = 1) {
  SkinPalette palette(skin.bone_count());
  update_palette(skin, world, palette);
  Output out(skin.vertex_count());
  SkinningThreads pool(threads, 16);
  const Status s = pool.run({&skin, &palette, method, out.view(skin.has_normals(), skin.has_tangents()), 0, skin.vertex_count()});
  EXPECT_TRUE(s.ok()) << s.error().message;
  return out;
}

/// A random skin: `bones` bones with rigid random binds, vertices with 1..max_k influences.
RawSkin random_skin(Random& rng, std::size_t vertices, std::uint32_t bones, std::size_t max_k) {
  RawSkin raw;
  raw.influence_offsets.push_back(0);
  for (std::size_t v = 0; v < vertices; ++v) {
    const Vec3<double> p = rng.vec3(2.0);
    raw.positions.push_back({float(p.x), float(p.y), float(p.z)});
    const Vec3<double> n = normalized(rng.vec3(1.0));
    raw.normals.push_back({float(n.x), float(n.y), float(n.z)});
    const std::size_t k = 1 + v % max_k;
    std::vector<double> w(k);
    for (double& x : w) x = rng.uniform(0.05, 1.0);
    const double sum = std::accumulate(w.begin(), w.end(), 0.0);
    for (std::size_t i = 0; i < k; ++i)
      raw.influences.push_back({static_cast<std::uint32_t>(rng.engine()() % bones), static_cast<float>(w[i] / sum)});
    raw.influence_offsets.push_back(static_cast<std::uint32_t>(raw.influences.size()));
  }
  for (std::uint32_t b = 0; b < bones; ++b) raw.inverse_bind.push_back(to_mat4(rng.rigid(3.0)));
  return raw;
}

std::vector<DualQuaternion<double>> random_pose(Random& rng, std::size_t bones) {
  std::vector<DualQuaternion<double>> w(bones);
  for (auto& q : w) q = rng.rigid(3.0);
  return w;
}

// ---- the contract ----------------------------------------------------------------------------

TEST(SkinContract, RejectsBadInputWithReasons) {
  Random rng(1);
  const RawSkin good = random_skin(rng, 10, 3, 3);
  ASSERT_TRUE(build_skin(good).has_value());
  auto expect_error = [](const RawSkin& raw, const std::string& part, SkinOptions options = {}) {
    const Expected<Skin> s = build_skin(raw, options);
    ASSERT_FALSE(s.has_value());
    EXPECT_NE(s.error().message.find(part), std::string::npos) << s.error().message;
  };
  RawSkin r = good;
  r.influences[4].bone = 7;
  expect_error(r, "bone index 7 is out of range");
  r = good;
  r.influences[2].weight = std::nanf("");
  expect_error(r, "not a finite non-negative number");
  r = good;
  r.influences[2].weight = -0.1f;
  expect_error(r, "not a finite non-negative number");
  r = good;
  r.positions[3].y = INFINITY;
  expect_error(r, "vertex 3: the position is not finite");
  r = good;
  r.influences[0].weight = 0;  // vertex 0 has one influence
  expect_error(r, "vertex 0: has no weight");
  r = good;
  r.influences[1].weight *= 2;  // vertex 1 sums to more than 1
  expect_error(r, "vertex 1: the weights sum to", {WeightPolicy::reject});
  r = good;
  r.normals.pop_back();
  expect_error(r, "normals for 10 vertices");
  r = good;
  r.inverse_bind[1](0, 0) = -r.inverse_bind[1](0, 0), r.inverse_bind[1](1, 0) = -r.inverse_bind[1](1, 0), r.inverse_bind[1](2, 0) = -r.inverse_bind[1](2, 0);
  expect_error(r, "bone 1: the inverse bind matrix mirrors");
  r = good;
  r.inverse_bind[0](3, 1) = 0.5;
  expect_error(r, "bone 0: the inverse bind matrix is not affine");
  r = good;
  r.triangles = {0, 1, 10};
  expect_error(r, "triangle 0 has a vertex index out of range");
}

TEST(SkinContract, JobsThatCannotRunAreRefusedWithReasons) {
  Random rng(2);
  RawSkin raw = random_skin(rng, 10, 3, 3);
  const Skin skin = *build_skin(raw);
  ASSERT_TRUE(skin.has_normals());
  SkinPalette palette(skin.bone_count());
  update_palette(skin, random_pose(rng, 3), palette);
  Output out(10);
  const auto refused = [&](const SkinningJob& job, const std::string& part) {
    const Status s = job.validate();
    ASSERT_FALSE(s.ok()) << "accepted, expected: " << part;
    EXPECT_NE(s.error().message.find(part), std::string::npos) << s.error().message;
  };
  const SkinningJob good{&skin, &palette, SkinningMethod::dqs, out.view(true, false), 0, 10};
  ASSERT_TRUE(good.validate().ok());
  SkinningJob job = good;
  job.out.ny = {}, job.out.nz = {};  // nx alone: run() would write normals through empty ny, nz
  refused(job, "normals need all three arrays");
  job = good;
  job.out.tx = out.tx;
  refused(job, "tangents need all three arrays");
  job = good;
  job.out.py = job.out.px;
  refused(job, "two output arrays overlap");
  job = good;
  job.out.nz = std::span<float>(out.px).subspan(5);  // overlaps px in [5, 10), and too short
  refused(job, "an array is too short");
  job.out.nz = std::span<float>(out.nx).subspan(0, 10), job.out.nx = std::span<float>(out.pz);
  refused(job, "two output arrays overlap");
  job = good;
  job.count = 11;
  refused(job, "the vertex range exceeds the skin");
  job = good;
  job.out.pz = std::span<float>(out.pz).subspan(0, 9);
  refused(job, "a position array is shorter than the vertex range");
  job.out.py = job.out.pz = {};
  refused(job, "positions need all three arrays (px, py, pz) or rows");
  job.first = job.count = 0;  // not even for an empty range
  refused(job, "positions need all three arrays (px, py, pz) or rows");
  // Disjoint parts of one buffer are fine: outputs over [first, first + count) only.
  std::vector<float> one(30);
  job = good;
  job.out = {.px = std::span<float>(one).subspan(0, 10), .py = std::span<float>(one).subspan(10, 10), .pz = std::span<float>(one).subspan(20, 10)};
  EXPECT_TRUE(job.validate().ok());
  // Rows: three floats a vertex, in place of a quantity's arrays, over [3 first, 3 (first + count)).
  std::vector<float> rows(60);
  const std::span<float> positions = std::span<float>(rows).subspan(0, 30), normals = std::span<float>(rows).subspan(30);
  job = good;
  job.out.positions = positions;
  refused(job, "positions given both as rows and as arrays (px, py, pz)");
  job.out.px = job.out.py = job.out.pz = {};
  EXPECT_TRUE(job.validate().ok());
  job.out.normals = normals;
  refused(job, "normals given both as rows and as arrays (nx, ny, nz)");
  job.out.nx = job.out.ny = job.out.nz = {};
  EXPECT_TRUE(job.validate().ok());  // both quantities as rows, in one buffer
  job.out.positions = positions.first(29);
  refused(job, "the rows of positions are shorter than the vertex range (3 floats a vertex)");
  job.out.positions = positions, job.out.normals = normals.first(29);
  refused(job, "the rows of normals are shorter than the vertex range");
  job.out.normals = normals, job.out.positions = positions.first(29);
  job.first = 1, job.count = 9;  // rows start at vertex 0, so the range's end decides
  refused(job, "the rows of positions are shorter than the vertex range");
  job.first = 0, job.count = 9;
  EXPECT_TRUE(job.validate().ok());
  job = good;
  job.out.px = job.out.py = job.out.pz = {};
  job.out.positions = std::span<float>(rows).subspan(1, 30);  // vertex 9's rows hold normal 0's x
  job.out.nx = std::span<float>(rows).subspan(30, 10);
  refused(job, "two output arrays overlap");
  job.out.nx = out.nx, job.out.positions = positions;
  job.out.tangents = normals;  // the skin has no tangents
  refused(job, "tangents requested but the skin has none");
  job.out.tangents = {};
  job.out.nx = job.out.ny = job.out.nz = {};
  job.out.normals = std::span<float>(rows).subspan(27);  // normal 0 is position 9
  refused(job, "two output arrays overlap");
  job.first = 0, job.count = 9;  // not in [0, 9)
  EXPECT_TRUE(job.validate().ok());
  // Empty rows are not given, whatever their pointer: the arrays are written, the rows' buffer
  // not (and tangents that the skin does not have are not asked for).
  std::vector<float> untouched(30, -1.0f);
  job = good;
  job.out.positions = job.out.normals = job.out.tangents = std::span<float>(untouched).first(0);
  ASSERT_TRUE(job.validate().ok());
  job.run();
  Output expected(10);
  SkinningJob{&skin, &palette, SkinningMethod::dqs, expected.view(true, false), 0, 10}.run();
  for (float x : untouched) ASSERT_EQ(x, -1.0f);
  for (std::size_t v = 0; v < 10; ++v) {
    ASSERT_EQ(out.p(v), expected.p(v)) << "vertex " << v;
    ASSERT_EQ(out.n(v), expected.n(v)) << "vertex " << v;
  }
}

TEST(SkinContract, NormalizesOnceAndOrdersCanonically) {
  RawSkin raw;
  raw.positions = {{0, 0, 0}, {1, 0, 0}};
  raw.influence_offsets = {0, 3, 4};
  raw.influences = {{2, 0.2f}, {0, 0.4f}, {1, 0.4f}, {1, 0.5f}};  // vertex 0 sums to 1; vertex 1 to 0.5
  raw.inverse_bind.assign(3, Mat4<double>::identity());
  const Expected<Skin> skin = build_skin(raw);
  ASSERT_TRUE(skin.has_value()) << skin.error().message;
  EXPECT_EQ(skin->renormalized_vertices(), 1u);
  ASSERT_EQ(skin->slots(), 3u);
  auto bone = [&](std::size_t k, std::size_t v) { return skin->slot_bones(k)[v]; };
  auto weight = [&](std::size_t k, std::size_t v) { return skin->slot_weights(k)[v]; };
  // Vertex 0: weight descending, ties by bone (0 before 1), then bone 2.
  EXPECT_EQ(bone(0, 0), 0u);
  EXPECT_EQ(bone(1, 0), 1u);
  EXPECT_EQ(bone(2, 0), 2u);
  EXPECT_FLOAT_EQ(weight(0, 0) + weight(1, 0) + weight(2, 0), 1.0f);
  // Vertex 1: one influence, normalized to 1, padded with weight 0 on its own bone.
  EXPECT_EQ(weight(0, 1), 1.0f);
  EXPECT_EQ(weight(1, 1), 0.0f);
  EXPECT_EQ(weight(2, 1), 0.0f);
  EXPECT_EQ(bone(1, 1), 1u);
}

// ---- DQS against independent computations ----------------------------------------------------

TEST(Skinning, DqsEqualsLbsWhereAllInfluencesAreOneBone) {
  Random rng(2);
  RawSkin raw = random_skin(rng, 300, 5, 4);
  // Every vertex's influences on one bone (several entries of the same bone, as files may have).
  for (std::size_t v = 0; v + 1 < raw.influence_offsets.size(); ++v)
    for (std::uint32_t i = raw.influence_offsets[v]; i < raw.influence_offsets[v + 1]; ++i) raw.influences[i].bone = static_cast<std::uint32_t>(v % 5);
  const Skin skin = *build_skin(raw);
  const auto pose = random_pose(rng, 5);
  const Output lbs = run(skin, pose, SkinningMethod::lbs), dqs = run(skin, pose, SkinningMethod::dqs), cor = run(skin, pose, SkinningMethod::cor);
  const float tol = position_tolerance(8);  // |p| ≤ 2√3, binds and poses move by ≤ 3√3
  for (std::size_t v = 0; v < skin.vertex_count(); ++v) {
    EXPECT_LE(test::max_abs_diff(dqs.p(v), lbs.p(v)), tol) << "vertex " << v;
    EXPECT_LE(test::max_abs_diff(cor.p(v), lbs.p(v)), tol) << "vertex " << v;
    EXPECT_LE(test::max_abs_diff(dqs.n(v), lbs.n(v)), position_tolerance(1)) << "vertex " << v;
  }
}

TEST(Skinning, DqsEqualsKavansFormulaThroughMatrices) {
  Random rng(3);
  const RawSkin raw = random_skin(rng, 500, 6, 5);
  const Skin skin = *build_skin(raw);
  const auto pose = random_pose(rng, 6);
  const Output dqs = run(skin, pose, SkinningMethod::dqs);
  // Reference (double): each bone's matrix W · B⁻¹ converted to a dual quaternion, blended with
  // signs taken against the influence of largest weight, normalized, converted back to a matrix.
  for (std::size_t v = 0; v < skin.vertex_count(); ++v) {
    const auto first = raw.influences.begin() + raw.influence_offsets[v], last = raw.influences.begin() + raw.influence_offsets[v + 1];
    const auto pivot = std::max_element(first, last, [](const RawSkinInfluence& a, const RawSkinInfluence& b) {
      return a.weight != b.weight ? a.weight < b.weight : a.bone > b.bone;
    });
    auto dq_of = [&](std::uint32_t b) { return from_matrix(to_mat4(pose[b]) * raw.inverse_bind[b]); };
    const DualQuaternion<double> q0 = dq_of(pivot->bone);
    DualQuaternion<double> blend{{0, 0, 0, 0}, {0, 0, 0, 0}};
    double wsum = 0;
    for (auto i = first; i != last; ++i) wsum += double(i->weight);
    for (auto i = first; i != last; ++i) {
      const DualQuaternion<double> q = dq_of(i->bone);
      blend += q * (dot(q.real, q0.real) < 0 ? -double(i->weight) / wsum : double(i->weight) / wsum);
    }
    const double n = std::sqrt(dot(blend.real, blend.real));
    const Mat4<double> m = to_mat4(DualQuaternion<double>{blend.real / n, blend.dual / n});
    const Vec3<double> expected = transform_point(m, raw.positions[v].cast<double>());
    EXPECT_LE(test::max_abs_diff(dqs.p(v), Vec3<float>{float(expected.x), float(expected.y), float(expected.z)}), position_tolerance(8)) << "vertex " << v;
  }
}

TEST(Skinning, UnchangedByInfluenceOrderAndBoneSigns) {
  Random rng(4);
  const RawSkin raw = random_skin(rng, 400, 6, 6);
  RawSkin reversed = raw;
  for (std::size_t v = 0; v + 1 < raw.influence_offsets.size(); ++v)
    std::reverse(reversed.influences.begin() + raw.influence_offsets[v], reversed.influences.begin() + raw.influence_offsets[v + 1]);
  const Skin a = *build_skin(raw), b = *build_skin(reversed);
  auto pose = random_pose(rng, 6);
  auto flipped = pose;
  for (std::size_t i = 0; i < flipped.size(); i += 2) flipped[i] = -flipped[i];
  for (SkinningMethod m : {SkinningMethod::lbs, SkinningMethod::dqs, SkinningMethod::cor}) {
    const Output x = run(a, pose, m), y = run(b, pose, m), z = run(a, flipped, m);
    // Bit for bit: the canonical order makes the sums identical, and a sign flip negates exactly.
    EXPECT_EQ(x.px, y.px);
    EXPECT_EQ(x.py, y.py);
    EXPECT_EQ(x.pz, y.pz);
    EXPECT_EQ(x.nx, y.nx);
    EXPECT_EQ(x.px, z.px);
    EXPECT_EQ(x.py, z.py);
    EXPECT_EQ(x.pz, z.pz);
    EXPECT_EQ(x.nz, z.nz);
  }
}

TEST(Skinning, ThreadsGiveTheSameResult) {
  Random rng(5);
  const Skin skin = *build_skin(random_skin(rng, 1003, 7, 4));
  const auto pose = random_pose(rng, 7);
  for (SkinningMethod m : {SkinningMethod::lbs, SkinningMethod::dqs, SkinningMethod::cor}) {
    const Output one = run(skin, pose, m, 1), three = run(skin, pose, m, 3);
    EXPECT_EQ(one.px, three.px);
    EXPECT_EQ(one.nz, three.nz);
  }
}

/// True when `out`'s positions and normals hold `expected`'s in [first, first + count), bit for bit,
/// and the sentinel `fill` elsewhere.
::testing::AssertionResult holds_range(const Output& out, const Output& expected, std::size_t first, std::size_t count, float fill) {
  for (auto part : {&Output::px, &Output::py, &Output::pz, &Output::nx, &Output::ny, &Output::nz})
    for (std::size_t v = 0; v < (out.*part).size(); ++v) {
      const float want = v >= first && v - first < count ? (expected.*part)[v] : fill;
      if (std::memcmp(&(out.*part)[v], &want, sizeof(float)) != 0)
        return ::testing::AssertionFailure() << "vertex " << v << ": " << (out.*part)[v] << " where " << want << " belongs";
    }
  return ::testing::AssertionSuccess();
}

// The pool cuts a job into parts that its threads claim: for counts around the part sizes, on 2, 3
// and 5 threads, with parts of 16 vertices and more, 48 and more and the default, the result is the
// one-thread result bit for bit, and nothing outside the range is written.
TEST(Skinning, ThreadsClaimPartsOfEveryCount) {
  Random rng(8);
  const std::size_t min = SkinningThreads::kDefaultMinPart, n = 3 * min + 100;
  const Skin skin = *build_skin(random_skin(rng, n, 11, 4));
  SkinPalette palette(skin.bone_count());
  update_palette(skin, random_pose(rng, 11), palette);
  Output reference(n);
  ASSERT_TRUE(SkinningThreads(1).run({&skin, &palette, SkinningMethod::dqs, reference.view(true, false), 0, n}).ok());
  const float fill = -std::numeric_limits<float>::quiet_NaN();
  for (unsigned threads : {2u, 3u, 5u})
    for (auto [asked, min_part] : {std::pair<std::size_t, std::size_t>{0, 16}, {33, 48}, {min, min}}) {
      SkinningThreads pool(threads, asked);
      ASSERT_EQ(pool.size(), threads);
      ASSERT_EQ(pool.min_part(), min_part);
      for (std::size_t first : {std::size_t{0}, std::size_t{5}})
        for (std::size_t count : {std::size_t{0}, std::size_t{1}, std::size_t{17}, min - 1, min, min + 1, 2 * min + 3, n - first}) {
          SCOPED_TRACE(std::to_string(threads) + " threads, parts of " + std::to_string(min_part) + " and more, vertices " +
                       std::to_string(first) + " + " + std::to_string(count));
          Output out(n);
          out.fill(fill);
          ASSERT_TRUE(pool.run({&skin, &palette, SkinningMethod::dqs, out.view(true, false), first, count}).ok());
          ASSERT_TRUE(holds_range(out, reference, first, count, fill));
        }
    }
  SkinningThreads largest(2, std::numeric_limits<std::size_t>::max());  // rounded down to the last multiple of 16
  ASSERT_EQ(largest.min_part(), std::numeric_limits<std::size_t>::max() - 15);
  Output out(n);
  ASSERT_TRUE(largest.run({&skin, &palette, SkinningMethod::dqs, out.view(true, false), 0, n}).ok());
  ASSERT_TRUE(holds_range(out, reference, 0, n, 0.0f));
}

// Jobs back to back on one pool, alternating between two outputs, two palettes and two ranges,
// each output reset before its job: a worker that wakes late must not run a part of one job with
// another's data, nor leave a part undone. Every tenth job comes after a pause longer than the
// workers' spin, so that they sleep and are woken, as between frames; and once more with workers
// that sleep as soon as their parts are done.
TEST(Skinning, ThreadsRunJobsBackToBack) {
  Random rng(9);
  const std::size_t n = 2000, first[2] = {0, 7}, count[2] = {n, n - 300};
  const Skin skin = *build_skin(random_skin(rng, n, 11, 4));
  std::vector<SkinPalette> palettes;
  std::vector<Output> out, reference;
  for (std::size_t k = 0; k < 2; ++k) {
    palettes.emplace_back(skin.bone_count());
    update_palette(skin, random_pose(rng, 11), palettes[k]);
    out.emplace_back(n);
    reference.emplace_back(n);
    ASSERT_TRUE(SkinningThreads(1).run({&skin, &palettes[k], SkinningMethod::dqs, reference[k].view(true, false), 0, n}).ok());
  }
  const float fill = -std::numeric_limits<float>::quiet_NaN();
  for (unsigned spin : {SkinningThreads::kWorkerSpinMicroseconds, 0u}) {  // workers that spin between calls, and that do not
    SkinningThreads pool(3, 16, spin);
    ASSERT_EQ(pool.worker_spin_microseconds(), spin);
    for (std::size_t i = 0; i < 400; ++i) {
      const std::size_t k = i % 2;
      if (i % 10 == 0) std::this_thread::sleep_for(std::chrono::microseconds(3 * SkinningThreads::kWorkerSpinMicroseconds));
      out[k].fill(fill);
      ASSERT_TRUE(pool.run({&skin, &palettes[k], SkinningMethod::dqs, out[k].view(true, false), first[k], count[k]}).ok());
      ASSERT_TRUE(holds_range(out[k], reference[k], first[k], count[k], fill)) << "job " << i << ", workers spinning " << spin << " us";
    }
  }
}

// By default workers spin only where the pool has a CPU per thread, by the affinity mask; a spin
// asked for is kept. With the mask cut to one CPU (this thread's, which the workers inherit), a
// pool of two no longer spins.
TEST(Skinning, ThreadsSpinOnlyWhereEveryThreadHasACpu) {
  cpu_set_t all;
  ASSERT_EQ(sched_getaffinity(0, sizeof all, &all), 0);
  const unsigned cpus = static_cast<unsigned>(CPU_COUNT(&all));
  EXPECT_EQ(SkinningThreads(1).worker_spin_microseconds(), SkinningThreads::kWorkerSpinMicroseconds);
  EXPECT_EQ(SkinningThreads(cpus).worker_spin_microseconds(), SkinningThreads::kWorkerSpinMicroseconds);
  EXPECT_EQ(SkinningThreads(cpus + 1).worker_spin_microseconds(), 0u);
  EXPECT_EQ(SkinningThreads(cpus + 1, 16, 7).worker_spin_microseconds(), 7u);
  cpu_set_t one;
  CPU_ZERO(&one);
  for (std::size_t c = 0; c < std::size_t{CPU_SETSIZE}; ++c)
    if (CPU_ISSET(c, &all)) {
      CPU_SET(c, &one);
      break;
    }
  ASSERT_EQ(sched_setaffinity(0, sizeof one, &one), 0);
  const unsigned one_cpu_two = SkinningThreads(2).worker_spin_microseconds(), one_cpu_one = SkinningThreads(1).worker_spin_microseconds();
  ASSERT_EQ(sched_setaffinity(0, sizeof all, &all), 0);
  EXPECT_EQ(one_cpu_two, 0u);
  EXPECT_EQ(one_cpu_one, SkinningThreads::kWorkerSpinMicroseconds);
}

// Workers take the caller's floating-point environment for each job: with the caller rounding
// upward, the pool's result is the one-thread result in that mode bit for bit (and differs from
// the result rounded to nearest, so the mode reaches the arithmetic). The pool is made before the
// mode changes, so its threads started in the default mode. The job is large (about 0.3 ms on one
// thread), so that the workers wake in time to claim parts.
TEST(Skinning, ThreadsTakeTheCallersRoundingMode) {
  Random rng(10);
  const std::size_t n = 100000;
  const Skin skin = *build_skin(random_skin(rng, n, 11, 4));
  SkinPalette palette(skin.bone_count());
  update_palette(skin, random_pose(rng, 11), palette);
  SkinningThreads pool(3, 16);
  Output nearest(n), upward(n), pooled(n);
  ASSERT_TRUE(SkinningThreads(1).run({&skin, &palette, SkinningMethod::dqs, nearest.view(true, false), 0, n}).ok());
  struct Upward {
    Upward() { std::fesetround(FE_UPWARD); }
    ~Upward() { std::fesetround(FE_TONEAREST); }
  } upward_rounding;
  ASSERT_TRUE(SkinningThreads(1).run({&skin, &palette, SkinningMethod::dqs, upward.view(true, false), 0, n}).ok());
  ASSERT_TRUE(pool.run({&skin, &palette, SkinningMethod::dqs, pooled.view(true, false), 0, n}).ok());
  ASSERT_NE(upward.px, nearest.px);
  ASSERT_TRUE(holds_range(pooled, upward, 0, n, 0.0f));
}

// Several jobs in one call (the meshes of a model): two skins, the three methods, ranges from
// empty to larger than a part, some vertices in no job. On 2 and 3 threads, with parts of 16
// vertices and more and the default, 50 calls each, and on the calling thread alone (one thread, or
// parts larger than all the jobs): every job's vertices are its one-thread result bit for bit, and
// nothing else is written.
TEST(Skinning, ThreadsRunManyJobsAsOne) {
  Random rng(11);
  const std::size_t n[2] = {9000, 700};
  const Skin skins[2] = {*build_skin(random_skin(rng, n[0], 11, 4)), *build_skin(random_skin(rng, n[1], 5, 3))};
  std::vector<SkinPalette> palettes;
  for (const Skin& skin : skins) {
    palettes.emplace_back(skin.bone_count());
    update_palette(skin, random_pose(rng, skin.bone_count()), palettes.back());
  }
  struct Range {
    std::size_t skin, first, count;
    SkinningMethod method;
  };
  const Range ranges[] = {{0, 0, 0, SkinningMethod::dqs},       {0, 0, 1, SkinningMethod::lbs},     {0, 1, 17, SkinningMethod::dqs},
                          {1, 0, 300, SkinningMethod::cor},     {0, 40, 5000, SkinningMethod::dqs}, {0, 5040, 16, SkinningMethod::cor},
                          {1, 300, 400, SkinningMethod::dqs},   {0, 6000, 3000, SkinningMethod::lbs}};  // vertices 18–39 and 5056–5999 of skin 0 in no job
  const float fill = -std::numeric_limits<float>::quiet_NaN();
  std::vector<Output> expected{Output(n[0]), Output(n[1])}, out{Output(n[0]), Output(n[1])};
  for (Output& o : expected) o.fill(fill);
  std::vector<SkinningJob> jobs;
  for (const Range& r : ranges) {
    const SkinningJob job{&skins[r.skin], &palettes[r.skin], r.method, out[r.skin].view(true, false), r.first, r.count};
    jobs.push_back(job);
    Output alone(n[r.skin]);
    ASSERT_TRUE(SkinningThreads(1).run({job.skin, job.palette, r.method, alone.view(true, false), r.first, r.count}).ok());
    for (auto part : Output::parts)
      std::copy_n((alone.*part).data() + r.first, r.count, (expected[r.skin].*part).data() + r.first);
  }
  for (unsigned threads : {1u, 2u, 3u})
    for (std::size_t min_part : {std::size_t{16}, SkinningThreads::kDefaultMinPart, std::size_t{16384}}) {
      SkinningThreads pool(threads, min_part);
      for (int call = 0; call < 50; ++call) {
        SCOPED_TRACE(std::to_string(threads) + " threads, parts of " + std::to_string(min_part) + " and more, call " + std::to_string(call));
        for (Output& o : out) o.fill(fill);
        const Status s = pool.run(jobs);
        ASSERT_TRUE(s.ok()) << s.error().message;
        for (std::size_t k = 0; k < 2; ++k) ASSERT_TRUE(holds_range(out[k], expected[k], 0, n[k], fill)) << "skin " << k;
      }
    }
}

// A call whose jobs write the same element, in one array or in two that alias, or with a job that
// does not validate, is refused with the jobs named, and writes nothing. Ranges that touch are not
// an overlap, and a call with no jobs does nothing.
TEST(Skinning, ThreadsRefuseJobsThatWriteTheSameElements) {
  Random rng(12);
  const std::size_t n = 5000;
  const Skin skin = *build_skin(random_skin(rng, n, 11, 4));
  SkinPalette palette(skin.bone_count()), wrong(skin.bone_count() + 1);
  update_palette(skin, random_pose(rng, 11), palette);
  const float fill = -std::numeric_limits<float>::quiet_NaN();
  Output out(n);
  out.fill(fill);
  const SkinnedVertices all = out.view(true, false);
  SkinnedVertices aliased = all;  // its nx[v] is pz[v + 850]
  aliased.nx = std::span<float>(out.pz).subspan(850);
  SkinningThreads pool(2, 16);
  const auto refused = [&](std::vector<SkinningJob> jobs, const std::string& message) {
    const Status s = pool.run(jobs);
    if (s.ok()) return ::testing::AssertionFailure() << "accepted";
    if (s.error().message.find(message) == std::string::npos) return ::testing::AssertionFailure() << s.error().message;
    for (auto part : Output::parts)
      for (float x : out.*part)
        if (!std::isnan(x)) return ::testing::AssertionFailure() << "refused, but wrote " << x;
    return ::testing::AssertionSuccess();
  };
  EXPECT_TRUE(refused({{&skin, &palette, SkinningMethod::dqs, all, 0, 2000}, {&skin, &palette, SkinningMethod::dqs, all, 2000, 100},
                       {&skin, &palette, SkinningMethod::lbs, all, 1999, 10}},
                      "skinning jobs 0 and 2 write the same output elements"));
  SkinnedVertices positions = all;
  positions.nx = positions.ny = positions.nz = {};
  EXPECT_TRUE(refused({{&skin, &palette, SkinningMethod::dqs, all, 0, 100}, {&skin, &palette, SkinningMethod::dqs, positions, 1000, 100},
                       {&skin, &palette, SkinningMethod::dqs, aliased, 200, 100}},
                      "skinning jobs 1 and 2 write the same output elements"));  // job 2's nx[200, 300) is pz[1050, 1150)
  EXPECT_TRUE(refused({{&skin, &palette, SkinningMethod::dqs, all, 0, 100}, {&skin, &wrong, SkinningMethod::dqs, all, 100, 100}},
                      "skinning job 1: the palette has 12 bones, the skin 11"));
  EXPECT_TRUE(refused({{&skin, &palette, SkinningMethod::dqs, all, 0, 100}, {&skin, &palette, SkinningMethod::dqs, all, 0, 100}},
                      "skinning jobs 0 and 1 write the same output elements"));
  // Rows: job 1 writes vertices [99, 200), whose rows start inside job 0's [0, 100).
  std::vector<float> rows(3 * n, fill);
  const SkinnedVertices as_rows{.positions = rows};
  EXPECT_TRUE(refused({{&skin, &palette, SkinningMethod::dqs, as_rows, 0, 100}, {&skin, &palette, SkinningMethod::dqs, as_rows, 99, 101}},
                      "skinning jobs 0 and 1 write the same output elements"));
  for (float x : rows) ASSERT_TRUE(std::isnan(x)) << "refused, but wrote " << x;
  EXPECT_TRUE(pool.run(std::span<const SkinningJob>{}).ok());
  const std::vector<SkinningJob> touching{{&skin, &palette, SkinningMethod::dqs, all, 2500, n - 2500}, {&skin, &palette, SkinningMethod::dqs, all, 0, 2500},
                                          {&skin, &palette, SkinningMethod::dqs, as_rows, 2500, n - 2500}, {&skin, &palette, SkinningMethod::dqs, as_rows, 0, 2500}};
  ASSERT_TRUE(pool.run(touching).ok());
  for (std::size_t v = 0; v < n; ++v) {
    ASSERT_FALSE(std::isnan(out.px[v]));
    ASSERT_EQ(Vec3<float>(rows[3 * v], rows[3 * v + 1], rows[3 * v + 2]), out.p(v)) << "vertex " << v;
  }
}

TEST(Skinning, TangentsRotateWithTheBone) {
  const Skin skin = *build_skin(two_bone_cylinder());
  ASSERT_TRUE(skin.has_tangents());
  const Quaternion<double> r = Quaternion<double>::from_axis_angle({0, 0, 1}, 0.9);
  const std::vector<DualQuaternion<double>> pose{DualQuaternion<double>::from_rotation(r), DualQuaternion<double>::from_rotation(r)};
  const Vec3<double> expected = r.rotate(Vec3<double>{1, 0, 0});
  for (SkinningMethod m : {SkinningMethod::lbs, SkinningMethod::dqs, SkinningMethod::cor}) {
    const Output o = run(skin, pose, m);
    for (std::size_t v = 0; v < skin.vertex_count(); ++v)
      ASSERT_LE(test::max_abs_diff(o.t(v), Vec3<float>{float(expected.x), float(expected.y), float(expected.z)}), position_tolerance(1));
  }
}

// ---- scale: Kavan's two-phase method -----------------------------------------------------------

TEST(Skinning, ScaledBindsLandWhereTheMeshTransformPutsThem) {
  // Bind: every bone's full transform is the same affine A (with scale and shear), so in the bind
  // pose every vertex must land at A v, for all three methods.
  Random rng(6);
  RawSkin raw = random_skin(rng, 300, 4, 4);
  Mat4<double> a = to_mat4(rng.rigid(2.0));
  const Mat4<double> scale_shear = Mat4<double>::from_rows(1.5, 0.2, 0, 0, 0.2, 0.8, 0.1, 0, 0, 0.1, 1.2, 0, 0, 0, 0, 1);
  a = a * scale_shear;
  std::vector<DualQuaternion<double>> bind = random_pose(rng, 4);
  raw.bone_scale.assign(4, 2.0);  // the joints carry a uniform scale of 2 the rigid pose does not
  for (std::size_t b = 0; b < 4; ++b) {
    // A = W S(2) B⁻¹  ⇒  B⁻¹ = S(½) W⁻¹ A
    Mat4<double> half = Mat4<double>::identity();
    half(0, 0) = half(1, 1) = half(2, 2) = 0.5;
    raw.inverse_bind[b] = half * to_mat4(bind[b].conjugate()) * a;
  }
  const Skin skin = *build_skin(raw);
  EXPECT_TRUE(skin.has_scale_shear());
  for (SkinningMethod m : {SkinningMethod::lbs, SkinningMethod::dqs, SkinningMethod::cor}) {
    const Output o = run(skin, bind, m);
    for (std::size_t v = 0; v < skin.vertex_count(); ++v) {
      const Vec3<double> e = transform_point(a, raw.positions[v].cast<double>());
      ASSERT_LE(test::max_abs_diff(o.p(v), Vec3<float>{float(e.x), float(e.y), float(e.z)}), position_tolerance(8))
          << "method " << static_cast<int>(m) << " vertex " << v;
    }
  }
}

// ---- the vector kernels against the scalar path ---------------------------------------------------

using test::for_each_target;

/// A skin with exactly `slots` slots whose vertex count is no multiple of any vector width, with
/// tangents, and (when `scaled`) binds with scale and shear and bone scales.
RawSkin vector_test_skin(Random& rng, std::size_t slots, bool scaled) {
  RawSkin raw = random_skin(rng, 16 * 5 + 2 * slots + 3, 9, slots);
  for (std::size_t v = 0; v < raw.positions.size(); ++v) {
    const Vec3<double> t = normalized(rng.vec3(1.0));
    raw.tangents.push_back({float(t.x), float(t.y), float(t.z)});
  }
  // Bones 0 to 3 bound with the identity (antipodal_pose's signs reach the palette), and every
  // vertex with two or more influences on one of bones 0, 1 and one of bones 2, 3.
  for (std::size_t b = 0; b < 4; ++b) raw.inverse_bind[b] = Mat4<double>::identity();
  for (std::size_t v = 0; v < raw.positions.size(); ++v)
    if (raw.influence_offsets[v + 1] - raw.influence_offsets[v] >= 2) {
      raw.influences[raw.influence_offsets[v]].bone = static_cast<std::uint32_t>(v % 2);
      raw.influences[raw.influence_offsets[v] + 1].bone = static_cast<std::uint32_t>(2 + v / 2 % 2);
    }
  if (scaled)
    for (std::size_t b = 4; b < raw.inverse_bind.size(); ++b) {
      Mat4<double> p = Mat4<double>::identity();
      for (int r = 0; r < 3; ++r)
        for (int c = r; c < 3; ++c) p(r, c) = p(c, r) = r == c ? rng.uniform(0.6, 1.5) : rng.uniform(-0.2, 0.2);
      raw.inverse_bind[b] = raw.inverse_bind[b] * p;
      raw.bone_scale.resize(raw.inverse_bind.size(), 1.0);
      raw.bone_scale[b] = rng.uniform(0.5, 2.0);
    }
  return raw;
}

/// A pose with antipodal bones: bone 1 is −bone 0 (the same transform, the opposite sign) and
/// bone 3 is −bone 2, which turns 180° about x from bone 0.
std::vector<DualQuaternion<double>> antipodal_pose(Random& rng, std::size_t bones) {
  const auto a = DualQuaternion<double>::from_rotation_translation(Quaternion<double>(1, 0, 0, 0), {0.5, -1, 2});
  const auto b = DualQuaternion<double>::from_rotation_translation(Quaternion<double>(0, 1, 0, 0), {-1, 0.25, 1});
  std::vector<DualQuaternion<double>> pose{a, -a, b, -b};
  for (const auto& q : random_pose(rng, bones - 4)) pose.push_back(q);
  return pose;
}

/// A job over [first, first + count) whose outputs are rows (one float past a vector's start, so
/// that no row is aligned), all three quantities (tangents where the skin has them) or with
/// normals as arrays, on `threads` threads
/// with parts of 16 vertices and more; the rows copied back into arrays. Rows outside the range
/// must keep their sentinel, and the arrays there stay 0 as in an Output's other runs.
Output run_into_rows(const Skin& skin, const SkinPalette& palette, SkinningMethod m, std::size_t first, std::size_t count,
                     bool normals_as_arrays, unsigned threads) {
  const std::size_t n = skin.vertex_count();
  const std::uint32_t sentinel = 0xffc0ffeeu;  // a NaN's bits
  std::vector<float> buffers[3];
  std::span<float> rows[3];
  for (std::size_t q = 0; q < 3; ++q) {
    buffers[q].assign(3 * n + 2, std::bit_cast<float>(sentinel));
    rows[q] = std::span<float>(buffers[q]).subspan(1, 3 * n);
  }
  Output o(n);
  SkinnedVertices view{.positions = rows[0]};
  if (skin.has_tangents()) view.tangents = rows[2];
  if (normals_as_arrays)
    view.nx = o.nx, view.ny = o.ny, view.nz = o.nz;
  else
    view.normals = rows[1];
  const Status s = SkinningThreads(threads, 16).run({&skin, &palette, m, view, first, count});
  EXPECT_TRUE(s.ok()) << s.error().message;
  for (std::size_t q = 0; q < 3; ++q) {
    if ((q == 1 && normals_as_arrays) || (q == 2 && !skin.has_tangents())) continue;
    for (std::size_t i = 0; i < buffers[q].size(); ++i)
      if (i < 1 + 3 * first || i >= 1 + 3 * (first + count)) {
        EXPECT_EQ(std::bit_cast<std::uint32_t>(buffers[q][i]), sentinel) << "rows of quantity " << q << ", float " << i << " (written outside the range)";
      }
    for (std::size_t v = first; v < first + count; ++v)
      for (std::size_t c = 0; c < 3; ++c) (o.*Output::parts[3 * q + c])[v] = rows[q][3 * v + c];
  }
  return o;
}

// Every vector path performs the scalar path's operations in the same order without fused
// multiply-adds, so the documented tolerance is zero: bit for bit, for every method, slot count
// 1 to 8, tails (counts and starts that are no multiple of the width), scaled and antipodal bones;
// and into rows (SkinnedVertices::positions, normals, tangents) as into arrays.
TEST(SkinningTargets, EveryTargetIsTheScalarPathBitForBit) {
  Random rng(21);
  for (bool scaled : {false, true})
    for (std::size_t slots = 1; slots <= 8; ++slots) {
      const Skin skin = *build_skin(vector_test_skin(rng, slots, scaled));
      ASSERT_EQ(skin.slots(), slots);
      ASSERT_EQ(skin.has_scale_shear(), scaled);
      const auto pose = antipodal_pose(rng, skin.bone_count());
      SkinPalette palette(skin.bone_count());
      update_palette(skin, pose, palette);
      // Real parts with signed zeros, so that the antipodality test meets dot products of
      // exactly +0 (bones 0 and 2, 1 and 3) and −0 (bones 0 and 3, 1 and 2): the sign rule must
      // follow the sign bit on every path.
      const float real[4][4] = {{1, 0, 0, 0}, {-1, -0.0f, -0.0f, -0.0f}, {0, 1, 0, 0}, {-0.0f, -1, -0.0f, -0.0f}};
      for (std::size_t b = 0; b < 4; ++b) std::copy(real[b], real[b] + 4, palette.dual_quaternions.begin() + 8 * static_cast<std::ptrdiff_t>(b));
      const std::size_t n = skin.vertex_count();
      for (SkinningMethod m : {SkinningMethod::lbs, SkinningMethod::dqs, SkinningMethod::cor})
        for (std::size_t first : {std::size_t{0}, std::size_t{3}}) {
          SCOPED_TRACE("slots " + std::to_string(slots) + (scaled ? " scaled" : "") + " method " + std::to_string(int(m)) + " first " + std::to_string(first));
          std::vector<Output> results;
          for_each_target([&](simd::Target) {
            Output o(n);
            ASSERT_TRUE(SkinningThreads(1).run({&skin, &palette, m, o.view(true, true), first, n - first - 2}).ok());
            results.push_back(std::move(o));
            // Again on two threads, into arrays that start cache lines (ComponentArrays), so that
            // the vectors' loads and stores meet lines whole at first = 0 and split at 3.
            ComponentArrays<float, 9> a(n);
            const SkinnedVertices view{a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7], a[8]};
            ASSERT_TRUE(SkinningThreads(2, 16).run({&skin, &palette, m, view, first, n - first - 2}).ok());
            Output aligned(n);
            for (std::size_t k = 0; k < std::size(Output::parts); ++k) std::copy(a[k].begin(), a[k].end(), (aligned.*Output::parts[k]).begin());
            results.push_back(std::move(aligned));
            results.push_back(run_into_rows(skin, palette, m, first, n - first - 2, false, 1));
            results.push_back(run_into_rows(skin, palette, m, first, n - first - 2, true, 2));
          });
          // results: each target's run, its run into ComponentArrays, into rows, into rows and
          // arrays; [0] is the scalar path's.
          const char* const runs[] = {"", ", into ComponentArrays on two threads", ", into rows", ", into rows and normal arrays on two threads"};
          for (std::size_t t = 1; t < results.size(); ++t) {
            SCOPED_TRACE(std::string(simd::to_string(simd::Target(t / 4))) + runs[t % 4]);
            for (auto part : Output::parts)
              for (std::size_t v = 0; v < n; ++v)
                ASSERT_EQ(std::memcmp(&(results[t].*part)[v], &(results[0].*part)[v], sizeof(float)), 0)
                    << "vertex " << v << ": " << (results[t].*part)[v] << " against the scalar " << (results[0].*part)[v];
          }
        }
    }
}

// Rows over a range long enough for the vector loop's prefetch (128 vertices ahead, which the
// skins above are too short for), on every target: the arrays' values, bit for bit. (Coverage of
// that loop only: a prefetch changes no result, so no test sees where it points.)
TEST(SkinningTargets, RowsOfLongRangesAreTheArrays) {
  Random rng(23);
  const Skin skin = *build_skin(random_skin(rng, 3000, 11, 4));
  SkinPalette palette(skin.bone_count());
  update_palette(skin, random_pose(rng, skin.bone_count()), palette);
  const std::size_t first = 5, count = 2990;
  for_each_target([&](simd::Target t) {
    for (SkinningMethod m : {SkinningMethod::lbs, SkinningMethod::dqs}) {
      SCOPED_TRACE(std::string(simd::to_string(t)) + " method " + std::to_string(int(m)));
      Output arrays(skin.vertex_count());
      ASSERT_TRUE(SkinningThreads(1).run({&skin, &palette, m, arrays.view(true, false), first, count}).ok());
      const Output rows = run_into_rows(skin, palette, m, first, count, false, 1);
      for (std::size_t k = 0; k < 6; ++k)
        for (std::size_t v = 0; v < skin.vertex_count(); ++v)
          ASSERT_EQ(std::bit_cast<std::uint32_t>((rows.*Output::parts[k])[v]), std::bit_cast<std::uint32_t>((arrays.*Output::parts[k])[v]))
              << "array " << k << ", vertex " << v;
    }
  });
}

// The antipodal pose through the vector paths against the direct reading of the policy: a vertex
// on bones 0 and 1 (= −bone 0) with any weights is moved by bone 0 alone (DQS and CoR), and a
// vertex on bones 2 and 3 by bone 2 alone, whichever of them is the pivot.
TEST(SkinningTargets, AntipodalBonesBlendToTheSameTransform) {
  Random rng(22);
  RawSkin raw = vector_test_skin(rng, 2, false);
  for (std::size_t v = 0; v < raw.positions.size(); ++v) {
    const std::uint32_t b = v % 2 ? 0 : 2;
    const float w = 0.1f + 0.8f * float(v % 7) / 6;
    raw.influences[raw.influence_offsets[v]] = {b, w};
    if (raw.influence_offsets[v + 1] - raw.influence_offsets[v] == 2) raw.influences[raw.influence_offsets[v] + 1] = {b + 1, 1 - w};
  }
  const Skin skin = *build_skin(raw, {.centers_of_rotation = true});
  const auto pose = antipodal_pose(rng, skin.bone_count());
  for_each_target([&](simd::Target) {
    for (SkinningMethod m : {SkinningMethod::dqs, SkinningMethod::cor}) {
      const Output o = run(skin, pose, m);
      for (std::size_t v = 0; v < skin.vertex_count(); ++v) {
        const DualQuaternion<double>& q = pose[v % 2 ? 0 : 2];
        const Vec3<double> e = q.transform_point(raw.positions[v].cast<double>());
        ASSERT_LE(test::max_abs_diff(o.p(v), Vec3<float>{float(e.x), float(e.y), float(e.z)}), position_tolerance(8)) << "vertex " << v;
      }
    }
  });
}

// ---- centres of rotation --------------------------------------------------------------------

TEST(Skinning, CentresOfRotationOfACylinderLieOnItsAxis) {
  const CylinderShape shape;
  const Skin skin = *build_skin(two_bone_cylinder(shape));
  std::size_t blended = 0;
  for (std::size_t v = 0; v < skin.vertex_count(); ++v) {
    const float w0 = skin.slot_weights(0)[v];
    const Vec3<float> c = skin.center(v);
    if (w0 == 1.0f) {
      EXPECT_EQ(c, skin.position(v)) << "one influence: the centre is the vertex";
      continue;
    }
    ++blended;
    // By the cylinder's symmetry the centre is on the axis, at the x of the vertex's ring (all
    // vertices of a ring have the same weights).
    EXPECT_LE(std::abs(c.y) + std::abs(c.z), position_tolerance(1)) << "vertex " << v;
    EXPECT_NEAR(c.x, skin.position(v).x, shape.blend) << "vertex " << v;
  }
  EXPECT_GT(blended, 0u);
}

// ---- real characters ---------------------------------------------------------------------------
#if defined(DQKIT_TEST_IMPORT)

ImportedScene import(const std::string& relative) {
  Expected<ImportedScene> s = import_scene(test::assimp_models() / relative);
  EXPECT_TRUE(s.has_value()) << (s ? "" : s.error().message);
  return s ? std::move(*s) : ImportedScene{};
}

SkinnedFrame skin_scene(const ImportedScene& scene, std::span<const DualQuaternion<double>> world, SkinningMethod m) {
  Expected<SceneSkin> skins = SceneSkin::build(scene);
  EXPECT_TRUE(skins.has_value()) << (skins ? "" : skins.error().message);
  SkinnedFrame frame = skins->make_frame();
  SkinningThreads threads(2, 16);  // parts of 16 vertices and more: the meshes are split
  const Status s = skins->skin(world, m, threads, frame);
  EXPECT_TRUE(s.ok()) << s.error().message;
  return frame;
}

float frame_size(const SkinnedFrame& f) {
  float m = 0;
  for (std::size_t v = 0; v < f.size(); ++v) m = std::max({m, std::abs(f.px[v]), std::abs(f.py[v]), std::abs(f.pz[v])});
  return m;
}

// The glTF 2.0 specification's skinning, computed from the file read by tinygltf (not Assimp):
// joint matrix = global transform of the joint node · its inverse bind matrix; a vertex is
// Σ wᵢ jointMatrixᵢ v. Rotation keys are normalized (glTF requires unit quaternions; this file's
// are off by up to 2.3e-4) and interpolated by slerp; the times tested are key times.
TEST(SkinningFiles, SimpleSkinLbsEqualsTheGltfSpecification) {
  DQKIT_REQUIRE_MODELS();
  const std::string path = (test::assimp_models() / "glTF2/simple_skin/simple_skin.gltf").string();
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string err, warn;
  ASSERT_TRUE(loader.LoadASCIIFromFile(&model, &err, &warn, path)) << err;
  auto floats = [&](int accessor_index) {
    const tinygltf::Accessor& a = model.accessors[static_cast<std::size_t>(accessor_index)];
    const tinygltf::BufferView& v = model.bufferViews[static_cast<std::size_t>(a.bufferView)];
    const auto* base = model.buffers[static_cast<std::size_t>(v.buffer)].data.data() + v.byteOffset + a.byteOffset;
    const std::size_t n = a.count * static_cast<std::size_t>(tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type)));
    std::vector<double> out(n);
    const std::size_t components = static_cast<std::size_t>(tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type)));
    const std::size_t stride = v.byteStride ? v.byteStride : components * static_cast<std::size_t>(tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType)));
    for (std::size_t i = 0; i < a.count; ++i)
      for (std::size_t c = 0; c < components; ++c) {
        if (a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT) {
          float f;
          std::memcpy(&f, base + i * stride + c * 4, 4);
          out[i * components + c] = static_cast<double>(f);
        } else {
          std::uint16_t u;
          std::memcpy(&u, base + i * stride + c * 2, 2);
          out[i * components + c] = u;
        }
      }
    return out;
  };
  const tinygltf::Primitive& prim = model.meshes[0].primitives[0];
  const auto pos = floats(prim.attributes.at("POSITION")), joints = floats(prim.attributes.at("JOINTS_0")),
             weights = floats(prim.attributes.at("WEIGHTS_0")), ibm = floats(model.skins[0].inverseBindMatrices);
  const auto& channel = model.animations[0].channels[0];
  const auto& sampler = model.animations[0].samplers[static_cast<std::size_t>(channel.sampler)];
  const auto key_times = floats(sampler.input), key_values = floats(sampler.output);

  const ImportedScene scene = import("glTF2/simple_skin/simple_skin.gltf");
  for (std::size_t k = 0; k < key_times.size(); ++k) {
    const double t = key_times[k];
    // Node matrices: T · R · S from the file, with the animated rotation (normalized key).
    auto local = [&](std::size_t node) {
      const tinygltf::Node& n = model.nodes[node];
      Quaternion<double> r;
      if (n.rotation.size() == 4) r = {n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]};
      if (static_cast<int>(node) == channel.target_node)
        r = Quaternion<double>(key_values[4 * k + 3], key_values[4 * k], key_values[4 * k + 1], key_values[4 * k + 2]).normalized();
      Mat4<double> m = Mat4<double>::identity();
      const Mat3<double> rm = r.to_matrix();
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) m(i, j) = rm(i, j);
      if (n.translation.size() == 3) m(0, 3) = n.translation[0], m(1, 3) = n.translation[1], m(2, 3) = n.translation[2];
      return m;
    };
    std::map<std::size_t, Mat4<double>> global;
    std::function<void(std::size_t, const Mat4<double>&)> walk = [&](std::size_t node, const Mat4<double>& parent) {
      global[node] = parent * local(node);
      for (int c : model.nodes[node].children) walk(static_cast<std::size_t>(c), global[node]);
    };
    for (int root : model.scenes[0].nodes) walk(static_cast<std::size_t>(root), Mat4<double>::identity());
    std::vector<DualQuaternion<double>> world;
    ASSERT_TRUE(pose_at(scene, 0, t, world).ok());
    const SkinnedFrame frame = skin_scene(scene, world, SkinningMethod::lbs);
    ASSERT_EQ(frame.size(), pos.size() / 3);
    for (std::size_t v = 0; v < frame.size(); ++v) {
      Vec3<double> expected{0, 0, 0};
      for (std::size_t i = 0; i < 4; ++i) {
        const auto joint_node = static_cast<std::size_t>(model.skins[0].joints[static_cast<std::size_t>(joints[4 * v + i])]);
        Mat4<double> inverse_bind;
        for (std::size_t e = 0; e < 16; ++e) inverse_bind.m[e] = ibm[16 * static_cast<std::size_t>(joints[4 * v + i]) + e];
        expected += transform_point(global[joint_node] * inverse_bind, Vec3<double>{pos[3 * v], pos[3 * v + 1], pos[3 * v + 2]}) * weights[4 * v + i];
      }
      EXPECT_LE(test::max_abs_diff(frame.position(v), Vec3<float>{float(expected.x), float(expected.y), float(expected.z)}), position_tolerance(2))
          << "t = " << t << ", vertex " << v;
    }
  }
}

// Assimp's own scene graph, as full 4x4 matrices with their scales: a vertex is
// Σ wᵢ Gᵢ Oᵢ v / Σ wᵢ (G: product of the node matrices, O: the bone's offset matrix). dqkit's
// skeleton is rigid with the scale recorded apart (joint_scale); LBS of the rest pose must agree.
struct AssimpReference {
  std::vector<Vec3<double>> positions;  ///< all meshes, import order
  std::vector<Vec3<double>> tangents;   ///< LBS of the tangents, normalize(Σ wᵢ L(Gᵢ Oᵢ) t); empty unless every mesh has them
  bool same_bind = true;                ///< every bone of every mesh has the same G·O at rest (rest pose = bind pose)
};

AssimpReference assimp_rest_pose(const std::string& relative) {
  Assimp::Importer importer;
  const aiScene* s = importer.ReadFile((test::assimp_models() / relative).string(),
                                       aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_LimitBoneWeights | aiProcess_ValidateDataStructure);
  EXPECT_NE(s, nullptr);
  std::map<std::string, aiMatrix4x4> global;
  std::function<void(const aiNode*, const aiMatrix4x4&)> walk = [&](const aiNode* n, const aiMatrix4x4& parent) {
    const aiMatrix4x4 g = parent * n->mTransformation;
    global[n->mName.C_Str()] = g;
    for (unsigned c = 0; c < n->mNumChildren; ++c) walk(n->mChildren[c], g);
  };
  walk(s->mRootNode, aiMatrix4x4());
  AssimpReference out;
  for (unsigned m = 0; m < s->mNumMeshes; ++m) {
    const aiMesh& mesh = *s->mMeshes[m];
    std::vector<Vec3<double>> sum(mesh.mNumVertices, Vec3<double>{0, 0, 0}), tangent(mesh.mNumVertices, Vec3<double>{0, 0, 0});
    std::vector<double> wsum(mesh.mNumVertices, 0);
    aiMatrix4x4 first;
    for (unsigned b = 0; b < mesh.mNumBones; ++b) {
      const aiBone& bone = *mesh.mBones[b];
      const aiMatrix4x4 k = global[bone.mName.C_Str()] * bone.mOffsetMatrix;
      if (b == 0) first = k;
      // Assimp's matrices are float: bones bound alike agree to float rounding (1e-6 relative);
      // 1e-4 separates that from a different bind (animation_with_skeleton.fbx differs by 744).
      for (unsigned i = 0; i < 4; ++i)
        for (unsigned j = 0; j < 4; ++j)
          if (std::abs(double(k[i][j]) - double(first[i][j])) > 1e-4 * (1 + std::abs(double(first[i][j])))) out.same_bind = false;
      double kd[3][4];
      for (unsigned i = 0; i < 3; ++i)
        for (unsigned j = 0; j < 4; ++j) kd[i][j] = double(k[i][j]);
      for (unsigned w = 0; w < bone.mNumWeights; ++w) {
        const aiVertexWeight& vw = bone.mWeights[w];
        const aiVector3D& p = mesh.mVertices[vw.mVertexId];
        const double x = double(p.x), y = double(p.y), z = double(p.z);
        const Vec3<double> q{kd[0][0] * x + kd[0][1] * y + kd[0][2] * z + kd[0][3], kd[1][0] * x + kd[1][1] * y + kd[1][2] * z + kd[1][3],
                             kd[2][0] * x + kd[2][1] * y + kd[2][2] * z + kd[2][3]};
        sum[vw.mVertexId] += q * double(vw.mWeight);
        if (mesh.mTangents) {
          const aiVector3D& t = mesh.mTangents[vw.mVertexId];
          const double tx = double(t.x), ty = double(t.y), tz = double(t.z);
          tangent[vw.mVertexId] += Vec3<double>{kd[0][0] * tx + kd[0][1] * ty + kd[0][2] * tz, kd[1][0] * tx + kd[1][1] * ty + kd[1][2] * tz,
                                                kd[2][0] * tx + kd[2][1] * ty + kd[2][2] * tz} * double(vw.mWeight);
        }
        wsum[vw.mVertexId] += double(vw.mWeight);
      }
    }
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) out.positions.push_back(sum[v] / wsum[v]);
    if (mesh.mTangents)
      for (unsigned v = 0; v < mesh.mNumVertices; ++v) out.tangents.push_back(normalized(tangent[v]));
  }
  return out;
}

class SkinnedCharacter : public ::testing::TestWithParam<const char*> {};

TEST_P(SkinnedCharacter, RestPoseAgreesWithAssimpsScaledSceneGraph) {
  DQKIT_REQUIRE_MODELS();
  const ImportedScene scene = import(GetParam());
  const AssimpReference reference = assimp_rest_pose(GetParam());
  std::vector<DualQuaternion<double>> rest(scene.skeleton.size());
  local_to_model<DualQuaternion<double>>(scene.skeleton, scene.skeleton.rest_pose(), rest);
  for (SkinningMethod m : {SkinningMethod::lbs, SkinningMethod::dqs, SkinningMethod::cor}) {
    // DQS and CoR equal LBS only where every bone maps the vertex the same way: rest = bind.
    if (m != SkinningMethod::lbs && !reference.same_bind) continue;
    const SkinnedFrame frame = skin_scene(scene, rest, m);
    ASSERT_EQ(frame.size(), reference.positions.size());
    const float tol = position_tolerance(frame_size(frame));
    for (std::size_t v = 0; v < frame.size(); ++v) {
      const Vec3<double>& e = reference.positions[v];
      ASSERT_LE(test::max_abs_diff(frame.position(v), Vec3<float>{float(e.x), float(e.y), float(e.z)}), tol)
          << GetParam() << " method " << static_cast<int>(m) << " vertex " << v;
    }
  }
}

TEST_P(SkinnedCharacter, AnimatedFramesAreFiniteAndOrderIndependent) {
  DQKIT_REQUIRE_MODELS();
  const ImportedScene scene = import(GetParam());
  ASSERT_FALSE(scene.animations.empty());
  std::vector<DualQuaternion<double>> world;
  ASSERT_TRUE(pose_at(scene, 0, 0.5 * scene.animations[0].animation.duration(), world).ok());
  ImportedScene reversed = scene;
  for (ImportedMesh& mesh : reversed.meshes)
    for (std::size_t v = 0; v + 1 < mesh.influence_offsets.size(); ++v)
      std::reverse(mesh.influences.begin() + mesh.influence_offsets[v], mesh.influences.begin() + mesh.influence_offsets[v + 1]);
  for (SkinningMethod m : {SkinningMethod::lbs, SkinningMethod::dqs, SkinningMethod::cor}) {
    const SkinnedFrame a = skin_scene(scene, world, m), b = skin_scene(reversed, world, m);
    EXPECT_EQ(a.px, b.px);
    EXPECT_EQ(a.pz, b.pz);
    for (std::size_t v = 0; v < a.size(); ++v) ASSERT_TRUE(std::isfinite(a.px[v] + a.py[v] + a.pz[v])) << v;
  }
}

INSTANTIATE_TEST_SUITE_P(Files, SkinnedCharacter,
                         ::testing::Values("glTF2/simple_skin/simple_skin.gltf", "X/BCN_Epileptic.X", "X/Testwuson.X",
                                           "FBX/animation_with_skeleton.fbx", "FBX/huesitos.fbx", "Collada/box_nested_animation.dae"));

// Tangents (issue 11): FBX/huesitos.fbx, a skinned and animated character, carries them. The
// importer hands Assimp's aiMesh::mTangents to the skins (checked against Assimp read directly with
// the importer's post-processing, so in the same vertex order). The file's tangents are unit and
// orthogonal to its normals to 1e-4 (its exporter's precision: the largest |t·n| is 7.9e-5). At
// rest every method's tangents are Assimp's scene graph applied to them; animated, they stay unit,
// and DQS and CoR, which rotate tangents and normals alike, keep each vertex's t·n of the bind.
TEST(SkinningFiles, TangentsFromTheFileAreSkinnedWithTheNormals) {
  DQKIT_REQUIRE_MODELS();
  const std::string relative = "FBX/huesitos.fbx";
  const ImportedScene scene = import(relative);
  Assimp::Importer importer;
  const aiScene* s = importer.ReadFile((test::assimp_models() / relative).string(),
                                       aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_LimitBoneWeights | aiProcess_ValidateDataStructure);
  ASSERT_NE(s, nullptr);
  ASSERT_EQ(s->mNumMeshes, scene.meshes.size());
  std::vector<float> bind_dot;  // t·n per vertex, frame order
  for (unsigned m = 0; m < s->mNumMeshes; ++m) {
    const aiMesh& mesh = *s->mMeshes[m];
    const ImportedMesh& imported = scene.meshes[m];
    ASSERT_NE(mesh.mTangents, nullptr) << "mesh " << m;
    ASSERT_EQ(imported.tangents.size(), mesh.mNumVertices);
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      ASSERT_EQ(imported.tangents[v], (Vec3<float>{mesh.mTangents[v].x, mesh.mTangents[v].y, mesh.mTangents[v].z})) << "vertex " << v;
      ASSERT_LE(std::abs(norm(imported.tangents[v]) - 1), position_tolerance(1)) << "vertex " << v;
      ASSERT_LE(std::abs(dot(imported.tangents[v], imported.normals[v])), 1e-4f) << "vertex " << v;
      bind_dot.push_back(dot(imported.tangents[v], imported.normals[v]));
    }
  }
  // At rest: Assimp's scene graph.
  const AssimpReference reference = assimp_rest_pose(relative);
  ASSERT_EQ(reference.tangents.size(), bind_dot.size());
  std::vector<DualQuaternion<double>> world(scene.skeleton.size());
  local_to_model<DualQuaternion<double>>(scene.skeleton, scene.skeleton.rest_pose(), world);
  for (SkinningMethod m : {SkinningMethod::lbs, SkinningMethod::dqs, SkinningMethod::cor}) {
    if (m != SkinningMethod::lbs && !reference.same_bind) continue;
    const SkinnedFrame frame = skin_scene(scene, world, m);
    ASSERT_EQ(frame.tx.size(), frame.size());
    for (std::size_t v = 0; v < frame.size(); ++v) {
      const Vec3<double>& e = reference.tangents[v];
      ASSERT_LE(test::max_abs_diff(Vec3<float>{frame.tx[v], frame.ty[v], frame.tz[v]}, Vec3<float>{float(e.x), float(e.y), float(e.z)}),
                position_tolerance(1))
          << "method " << static_cast<int>(m) << " vertex " << v;
    }
  }
  // Animated.
  ASSERT_FALSE(scene.animations.empty());
  for (double t : {0.3, 0.7}) {
    ASSERT_TRUE(pose_at(scene, 0, t * scene.animations[0].animation.duration(), world).ok());
    for (SkinningMethod m : {SkinningMethod::lbs, SkinningMethod::dqs, SkinningMethod::cor}) {
      const SkinnedFrame frame = skin_scene(scene, world, m);
      for (std::size_t v = 0; v < frame.size(); ++v) {
        const Vec3<float> tv{frame.tx[v], frame.ty[v], frame.tz[v]}, nv{frame.nx[v], frame.ny[v], frame.nz[v]};
        ASSERT_LE(std::abs(norm(tv) - 1), position_tolerance(1)) << "method " << static_cast<int>(m) << " vertex " << v;
        if (m != SkinningMethod::lbs) {
          ASSERT_LE(std::abs(dot(tv, nv) - bind_dot[v]), position_tolerance(1)) << "method " << static_cast<int>(m) << " vertex " << v;
        }
      }
    }
  }
}

TEST(SkinningFiles, AFrameAllocatesNothing) {
  DQKIT_REQUIRE_MODELS();
  const ImportedScene scene = import("X/BCN_Epileptic.X");
  Expected<SceneSkin> skins = SceneSkin::build(scene);
  ASSERT_TRUE(skins.has_value());
  SkinnedFrame frame = skins->make_frame();
  SkinningThreads threads(2, 16);  // parts of 16 vertices and more: the meshes are split over the threads
  std::vector<DualQuaternion<double>> world;
  ASSERT_TRUE(pose_at(scene, 0, 0, world).ok());  // sizes `world`
  ASSERT_TRUE(skins->skin(world, SkinningMethod::dqs, threads, frame).ok());  // sizes the pool's list of outputs
  allocations = 0;
  counting = true;
  for (int f = 0; f < 20; ++f)
    for (SkinningMethod m : {SkinningMethod::lbs, SkinningMethod::dqs, SkinningMethod::cor}) {
      const bool posed = pose_at(scene, 0, 0.1 * f, world).ok();
      const bool skinned = skins->skin(world, m, threads, frame).ok();
      if (!posed || !skinned) counting = false;
    }
  counting = false;
  EXPECT_EQ(allocations.load(), 0);
}

TEST(SkinningFiles, FormatsKeepTheVertexOrder) {
  DQKIT_REQUIRE_MODELS();
  const ImportedScene scene = import("X/Testwuson.X");
  std::vector<DualQuaternion<double>> world;
  ASSERT_TRUE(pose_at(scene, 0, 0.3, world).ok());
  const SkinnedFrame frame = skin_scene(scene, world, SkinningMethod::dqs);
  const std::string csv = *format_frame(frame, MeshFormat::csv);
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "vertex,x,y,z\r");  // CRLF, as RFC 4180
  EXPECT_EQ(static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n')), frame.size() + 1);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\r'), std::count(csv.begin(), csv.end(), '\n'));
  char line[128];
  std::snprintf(line, sizeof line, "\n7,%.9g,%.9g,%.9g\r\n", double(frame.px[7]), double(frame.py[7]), double(frame.pz[7]));
  EXPECT_NE(csv.find(line), std::string::npos);
  const std::string obj = *format_frame(frame, MeshFormat::obj);
  std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", double(frame.px[0]), double(frame.py[0]), double(frame.pz[0]));
  EXPECT_EQ(obj.find("v "), obj.find(line));
  const std::string ply = *format_frame(frame, MeshFormat::ply);
  EXPECT_NE(ply.find("element vertex " + std::to_string(frame.size()) + "\n"), std::string::npos);
  EXPECT_NE(ply.find("element face " + std::to_string(frame.triangles.size() / 3) + "\n"), std::string::npos);
  // glTF: read back with tinygltf; positions and indices as written.
  const std::string gltf = *format_frame(frame, MeshFormat::gltf);
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string err, warn;
  ASSERT_TRUE(loader.LoadASCIIFromString(&model, &err, &warn, gltf.data(), static_cast<unsigned>(gltf.size()), "")) << err;
  const tinygltf::Accessor& a = model.accessors[static_cast<std::size_t>(model.meshes[0].primitives[0].attributes["POSITION"])];
  ASSERT_EQ(a.count, frame.size());
  const tinygltf::BufferView& view = model.bufferViews[static_cast<std::size_t>(a.bufferView)];
  const auto* p = reinterpret_cast<const float*>(model.buffers[0].data.data() + view.byteOffset);
  for (std::size_t v = 0; v < frame.size(); ++v) ASSERT_EQ(p[3 * v + 2], frame.pz[v]);
}

#endif

}  // namespace
}  // namespace dq
