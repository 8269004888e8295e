// One-at-a-time operations in loops of a fixed length, for counting their instructions with
// callgrind (the machines here have no hardware counters for `perf stat`):
//   instruction_counts <case> <rounds>
// runs <rounds> rounds of 1024 operations of <case> on random inputs; scripts/instruction_counts.sh
// runs it under `valgrind --tool=callgrind` for two round counts and divides the difference by the
// extra operations, which cancels the start-up and the set-up. Cases: the ones docs/performance.md
// reports as missed targets, with their peers.
#include <Eigen/Geometry>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtx/dual_quaternion.hpp>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "dq/dq.hpp"
#include "dq/interop/eigen.hpp"
#include "dq/interop/glm.hpp"

namespace {

constexpr std::size_t kCount = 1024;

/// Unit rigid transforms, rotations from normalized Gaussian quaternions.
std::vector<dq::DualQuaternion<float>> transforms(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1, 1);
  std::vector<dq::DualQuaternion<float>> out(kCount);
  for (auto& x : out)
    x = dq::DualQuaternion<float>::from_rotation_translation(dq::Quaternion<float>(u(rng), u(rng), u(rng), u(rng)).normalized(),
                                                             {u(rng), u(rng), u(rng)});
  return out;
}

/// `rounds` passes of out[i] = op(in[i], i) over the kCount elements.
template <class In, class Out, class Op>
void run(const std::vector<In>& in, std::vector<Out>& out, long rounds, Op op) {
  for (long r = 0; r < rounds; ++r)
    for (std::size_t i = 0; i < kCount; ++i) out[i] = op(in[i], i);
}

/// The sum of every float of `values` (results of types that are arrays of floats: dqkit's, GLM's
/// and Eigen's fixed-size ones): printed, so that no part of a result is optimized away. Its cost
/// does not depend on the rounds, so the difference cancels it.
template <class T>
float checksum(const std::vector<T>& values) {
  static_assert(sizeof(T) % sizeof(float) == 0);
  float sum = 0;
  for (const T& v : values) {
    const float* f = reinterpret_cast<const float*>(&v);
    for (std::size_t k = 0; k < sizeof(T) / sizeof(float); ++k) sum += f[k];
  }
  return sum;
}

template <class T>
std::vector<T> convert(const std::vector<dq::DualQuaternion<float>>& q, T (*make)(const dq::DualQuaternion<float>&)) {
  std::vector<T> out;
  for (const auto& x : q) out.push_back(make(x));
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: instruction_counts <case> <rounds>\n");
    return 2;
  }
  const std::string name = argv[1];
  const long rounds = std::strtol(argv[2], nullptr, 10);
  const auto a = transforms(1), b = transforms(2);
  std::vector<dq::Vec3<float>> points;
  for (const auto& x : transforms(3)) points.push_back(x.translation());
  float sink = 0;
  // Chains: x = x * a[i] over the array, `rounds` times.
  auto chain = [&](auto x, const auto& values) {
    for (long r = 0; r < rounds; ++r)
      for (std::size_t i = 0; i < kCount; ++i) x = x * values[i];
    return x;
  };
  const auto eigen4 = [](const dq::DualQuaternion<float>& q) -> Eigen::Matrix4f { return dq::eigen::to_eigen(dq::to_mat4(q)); };
  const auto glm_dq = [](const dq::DualQuaternion<float>& q) -> glm::dualquat { return dq::glm_interop::to_glm(q); };
  const std::map<std::string, std::function<void()>> cases{
      {"chain_dqkit", [&] { sink = checksum(std::vector{chain(a[0], a)}); }},
      {"chain_eigen_matrix4f", [&] { sink = chain(eigen4(a[0]), convert<Eigen::Matrix4f>(a, +eigen4)).sum(); }},
      // Eigen's faster form of the chain (bench_core's ChainEigenMatrix4TwoBuffers): two matrices
      // and noalias(), no temporary per product.
      {"chain_eigen_matrix4f_two_buffers",
       [&] {
         const auto m = convert<Eigen::Matrix4f>(a, +eigen4);
         Eigen::Matrix4f x = m[0], y;
         for (long r = 0; r < rounds; ++r)
           for (std::size_t i = 0; i + 1 < kCount; i += 2) {
             y.noalias() = x * m[i];
             x.noalias() = y * m[i + 1];
           }
         sink = x.sum();
       }},
      {"compose_dqkit",
       [&] {
         std::vector<dq::DualQuaternion<float>> out(kCount);
         run(a, out, rounds, [&](const auto& x, std::size_t i) { return x * b[i]; });
         sink = checksum(out);
       }},
      {"compose_glm_dualquat",
       [&] {
         const auto ga = convert<glm::dualquat>(a, +glm_dq), gb = convert<glm::dualquat>(b, +glm_dq);
         std::vector<glm::dualquat> out(kCount);
         run(ga, out, rounds, [&](const auto& x, std::size_t i) { return x * gb[i]; });
         sink = checksum(out);
       }},
      {"point_dqkit",
       [&] {
         std::vector<dq::Vec3<float>> out(kCount);
         run(a, out, rounds, [&](const auto& q, std::size_t i) { return q.transform_point(points[i]); });
         sink = checksum(out);
       }},
      {"point_eigen_isometry3f",
       [&] {
         std::vector<Eigen::Isometry3f> m;
         std::vector<Eigen::Vector3f> out(kCount);
         for (const auto& q : a) m.push_back(dq::eigen::to_isometry(q));
         run(m, out, rounds, [&](const auto& t, std::size_t i) -> Eigen::Vector3f { return t * Eigen::Vector3f(points[i].x, points[i].y, points[i].z); });
         sink = checksum(out);
       }},
      {"point_glm_mat4",
       [&] {
         std::vector<glm::mat4> m;
         std::vector<glm::vec4> out(kCount);
         for (const auto& q : a) m.push_back(dq::glm_interop::to_glm(dq::to_mat4(q)));
         run(m, out, rounds, [&](const auto& t, std::size_t i) { return t * glm::vec4(points[i].x, points[i].y, points[i].z, 1); });
         sink = checksum(out);
       }},
      {"point_glm_dualquat",
       [&] {
         const auto g = convert<glm::dualquat>(a, +glm_dq);
         std::vector<glm::vec3> out(kCount);
         run(g, out, rounds, [&](const auto& q, std::size_t i) { return q * glm::vec3(points[i].x, points[i].y, points[i].z); });
         sink = checksum(out);
       }},
      {"slerp_dqkit",
       [&] {
         std::vector<dq::Quaternion<float>> out(kCount);
         run(a, out, rounds, [&](const auto& q, std::size_t i) { return dq::slerp(q.real, b[i].real, 0.3f); });
         sink = checksum(out);
       }},
      {"slerp_eigen",
       [&] {
         std::vector<Eigen::Quaternionf> qa, qb, out(kCount);
         for (std::size_t i = 0; i < kCount; ++i) qa.push_back(dq::eigen::to_eigen(a[i].real)), qb.push_back(dq::eigen::to_eigen(b[i].real));
         run(qa, out, rounds, [&](const auto& q, std::size_t i) { return q.slerp(0.3f, qb[i]); });
         sink = checksum(out);
       }},
      {"slerp_glm",
       [&] {
         std::vector<glm::quat> qa, qb, out(kCount);
         for (std::size_t i = 0; i < kCount; ++i) qa.push_back(dq::glm_interop::to_glm(a[i].real)), qb.push_back(dq::glm_interop::to_glm(b[i].real));
         run(qa, out, rounds, [&](const auto& q, std::size_t i) { return glm::slerp(q, qb[i], 0.3f); });
         sink = checksum(out);
       }},
  };
  const auto found = cases.find(name);
  if (found == cases.end() || rounds < 0) {
    std::fprintf(stderr, "instruction_counts: unknown case '%s' or negative rounds\n", name.c_str());
    return 2;
  }
  found->second();
  std::printf("%s %ld %g\n", name.c_str(), rounds, static_cast<double>(sink));
  return 0;
}
