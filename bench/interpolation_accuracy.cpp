// The accuracy of the batch slerp and sclerp kernels (dq::simd::slerp, dq::simd::sclerp) on every
// instruction set this CPU has, and of the scalar float functions they are held against, over
// many random pairs: each result against dq::slerp and dq::sclerp in long double on the same float
// inputs, the worst error in float ulps (ε = 2^-23) per component. docs/performance.md and
// include/dq/simd/batch.hpp quote its output.
//
// The pairs, drawn separately for slerp and sclerp: a random rotation a (for sclerp with a
// translation of 1e-3 to 1e3, log-uniform); b = a times a relative motion whose angle is
// log-uniform from 1e-25 rad to π, or π less 1e-8 to 1 (half the pairs each; the relative rotation
// made in double, then rounded to float), about a random axis (for sclerp, a screw about an axis
// through a point up to 1e3 from the origin, with a pitch's translation of 1e-3 to 1e3 along it);
// b or −b. One t per block of 1024 pairs (the kernels take one t per call): 0 for the first block,
// 1 for the second, then uniform in [0, 1].
//
//   interpolation_accuracy [--pairs N] [--seed S]
// prints a Markdown table; the error of the dual part is relative to (1 + |t_a| + |t_b|)/2, the
// translations' scale. Exits with 1 when an error exceeds the bounds of tests/test_simd.cpp (16
// ulps for slerp, 8 for sclerp), which hold the scalar functions too.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <random>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "dq/dq.hpp"
#include "dq/simd/batch.hpp"
#include "interpolation_reference.hpp"  // tests/

namespace {

using namespace dq;

constexpr std::size_t kBlock = 1024;

struct Random {
  explicit Random(unsigned long long seed) : engine(seed) {}
  std::mt19937_64 engine;
  std::normal_distribution<float> normal;
  std::uniform_real_distribution<double> uniform{0.0, 1.0};
  double log_uniform(double lo_exponent, double hi_exponent) { return std::pow(10.0, lo_exponent + (hi_exponent - lo_exponent) * uniform(engine)); }
  Vec3<float> direction() { return normalized(Vec3<float>(normal(engine), normal(engine), normal(engine))); }
  Quaternion<float> rotation() { return Quaternion<float>(normal(engine), normal(engine), normal(engine), normal(engine)).normalized(); }
  /// A rotation about `axis` by an angle log-uniform from 1e-25 to π, or π less 1e-8 to 1, made in
  /// double (a float angle cannot come within 8.7e-8 of π) and rounded to float.
  Quaternion<float> relative_rotation(const Vec3<float>& axis) {
    const double pi = std::numbers::pi;
    const double angle = uniform(engine) < 0.5 ? log_uniform(-25, std::log10(pi)) : pi - log_uniform(-8, 0);
    return Quaternion<double>::from_axis_angle(axis.cast<double>(), angle).cast<float>();
  }
  bool coin() { return uniform(engine) < 0.5; }
};

/// The worst errors seen, in ulps: the real part (or the quaternion) and the dual part.
struct Worst {
  double real = 0, dual = 0;
};

/// The largest error in ulps of `got` against `want`, each component relative to `scale`, into `worst`.
template <std::size_t K>
void record(double& worst, const float (&got)[K], const long double (&want)[K], long double scale) {
  for (std::size_t k = 0; k < K; ++k) {
    const long double err = std::abs(static_cast<long double>(got[k]) - want[k]) / scale / std::numeric_limits<float>::epsilon();
    worst = std::max(worst, std::isnan(static_cast<double>(err)) ? std::numeric_limits<double>::infinity() : static_cast<double>(err));
  }
}

void record_quaternion(Worst& w, const Quaternion<float>& got, const Quaternion<long double>& want) {
  record(w.real, {got.w, got.x, got.y, got.z}, {want.w, want.x, want.y, want.z}, 1);
}
void record_dual_quaternion(Worst& w, const DualQuaternion<float>& got, const DualQuaternion<long double>& want, long double scale) {
  record_quaternion(w, got.real, want.real);
  record(w.dual, {got.dual.w, got.dual.x, got.dual.y, got.dual.z}, {want.dual.w, want.dual.x, want.dual.y, want.dual.z}, scale);
}

struct Pairs {
  std::vector<Quaternion<float>> qa, qb;
  std::vector<DualQuaternion<float>> da, db;
  std::vector<Quaternion<long double>> slerp_want;
  std::vector<DualQuaternion<long double>> sclerp_want;
  std::vector<long double> scale;

  void make(Random& rng, float t) {
    qa.clear(), qb.clear(), da.clear(), db.clear(), slerp_want.clear(), sclerp_want.clear(), scale.clear();
    for (std::size_t i = 0; i < kBlock; ++i) {
      const Vec3<float> axis = rng.direction();
      const Quaternion<float> relative = rng.relative_rotation(axis);
      // slerp
      const Quaternion<float> a = rng.rotation(), b0 = a * relative, b = rng.coin() ? -b0 : b0;
      qa.push_back(a), qb.push_back(b);
      const Quaternion<float> bf = dot(a, b) < 0.0f ? -b : b;
      const Quaternion<long double> al = a.cast<long double>(), bl = bf.cast<long double>();
      slerp_want.push_back(slerp(al, bl, static_cast<long double>(t), dot(al, bl) < 0 ? Path::longest : Path::shortest));
      // sclerp: a screw about an axis through c, with a translation along it
      const Vec3<float> c = rng.direction() * static_cast<float>(rng.log_uniform(-3, 3));
      const float pitch = static_cast<float>(rng.log_uniform(-3, 3)) * (rng.coin() ? -1.0f : 1.0f);
      const Vec3<float> across = c - relative.rotate(c);
      const DualQuaternion<float> screw = DualQuaternion<float>::from_rotation_translation(relative, across + axis * pitch);
      const DualQuaternion<float> ra = DualQuaternion<float>::from_rotation_translation(rng.rotation(), rng.direction() * static_cast<float>(rng.log_uniform(-3, 3)));
      const DualQuaternion<float> rb0 = ra * screw, rb = rng.coin() ? -rb0 : rb0;
      da.push_back(ra), db.push_back(rb);
      sclerp_want.push_back(test::sclerp_reference(ra, rb, t));
      scale.push_back((1 + norm(ra.cast<long double>().translation()) + norm(rb.cast<long double>().translation())) / 2);
    }
  }
};

/// The four arrays of `c` as the slerp kernel's rows (T const for reading).
template <class T, class C>
simd::QuaternionRows<T> quaternion_rows(C& c) {
  return {c[0].data(), c[1].data(), c[2].data(), c[3].data()};
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t pairs = std::size_t{1} << 24;
  unsigned long long seed = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if ((arg == "--pairs" || arg == "--seed") && i + 1 < argc) {
      char* end = nullptr;
      const unsigned long long v = std::strtoull(argv[++i], &end, 10);
      if (*end != '\0' || v == 0) {
        std::fprintf(stderr, "interpolation_accuracy: %s needs a positive integer, got '%s'\n", arg.c_str(), argv[i]);
        return 2;
      }
      if (arg == "--pairs")
        pairs = static_cast<std::size_t>(v);
      else
        seed = v;
    } else {
      std::fprintf(stderr, "usage: interpolation_accuracy [--pairs N] [--seed S]\n");
      return 2;
    }
  }
  const std::span<const simd::Target> targets = simd::available_targets();
  std::vector<Worst> slerp_worst(targets.size() + 1), sclerp_worst(targets.size() + 1);  // [0]: the scalar float functions
  Random rng(seed);
  Pairs p;
  ComponentArrays<float, 4> qa(kBlock), qb(kBlock), q_out(kBlock);
  ComponentArrays<float, 8> da(kBlock), db(kBlock), d_out(kBlock);
  std::vector<Quaternion<float>> q_got(kBlock);
  std::vector<DualQuaternion<float>> d_got(kBlock);
  const std::size_t blocks = (pairs + kBlock - 1) / kBlock;
  for (std::size_t block = 0; block < blocks; ++block) {
    const float t = block == 0 ? 0.0f : block == 1 ? 1.0f : static_cast<float>(rng.uniform(rng.engine));
    p.make(rng, t);
    for (std::size_t i = 0; i < kBlock; ++i) {
      record_quaternion(slerp_worst[0], slerp(p.qa[i], p.qb[i], t), p.slerp_want[i]);
      record_dual_quaternion(sclerp_worst[0], sclerp(p.da[i], p.db[i], t), p.sclerp_want[i], p.scale[i]);
    }
    simd::to_rows(p.qa, quaternion_rows<float>(qa)), simd::to_rows(p.qb, quaternion_rows<float>(qb));
    simd::to_rows(p.da, simd::rows(da)), simd::to_rows(p.db, simd::rows(db));
    for (std::size_t k = 0; k < targets.size(); ++k) {
      const simd::ScopedTarget scope(targets[k]);
      simd::slerp(quaternion_rows<const float>(qa), quaternion_rows<const float>(qb), t, quaternion_rows<float>(q_out), kBlock);
      simd::from_rows(quaternion_rows<const float>(q_out), q_got);
      for (std::size_t i = 0; i < kBlock; ++i) record_quaternion(slerp_worst[k + 1], q_got[i], p.slerp_want[i]);
      simd::sclerp(simd::rows(std::as_const(da)), simd::rows(std::as_const(db)), t, simd::rows(d_out), kBlock);
      simd::from_rows(simd::rows(std::as_const(d_out)), d_got);
      for (std::size_t i = 0; i < kBlock; ++i) record_dual_quaternion(sclerp_worst[k + 1], d_got[i], p.sclerp_want[i], p.scale[i]);
    }
  }
  std::printf("%zu pairs (seed %llu), worst error in float ulps against long double\n\n", blocks * kBlock, seed);
  std::printf("| function | slerp | sclerp, real part | sclerp, dual part |\n| --- | ---: | ---: | ---: |\n");
  std::printf("| dq::slerp<float>, dq::sclerp<float> | %.2f | %.2f | %.2f |\n", slerp_worst[0].real, sclerp_worst[0].real, sclerp_worst[0].dual);
  for (std::size_t k = 0; k < targets.size(); ++k)
    std::printf("| dq::simd, %s | %.2f | %.2f | %.2f |\n", std::string(simd::to_string(targets[k])).c_str(), slerp_worst[k + 1].real,
                sclerp_worst[k + 1].real, sclerp_worst[k + 1].dual);
  bool within = true;
  for (std::size_t k = 0; k < slerp_worst.size(); ++k)
    within = within && slerp_worst[k].real <= 16 && sclerp_worst[k].real <= 8 && sclerp_worst[k].dual <= 8;
  if (!within) std::printf("\nAn error exceeds the tests' bounds (16 ulps for slerp, 8 for sclerp).\n");
  return within ? 0 : 1;
}
