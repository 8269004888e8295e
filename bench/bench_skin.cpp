// Skinning throughput (vertices per second, positions and normals): dqkit's LBS, DQS and CoR
// batch jobs on one and two threads, against plain per-vertex GLM implementations of the same
// three methods (array of structures, glm::mat4 / glm::dualquat / glm::quat palettes) in the same
// binary. The skin: 65,536 vertices, 4 influences each, 64 bones with random rigid binds and poses.
#include <benchmark/benchmark.h>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtx/norm.hpp>
#include <glm/gtx/dual_quaternion.hpp>
#include <random>
#include <thread>
#include <vector>

#include "dq/convert/matrix.hpp"
#include "dq/skin/skinning.hpp"

namespace {

using namespace dq;

constexpr std::size_t kVertices = 1 << 16;
constexpr std::uint32_t kBones = 64;

struct Fixture {
  Skin skin;  // built in the constructor
  std::vector<DualQuaternion<double>> pose;
  // GLM's side: the same skin as arrays of structures.
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
    for (std::size_t v = 0; v < kVertices; ++v) {
      raw.positions.push_back({float(u(rng)), float(u(rng)), float(u(rng))});
      raw.normals.push_back(normalized(Vec3<float>{float(u(rng)), float(u(rng)), float(u(rng)) + 2}));
      float w[4], sum = 0;
      for (float& x : w) sum += (x = float(u(rng)) + 1.1f);
      for (float& x : w) raw.influences.push_back({static_cast<std::uint32_t>(rng() % kBones), x / sum});
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
    for (std::size_t v = 0; v < kVertices; ++v) {
      positions.emplace_back(raw.positions[v].x, raw.positions[v].y, raw.positions[v].z);
      normals.emplace_back(raw.normals[v].x, raw.normals[v].y, raw.normals[v].z);
      centers.push_back(positions.back());
      glm::uvec4 j;
      glm::vec4 w;
      for (int k = 0; k < 4; ++k) j[k] = raw.influences[4 * v + static_cast<std::size_t>(k)].bone, w[k] = raw.influences[4 * v + static_cast<std::size_t>(k)].weight;
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

void dqkit_skinning(benchmark::State& state, SkinningMethod method) {
  Fixture& f = fixture();
  const Skin& skin = f.skin;
  SkinPalette palette(kBones);
  update_palette(skin, f.pose, palette);
  std::vector<float> out(6 * kVertices);
  std::span<float> o(out);
  const SkinnedVertices vertices{o.subspan(0, kVertices), o.subspan(kVertices, kVertices), o.subspan(2 * kVertices, kVertices),
                                 o.subspan(3 * kVertices, kVertices), o.subspan(4 * kVertices, kVertices), o.subspan(5 * kVertices, kVertices),
                                 {}, {}, {}};
  SkinningThreads threads(static_cast<unsigned>(state.range(0)));
  for (auto _ : state) {
    if (!threads.run({&skin, &palette, method, vertices, 0, kVertices})) state.SkipWithError("job does not validate");
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * kVertices));
}

// ---- plain per-vertex GLM ------------------------------------------------------------------

void glm_lbs_range(const Fixture& f, std::vector<glm::vec3>& p, std::vector<glm::vec3>& n, std::size_t b, std::size_t e) {
  for (std::size_t v = b; v < e; ++v) {
    const glm::uvec4 j = f.joints[v];
    const glm::vec4 w = f.weights[v];
    const glm::mat4 m = f.matrices[j.x] * w.x + f.matrices[j.y] * w.y + f.matrices[j.z] * w.z + f.matrices[j.w] * w.w;
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
    const glm::mat4 m = f.matrices[j.x] * w.x + f.matrices[j.y] * w.y + f.matrices[j.z] * w.z + f.matrices[j.w] * w.w;
    const glm::vec3 c = f.centers[v];
    p[v] = q * (f.positions[v] - c) + glm::vec3(m * glm::vec4(c, 1));
    n[v] = q * f.normals[v];
  }
}

template <void (*Range)(const Fixture&, std::vector<glm::vec3>&, std::vector<glm::vec3>&, std::size_t, std::size_t)>
void glm_skinning(benchmark::State& state) {
  const Fixture& f = fixture();
  std::vector<glm::vec3> p(kVertices), n(kVertices);
  const auto threads = static_cast<std::size_t>(state.range(0));
  for (auto _ : state) {
    if (threads == 1) {
      Range(f, p, n, 0, kVertices);
    } else {
      // One extra thread started per frame (what a plain implementation does).
      std::jthread other([&] { Range(f, p, n, kVertices / 2, kVertices); });
      Range(f, p, n, 0, kVertices / 2);
    }
    benchmark::DoNotOptimize(p.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * kVertices));
}

BENCHMARK_CAPTURE(dqkit_skinning, lbs, SkinningMethod::lbs)->Arg(1)->Arg(2)->UseRealTime();
BENCHMARK_CAPTURE(dqkit_skinning, dqs, SkinningMethod::dqs)->Arg(1)->Arg(2)->UseRealTime();
BENCHMARK_CAPTURE(dqkit_skinning, cor, SkinningMethod::cor)->Arg(1)->Arg(2)->UseRealTime();
BENCHMARK(glm_skinning<glm_lbs_range>)->Name("glm_lbs")->Arg(1)->Arg(2)->UseRealTime();
BENCHMARK(glm_skinning<glm_dqs_range>)->Name("glm_dqs")->Arg(1)->Arg(2)->UseRealTime();
BENCHMARK(glm_skinning<glm_cor_range>)->Name("glm_cor")->Arg(1)->Arg(2)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
