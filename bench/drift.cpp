// The Kenwright paper's drift experiment (§10–11), measured. A chain of links is animated by
// accumulating a small incremental rigid motion into every link's local transform each frame, in
// single precision, with four representations:
//   (a) 4x4 matrices, (b) 3x4 affine matrices, (c) quaternion + vector, (d) dual quaternions,
// each without renormalization, renormalized every step, and every k steps (Gram–Schmidt or polar
// for matrices, normalization for quaternions and dual quaternions). The same accumulation in
// double precision is the reference. Reported after the last frame: the rotation blocks' unit /
// orthogonality error, their scale and skew, the end effector's position and orientation error,
// and the time a renormalization costs.
//
//   drift [--links N] [--frames F] [--every K] [--csv FILE]
// prints a Markdown table; --csv writes the end-effector position error every 1% of the frames.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "dq/dq.hpp"

namespace {

using namespace dq;

// ---- the representations, each with compose, renormalize and readouts ---------------------------

/// Replaces the rotation block of a 3x4 or 4x4 matrix by its orthonormalized version.
template <int R, class F>
void repair_rotation_block(Mat<float, R, 4>& m, F orthonormalize) {
  const Mat3<float> r = orthonormalize(rotation_block(m));
  for (int c = 0; c < 3; ++c)
    for (int row = 0; row < 3; ++row) m(row, c) = r(row, c);
}

struct Mat4Rep {
  using X = Mat4<float>;
  static X make(const DualQuaternion<double>& q) { return narrow(to_mat4(q)); }
  static X compose(const X& a, const X& b) { return a * b; }
  static Mat3<float> rotation(const X& m) { return rotation_block(m); }
  static Vec3<float> position(const X& m) { return {m(0, 3), m(1, 3), m(2, 3)}; }
  template <class F>
  static void repair(X& m, F orthonormalize) {
    repair_rotation_block(m, orthonormalize);
    m(3, 0) = m(3, 1) = m(3, 2) = 0;  // a 4x4 can also drift in its last row
    m(3, 3) = 1;
  }
  static X narrow(const Mat4<double>& d) {
    X m;
    for (std::size_t i = 0; i < 16; ++i) m.m[i] = static_cast<float>(d.m[i]);
    return m;
  }
};

struct Mat34Rep {
  using X = Mat34<float>;
  static X make(const DualQuaternion<double>& q) {
    const Mat34<double> d = to_mat34(q);
    X m;
    for (std::size_t i = 0; i < 12; ++i) m.m[i] = static_cast<float>(d.m[i]);
    return m;
  }
  static X compose(const X& a, const X& b) { return dq::compose(a, b); }
  static Mat3<float> rotation(const X& m) { return rotation_block(m); }
  static Vec3<float> position(const X& m) { return {m(0, 3), m(1, 3), m(2, 3)}; }
  template <class F>
  static void repair(X& m, F orthonormalize) {
    repair_rotation_block(m, orthonormalize);
  }
};

struct QuatVecRep {
  struct X {
    Quaternion<float> r;
    Vec3<float> t;
  };
  static X make(const DualQuaternion<double>& q) {
    const Vec3<double> t = q.translation();
    return {q.real.cast<float>(), {float(t.x), float(t.y), float(t.z)}};
  }
  static X compose(const X& a, const X& b) { return {a.r * b.r, a.r.rotate(b.t) + a.t}; }
  static Mat3<float> rotation(const X& x) { return x.r.to_matrix(); }
  static Vec3<float> position(const X& x) { return x.t; }
  static void repair(X& x) { x.r.normalize(); }
};

struct DualQuatRep {
  using X = DualQuaternion<float>;
  static X make(const DualQuaternion<double>& q) {
    return q.cast<float>();
  }
  static X compose(const X& a, const X& b) { return a * b; }
  static Mat3<float> rotation(const X& x) { return x.real.to_matrix(); }
  static Vec3<float> position(const X& x) { return x.translation(); }
  static void repair(X& x) { x.normalize(); }
};

// ---- the experiment ------------------------------------------------------------------------------

struct Setup {
  std::size_t links = 32, frames = 100000, every = 16;
  std::vector<DualQuaternion<double>> start, step;  // per link: initial local transform, per-frame increment
};

Setup make_setup(std::size_t links, std::size_t frames, std::size_t every) {
  Setup s{links, frames, every, {}, {}};
  std::mt19937_64 rng(2012);
  std::normal_distribution<double> g;
  for (std::size_t j = 0; j < links; ++j) {
    const Quaternion<double> r = Quaternion<double>(g(rng), g(rng), g(rng), g(rng)).normalized();
    s.start.push_back(DualQuaternion<double>::from_rotation_translation(r, {0, 1, 0}));  // links of length 1
    // A small motion per frame: about 0.6° about a random axis, 1 mm of sway.
    const Vec3<double> axis = normalized(Vec3<double>{g(rng), g(rng), g(rng)});
    s.step.push_back(DualQuaternion<double>::from_rotation_translation(Quaternion<double>::from_axis_angle(axis, 0.01),
                                                                       {1e-3 * g(rng), 1e-3 * g(rng), 1e-3 * g(rng)}));
  }
  return s;
}

struct Result {
  std::string representation, policy;
  double unit_error = 0;      // matrices: max |RᵀR − I|; quaternions: max ||q| − 1| (and |q_r·q_d|)
  double scale_error = 0;     // max | |column| − 1 |
  double skew = 0;            // max |column_i · column_j|, i ≠ j
  double position_error = 0;  // end effector, relative to the chain's reach
  double orientation_error = 0;  // end effector, radians
  double repair_ns = 0;       // one renormalization
  std::vector<double> position_curve;
};

struct Reference {
  std::vector<Vec3<double>> effector_position;  // sampled every 1%
  Vec3<double> final_position;
  Quaternion<double> final_rotation;
};

Reference run_reference(const Setup& s) {
  std::vector<DualQuaternion<double>> local = s.start;
  Reference ref;
  const std::size_t sample = std::max<std::size_t>(1, s.frames / 100);
  for (std::size_t f = 1; f <= s.frames; ++f) {
    DualQuaternion<double> chain = DualQuaternion<double>::identity();
    for (std::size_t j = 0; j < s.links; ++j) {
      local[j] = local[j] * s.step[j];
      chain = chain * local[j];
    }
    if (f % sample == 0) ref.effector_position.push_back(chain.translation());
    if (f == s.frames) {
      ref.final_position = chain.translation();
      ref.final_rotation = chain.real;
    }
  }
  return ref;
}

Vec3<double> widen(const Vec3<float>& v) { return {v.x, v.y, v.z}; }

void measure_rotation(const Mat3<float>& r, Result& out) {
  double worst_scale = 0, worst_skew = 0;
  for (int c = 0; c < 3; ++c) {
    const Vec3<double> a{r(0, c), r(1, c), r(2, c)};
    worst_scale = std::max(worst_scale, std::abs(norm(a) - 1));
    for (int d = c + 1; d < 3; ++d) worst_skew = std::max(worst_skew, std::abs(dot(a, Vec3<double>{r(0, d), r(1, d), r(2, d)})));
  }
  out.scale_error = std::max(out.scale_error, worst_scale);
  out.skew = std::max(out.skew, worst_skew);
  out.unit_error = std::max(out.unit_error, static_cast<double>(orthonormality_error(r)));
}

template <class Rep, class Repair>
Result run(const Setup& s, const Reference& ref, const char* name, const char* policy, std::size_t every, Repair repair) {
  using X = typename Rep::X;
  std::vector<X> local, step;
  for (std::size_t j = 0; j < s.links; ++j) {
    local.push_back(Rep::make(s.start[j]));
    step.push_back(Rep::make(s.step[j]));
  }
  Result out;
  out.representation = name;
  out.policy = policy;
  const std::size_t sample = std::max<std::size_t>(1, s.frames / 100);
  const double reach = static_cast<double>(s.links);
  X chain{};
  for (std::size_t f = 1; f <= s.frames; ++f) {
    for (std::size_t j = 0; j < s.links; ++j) {
      local[j] = Rep::compose(local[j], step[j]);
      if (every && f % every == 0) repair(local[j]);
    }
    chain = local[0];
    for (std::size_t j = 1; j < s.links; ++j) chain = Rep::compose(chain, local[j]);
    if (f % sample == 0) {
      out.position_curve.push_back(norm(widen(Rep::position(chain)) - ref.effector_position[f / sample - 1]) / reach);
    }
  }
  for (const X& x : local) measure_rotation(Rep::rotation(x), out);
  if constexpr (std::is_same_v<Rep, DualQuatRep>) {
    for (const X& x : local) {
      out.unit_error = std::max(out.unit_error, std::abs(double(x.real.norm()) - 1));
      out.unit_error = std::max(out.unit_error, std::abs(double(dot(x.real, x.dual))));
    }
  }
  if constexpr (std::is_same_v<Rep, QuatVecRep>) {
    for (const X& x : local) out.unit_error = std::max(out.unit_error, std::abs(double(x.r.norm()) - 1));
  }
  out.position_error = norm(widen(Rep::position(chain)) - ref.final_position) / reach;
  // Orientation: the rotation of the (repaired) end-effector frame against the reference.
  const Mat3<float> rf = orthonormalize_polar(Rep::rotation(chain));
  Mat3<double> rd;
  for (std::size_t i = 0; i < 9; ++i) rd.m[i] = rf.m[i];
  out.orientation_error = angular_distance(Quaternion<double>::from_matrix(rd), ref.final_rotation);
  // The cost of one repair, timed over many copies of a value drifted by `every` unrepaired steps
  // (at least 16), the typical input of a repair.
  if (every) {
    X drifted = Rep::make(s.start[0]);
    for (std::size_t i = 0; i < std::max<std::size_t>(every, 16); ++i) drifted = Rep::compose(drifted, step[0]);
    std::vector<X> copies(4096, drifted);
    out.repair_ns = 1e300;
    for (int rep = 0; rep < 30; ++rep) {  // the fastest of 30 rounds: the least disturbed
      std::fill(copies.begin(), copies.end(), drifted);
      const auto t0 = std::chrono::steady_clock::now();
      for (X& x : copies) repair(x);
      const auto t1 = std::chrono::steady_clock::now();
      out.repair_ns = std::min(out.repair_ns, std::chrono::duration<double, std::nano>(t1 - t0).count() / static_cast<double>(copies.size()));
    }
    volatile float sink = Rep::position(copies[7]).x;
    (void)sink;
  }
  return out;
}

std::string fmt(double v) {
  char buf[32];
  if (v == 0) return "0";
  std::snprintf(buf, sizeof buf, "%.2e", v);
  return buf;
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t links = 32, frames = 100000, every = 16;
  std::string csv;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i];
    char* end = nullptr;
    const unsigned long long value = std::strtoull(argv[i + 1], &end, 10);
    if (key == "--csv") {
      csv = argv[i + 1];
    } else if ((key == "--links" || key == "--frames" || key == "--every") && end && *end == '\0' && value > 0) {
      (key == "--links" ? links : key == "--frames" ? frames : every) = value;
    } else {
      std::fprintf(stderr, "drift: bad option %s %s\nusage: drift [--links N] [--frames F] [--every K] [--csv FILE]\n", argv[i], argv[i + 1]);
      return 2;
    }
  }
  const Setup s = make_setup(links, frames, every);
  const Reference ref = run_reference(s);
  auto gram = [](const Mat3<float>& m) { return orthonormalize_gram_schmidt(m); };
  auto polar = [](const Mat3<float>& m) { return orthonormalize_polar(m, 3); };
  std::vector<Result> results;
  for (std::size_t k : {std::size_t{0}, std::size_t{1}, every}) {
    const char* policy = k == 0 ? "none" : k == 1 ? "every step" : "every k";
    results.push_back(run<Mat4Rep>(s, ref, "4x4 matrix", policy, k, [&](Mat4Rep::X& m) { Mat4Rep::repair(m, gram); }));
    if (k) results.push_back(run<Mat4Rep>(s, ref, "4x4 matrix (polar)", policy, k, [&](Mat4Rep::X& m) { Mat4Rep::repair(m, polar); }));
    results.push_back(run<Mat34Rep>(s, ref, "3x4 matrix", policy, k, [&](Mat34Rep::X& m) { Mat34Rep::repair(m, gram); }));
    if (k) results.push_back(run<Mat34Rep>(s, ref, "3x4 matrix (polar)", policy, k, [&](Mat34Rep::X& m) { Mat34Rep::repair(m, polar); }));
    results.push_back(run<QuatVecRep>(s, ref, "quaternion + vector", policy, k, [](QuatVecRep::X& x) { QuatVecRep::repair(x); }));
    results.push_back(run<DualQuatRep>(s, ref, "dual quaternion", policy, k, [](DualQuatRep::X& x) { DualQuatRep::repair(x); }));
  }
  std::printf("Drift after %zu frames of a %zu-link chain in float (k = %zu); errors against the same accumulation in double.\n\n",
              frames, links, every);
  std::printf("| representation | renormalize | unit / orthogonality error | scale error | skew | end position error (÷ reach) | end orientation error (rad) | one repair (ns) |\n");
  std::printf("|---|---|---:|---:|---:|---:|---:|---:|\n");
  for (const Result& r : results)
    std::printf("| %s | %s | %s | %s | %s | %s | %s | %s |\n", r.representation.c_str(), r.policy.c_str(), fmt(r.unit_error).c_str(),
                fmt(r.scale_error).c_str(), fmt(r.skew).c_str(), fmt(r.position_error).c_str(), fmt(r.orientation_error).c_str(),
                r.repair_ns ? (std::to_string(static_cast<int>(std::lround(r.repair_ns * 10)) / 10.0).substr(0, 5)).c_str() : "—");
  if (!csv.empty()) {
    std::ofstream out(csv);
    out << "percent";
    for (const Result& r : results) out << "," << r.representation << " / " << r.policy;
    out << "\n";
    for (std::size_t i = 0; i < ref.effector_position.size(); ++i) {
      out << (i + 1);
      for (const Result& r : results) out << "," << (i < r.position_curve.size() ? r.position_curve[i] : 0.0);
      out << "\n";
    }
    if (!out) {
      std::fprintf(stderr, "drift: cannot write %s\n", csv.c_str());
      return 1;
    }
  }
  return 0;
}
