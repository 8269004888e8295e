// Poses in blocks of 16 (dq/anim/pose_blocks.hpp): the documented layout, the blocked forward
// kinematics against 4x4 matrices in double and bit for bit against the pose-by-pose and the
// joint-major results, the dispatched kernel on every instruction set the CPU has, threads, and
// the validation.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include "dq/convert/matrix.hpp"
#include "dq/simd/pose_blocks.hpp"
#include "simd_targets.hpp"
#include "support.hpp"

namespace {

using namespace dq;
using test::for_each_target;
using test::same_bits;

// Two roots, a chain and branches; 37 poses: two full blocks and a partial one.
const std::vector<int> kParents{-1, 0, 1, 2, 1, 4, -1, 6, 3, 8, 0};
constexpr std::size_t kPoses = 37;

struct Poses {
  DualQuaternionBlockStorage<float> local{kParents.size(), kPoses};
  explicit Poses(unsigned seed) {
    test::Random rng(seed);
    for (std::size_t j = 0; j < kParents.size(); ++j)
      for (std::size_t p = 0; p < kPoses; ++p) local.view().set(j, p, rng.rigid<float>(3));
  }
};

template <class T>
void expect_same_bits(const DualQuaternion<T>& a, const DualQuaternion<T>& b, std::size_t j, std::size_t p) {
  const T* x = &a.real.w;
  const T* y = &b.real.w;
  for (int k = 0; k < 8; ++k) ASSERT_EQ(std::memcmp(x + k, y + k, sizeof(T)), 0) << "joint " << j << " pose " << p << " component " << k;
}

/// Every value of `data` set to NaN, so that a value a job does not write cannot pass for a result.
void poison(std::span<float> data) {
  for (float& x : data) x = std::numeric_limits<float>::quiet_NaN();
}

TEST(PoseBlocks, LayoutIsTheDocumentedOne) {
  const std::size_t joints = 3, poses = 35;
  DualQuaternionBlockStorage<float> storage(joints, poses);
  const DualQuaternionBlocks<float> v = storage.view();
  EXPECT_EQ(v.blocks, 3u);  // 35 poses in blocks of 16
  EXPECT_EQ(v.poses(), 48u);
  EXPECT_EQ(v.data.size(), 3u * joints * 128);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(v.data.data()) % 64, 0u);
  for (float x : v.data) ASSERT_EQ(x, 0.0f);  // zero-initialized, padding poses included
  for (std::size_t j = 0; j < joints; ++j)
    for (std::size_t p = 0; p < poses; ++p) {
      const float base = static_cast<float>(1000 * j + 10 * p);
      v.set(j, p, {base, base + 1, base + 2, base + 3, base + 4, base + 5, base + 6, base + 7});
    }
  for (std::size_t j = 0; j < joints; ++j)
    for (std::size_t p = 0; p < poses; ++p)
      for (std::size_t c = 0; c < 8; ++c) {
        const std::size_t at = ((p / 16 * joints + j) * 8 + c) * 16 + p % 16;
        ASSERT_EQ(v.data[at], static_cast<float>(1000 * j + 10 * p + c)) << j << " " << p << " " << c;
      }
  EXPECT_EQ(v.get(2, 34), (DualQuaternion<float>{2340, 2341, 2342, 2343, 2344, 2345, 2346, 2347}));
}

TEST(PoseBlocks, ForwardKinematicsIsTheMatrixProductAndThePoseByPoseResult) {
  const Poses in(1);
  DualQuaternionBlockStorage<float> model(kParents.size(), kPoses);
  const BlockedForwardKinematicsJob<float> job{kParents, in.local.view(), model.view(), 0, 3};
  ASSERT_TRUE(job.validate().ok());
  job.run();
  for (std::size_t p = 0; p < kPoses; ++p) {
    // The same product pose by pose (the scalar type's operator*): equal (its float product may
    // differ in the sign of an exact zero, docs/design.md).
    std::vector<DualQuaternion<float>> local, expected(kParents.size());
    for (std::size_t j = 0; j < kParents.size(); ++j) local.push_back(in.local.view().get(j, p));
    local_to_model<DualQuaternion<float>>(kParents, local, expected);
    // 4x4 matrices in double, chained independently of dqkit's products.
    std::vector<Mat4<double>> m(kParents.size());
    for (std::size_t j = 0; j < kParents.size(); ++j) {
      const Mat4<double> l = to_mat4(local[j].cast<double>());
      m[j] = kParents[j] < 0 ? l : m[static_cast<std::size_t>(kParents[j])] * l;
      const DualQuaternion<float> got = model.view().get(j, p);
      ASSERT_EQ(got, expected[j]) << "joint " << j << " pose " << p;
      const Mat4<double> g = to_mat4(got.cast<double>());
      for (std::size_t k = 0; k < 16; ++k) ASSERT_NEAR(g.m[k], m[j].m[k], 2e-5 * (1 + std::abs(m[j].m[k]))) << j << " " << p;
    }
  }
}

TEST(PoseBlocks, BlockedEqualsTheJointMajorJobBitForBit) {
  const Poses in(2);
  DualQuaternionSoAStorage<float> soa_local(kParents.size(), kPoses), soa_model(kParents.size(), kPoses);
  for (std::size_t j = 0; j < kParents.size(); ++j)
    for (std::size_t p = 0; p < kPoses; ++p) soa_local.view().set(j, p, in.local.view().get(j, p));
  ForwardKinematicsJob<float>{kParents, soa_local.view(), soa_model.view(), 0, kPoses}.run();
  DualQuaternionBlockStorage<float> model(kParents.size(), kPoses);
  BlockedForwardKinematicsJob<float>{kParents, in.local.view(), model.view(), 0, 3}.run();
  for (std::size_t j = 0; j < kParents.size(); ++j)
    for (std::size_t p = 0; p < kPoses; ++p) expect_same_bits(model.view().get(j, p), soa_model.view().get(j, p), j, p);
}

TEST(PoseBlocks, DispatchedKernelIsTheScalarJobBitForBitAndKeepsToItsBlocks) {
  const Poses in(3);
  DualQuaternionBlockStorage<float> expected(kParents.size(), kPoses);
  BlockedForwardKinematicsJob<float>{kParents, in.local.view(), expected.view(), 0, 3}.run();
  const std::span<const float> want = std::as_const(expected).view().data;
  const std::size_t block = kParents.size() * DualQuaternionBlocks<float>::joint_values;  // values per block
  for (const Stores stores : {Stores::cached, Stores::streaming}) {
    SCOPED_TRACE(stores == Stores::cached ? "cached stores" : "streaming stores");
    for_each_target([&](simd::Target) {
      DualQuaternionBlockStorage<float> got(kParents.size(), kPoses);
      const std::span<float> data = got.view().data;
      // Block 1 alone: blocks 0 and 2 (with its padding poses) keep every value they had.
      poison(data);
      simd::run(BlockedForwardKinematicsJob<float>{kParents, in.local.view(), got.view(), 1, 1, stores});
      for (std::size_t i = 0; i < data.size(); ++i) {
        if (i >= block && i < 2 * block)
          ASSERT_TRUE(same_bits(data[i], want[i])) << "value " << i;
        else
          ASSERT_TRUE(std::isnan(data[i])) << "value " << i << " outside block 1 was written";
      }
      // Every block, padding poses included.
      simd::run(BlockedForwardKinematicsJob<float>{kParents, in.local.view(), got.view(), 0, 3, stores});
      for (std::size_t i = 0; i < data.size(); ++i) ASSERT_TRUE(same_bits(data[i], want[i])) << "value " << i;
    });
  }
}

TEST(PoseBlocks, FramesOneAfterAnotherGiveTheBlockedJobsResultBitForBit) {
  // local_to_model_frames on frames stored one after another (joint j of frame f at [f·J + j]),
  // every target, frame counts that are no multiple of any width: bit for bit the blocked job on
  // the same poses (another layout, another kernel); nothing outside `model` written.
  const Poses in(4);
  const std::size_t joints = kParents.size();
  DualQuaternionBlockStorage<float> expected(joints, kPoses);
  BlockedForwardKinematicsJob<float>{kParents, in.local.view(), expected.view(), 0, 3}.run();
  for (const std::size_t frames : {std::size_t{0}, std::size_t{1}, std::size_t{3}, std::size_t{16}, std::size_t{17}, kPoses}) {
    std::vector<DualQuaternion<float>> local(frames * joints);
    for (std::size_t f = 0; f < frames; ++f)
      for (std::size_t j = 0; j < joints; ++j) local[f * joints + j] = in.local.view().get(j, f);
    for_each_target([&](simd::Target) {
      const DualQuaternion<float> guard(1, 2, 3, 4, 5, 6, 7, 8);
      std::vector<DualQuaternion<float>> model(frames * joints + 2, guard);
      ASSERT_TRUE(simd::local_to_model_frames(kParents, local, std::span(model).subspan(1, frames * joints)).ok());
      ASSERT_TRUE(std::memcmp(&model.front(), &guard, sizeof guard) == 0 && std::memcmp(&model.back(), &guard, sizeof guard) == 0)
          << "frames " << frames;
      for (std::size_t f = 0; f < frames; ++f)
        for (std::size_t j = 0; j < joints; ++j) expect_same_bits(model[1 + f * joints + j], expected.view().get(j, f), j, f);
    });
  }
  // More joints than the kernel keeps on the stack (128): parents loaded back from `model`.
  test::Random rng(5);
  std::vector<int> many{-1};
  for (int j = 1; j < 200; ++j) many.push_back(j % 50 == 0 ? -1 : static_cast<int>(rng.uniform<double>(0, j - 0.5)));
  const std::size_t frames = 21;
  DualQuaternionBlockStorage<float> many_local(many.size(), frames), many_expected(many.size(), frames);
  std::vector<DualQuaternion<float>> flat(frames * many.size());
  for (std::size_t f = 0; f < frames; ++f)
    for (std::size_t j = 0; j < many.size(); ++j) many_local.view().set(j, f, flat[f * many.size() + j] = rng.rigid<float>(3));
  BlockedForwardKinematicsJob<float>{many, many_local.view(), many_expected.view(), 0, 2}.run();
  for_each_target([&](simd::Target) {
    std::vector<DualQuaternion<float>> model(flat.size());
    ASSERT_TRUE(simd::local_to_model_frames(many, flat, model).ok());
    for (std::size_t f = 0; f < frames; ++f)
      for (std::size_t j = 0; j < many.size(); ++j) expect_same_bits(model[f * many.size() + j], many_expected.view().get(j, f), j, f);
  });
  // What cannot run says why, and writes nothing.
  std::vector<DualQuaternion<float>> local(2 * joints), model(2 * joints);
  EXPECT_EQ(simd::local_to_model_frames(kParents, local, std::span(model).first(joints)).error().message,
            "local and model must hold the same whole number of frames of 11 joints");
  EXPECT_EQ(simd::local_to_model_frames(kParents, std::span(local).first(joints + 1), std::span(model).first(joints + 1)).error().message,
            "local and model must hold the same whole number of frames of 11 joints");
  const std::vector<int> late{-1, 2, 0};
  EXPECT_EQ(simd::local_to_model_frames(late, std::span(local).first(3), std::span(model).first(3)).error().message,
            "joint 1: parent does not come before it");
  EXPECT_EQ(simd::local_to_model_frames(kParents, local, std::span(local)).error().message, "model must not overlap local");
}

/// local_to_model_frames_parallel<T> with grains below, at and above its 16-frame unit, frame counts
/// that leave the last range partial, on one thread, two and all: bit for bit the one-thread
/// function's result, nothing outside `model` written; its errors come before any work.
template <class T>
void expect_frames_on_threads_as_on_one() {
  const std::size_t joints = kParents.size();
  test::Random rng(6);
  for (const std::size_t frames : {std::size_t{0}, std::size_t{5}, std::size_t{16}, std::size_t{17}, std::size_t{100}, std::size_t{333}}) {
    std::vector<DualQuaternion<T>> local(frames * joints), want(frames * joints);
    for (auto& q : local) q = rng.rigid<T>(3);
    ASSERT_TRUE(simd::local_to_model_frames(kParents, std::span<const DualQuaternion<T>>(local), std::span(want)).ok());
    for (const unsigned threads : {1u, 2u, 0u})
      for (const std::size_t grain : {std::size_t{0}, std::size_t{7}, std::size_t{16}, std::size_t{40}, std::size_t{256}}) {
        const DualQuaternion<T> guard(1, 2, 3, 4, 5, 6, 7, 8);
        std::vector<DualQuaternion<T>> model(frames * joints + 2, guard);
        ASSERT_TRUE(simd::local_to_model_frames_parallel(kParents, std::span<const DualQuaternion<T>>(local),
                                                         std::span(model).subspan(1, frames * joints), threads, grain).ok());
        ASSERT_TRUE(std::memcmp(&model.front(), &guard, sizeof guard) == 0 && std::memcmp(&model.back(), &guard, sizeof guard) == 0)
            << "frames " << frames << ", threads " << threads << ", grain " << grain;
        for (std::size_t f = 0; f < frames; ++f)
          for (std::size_t j = 0; j < joints; ++j) expect_same_bits(model[1 + f * joints + j], want[f * joints + j], j, f);
      }
  }
  // Overlapping spans whose parts would not overlap (model 64 frames after local, parts of 16):
  // refused as a whole, every value left as it was.
  std::vector<DualQuaternion<T>> buffer(164 * joints);
  for (auto& q : buffer) q = rng.rigid<T>(3);
  const std::vector<DualQuaternion<T>> before = buffer;
  const std::span<DualQuaternion<T>> all(buffer);
  const auto in = [](std::span<DualQuaternion<T>> x) { return std::span<const DualQuaternion<T>>(x); };
  EXPECT_EQ(simd::local_to_model_frames_parallel(kParents, in(all.first(100 * joints)), all.subspan(64 * joints), 2, 16).error().message,
            "model must not overlap local");
  const std::vector<int> late{-1, 2, 0};
  EXPECT_EQ(simd::local_to_model_frames_parallel(late, in(all.first(3)), all.subspan(3, 3), 2, 16).error().message,
            "joint 1: parent does not come before it");
  EXPECT_EQ(simd::local_to_model_frames_parallel(kParents, in(all.first(joints + 1)), all.subspan(2 * joints, joints + 1)).error().message,
            "local and model must hold the same whole number of frames of 11 joints");
  EXPECT_EQ(std::memcmp(buffer.data(), before.data(), buffer.size() * sizeof buffer[0]), 0);
}

TEST(PoseBlocks, FramesOnThreadsGiveTheOneThreadResult) {
  expect_frames_on_threads_as_on_one<float>();
  expect_frames_on_threads_as_on_one<double>();
}

TEST(PoseBlocks, FramesInDoubleAreTheProductFrameByFrame) {
  // The double overload runs a kernel of its own per instruction set (2, 4 or 8 frames in the
  // lanes of a vector, records of eight doubles transposed): on every target, frame counts that
  // are no multiple of any width, and more joints than the kernel keeps (parents loaded back from
  // `model`), bit for bit each frame's forward kinematics with the product written out (test::product_reference),
  // nothing outside `model` written; and where FMA is not enabled (GCC's SLP vectorizer then fuses
  // nothing), bit for bit dq::local_to_model on each frame alone. The same checks as float's, with
  // the same messages.
  test::Random rng(7);
  std::vector<int> many{-1};
  for (int j = 1; j < 200; ++j) many.push_back(j % 50 == 0 ? -1 : static_cast<int>(rng.uniform<double>(0, j - 0.5)));
  for (const std::vector<int>* parents : {&kParents, static_cast<const std::vector<int>*>(&many)}) {
    const std::size_t joints = parents->size();
    for (const std::size_t frames : {0u, 1u, 2u, 3u, 4u, 5u, 7u, 8u, 9u, 16u, 17u, 23u}) {
      if (parents == &many && frames % 2 == 0 && frames != 16) continue;  // the long skeleton on fewer counts
      std::vector<DualQuaternion<double>> local(frames * joints), want(frames * joints);
      for (auto& q : local) q = rng.rigid<double>(3);
      for (std::size_t i = 0; i < local.size(); ++i) {
        const int p = (*parents)[i % joints];
        want[i] = p < 0 ? local[i] : test::product_reference(want[i - i % joints + static_cast<std::size_t>(p)], local[i]);
      }
#if !defined(__FMA__)
      std::vector<DualQuaternion<double>> frame(joints);
      for (std::size_t f = 0; f < frames; ++f) {
        local_to_model<DualQuaternion<double>>(*parents, std::span(local).subspan(f * joints, joints), frame);
        for (std::size_t j = 0; j < joints; ++j) expect_same_bits(frame[j], want[f * joints + j], j, f);
      }
#endif
      for_each_target([&](simd::Target) {
        const DualQuaternion<double> guard(1, 2, 3, 4, 5, 6, 7, 8);
        std::vector<DualQuaternion<double>> model(frames * joints + 2, guard);
        ASSERT_TRUE(simd::local_to_model_frames(*parents, std::span<const DualQuaternion<double>>(local),
                                                std::span(model).subspan(1, frames * joints)).ok());
        ASSERT_TRUE(std::memcmp(&model.front(), &guard, sizeof guard) == 0 && std::memcmp(&model.back(), &guard, sizeof guard) == 0)
            << "joints " << joints << ", frames " << frames;
        for (std::size_t f = 0; f < frames; ++f)
          for (std::size_t j = 0; j < joints; ++j) expect_same_bits(model[1 + f * joints + j], want[f * joints + j], j, f);
      });
    }
  }
  const std::size_t joints = kParents.size();
  std::vector<DualQuaternion<double>> local(2 * joints), model(2 * joints);
  const std::span<const DualQuaternion<double>> in(local);
  EXPECT_EQ(simd::local_to_model_frames(kParents, in, std::span(model).first(joints)).error().message,
            "local and model must hold the same whole number of frames of 11 joints");
  EXPECT_EQ(simd::local_to_model_frames(std::vector<int>{-1, 2, 0}, in.first(3), std::span(model).first(3)).error().message,
            "joint 1: parent does not come before it");
  EXPECT_EQ(simd::local_to_model_frames(kParents, in, std::span(local)).error().message, "model must not overlap local");
}

// Streaming stores need a copy of one block's joints on the stack (128 at most) and model storage
// aligned for the widest vector: beyond those, the job falls back to cached stores, with the same
// results (a non-temporal store to an address not aligned to its vector faults: 16 bytes off is
// misaligned for AVX2 and AVX-512, 32 bytes off for AVX-512).
TEST(PoseBlocks, StreamingStoresFallBackWhereTheyCannotRun) {
  test::Random rng(9);
  for (const std::size_t joints : {std::size_t{128}, std::size_t{129}}) {
    std::vector<int> chain(joints);
    for (std::size_t j = 0; j < joints; ++j) chain[j] = static_cast<int>(j) - 1;
    DualQuaternionBlockStorage<float> local(joints, 20), want(joints, 20), got(joints, 20);
    for (std::size_t j = 0; j < joints; ++j)
      for (std::size_t p = 0; p < 20; ++p) local.view().set(j, p, rng.rigid<float>(0.1f));
    BlockedForwardKinematicsJob<float>{chain, local.view(), want.view(), 0, 2}.run();
    for_each_target([&](simd::Target) {
      poison(got.view().data);
      simd::run(BlockedForwardKinematicsJob<float>{chain, local.view(), got.view(), 0, 2, Stores::streaming});
      for (std::size_t i = 0; i < want.view().data.size(); ++i)
        ASSERT_TRUE(same_bits(got.view().data[i], want.view().data[i])) << joints << " joints, value " << i;
    });
  }
  // Model storage 4, 8 and 12 floats (16, 32 and 48 bytes) off a 64-byte boundary, in a larger array.
  const Poses in(5);
  const std::size_t values = kParents.size() * DualQuaternionBlocks<float>::joint_values * 3;
  DualQuaternionBlockStorage<float> want(kParents.size(), kPoses), room(kParents.size(), kPoses + 16);
  BlockedForwardKinematicsJob<float>{kParents, in.local.view(), want.view(), 0, 3}.run();
  for (const std::size_t offset : {std::size_t{4}, std::size_t{8}, std::size_t{12}}) {
    const DualQuaternionBlocks<float> shifted{room.view().data.subspan(offset, values), kParents.size(), 3};
    for_each_target([&](simd::Target) {
      poison(room.view().data);
      simd::run(BlockedForwardKinematicsJob<float>{kParents, in.local.view(), shifted, 0, 3, Stores::streaming});
      for (std::size_t i = 0; i < values; ++i)
        ASSERT_TRUE(same_bits(shifted.data[i], want.view().data[i])) << "offset " << offset << ", value " << i;
    });
  }
}

TEST(PoseBlocks, ThreadsGiveTheSerialResult) {
  const Poses in(4);
  DualQuaternionBlockStorage<float> serial(kParents.size(), kPoses), parallel(kParents.size(), kPoses);
  BlockedForwardKinematicsJob<float>{kParents, in.local.view(), serial.view(), 0, 3}.run();
  for (const Stores stores : {Stores::cached, Stores::streaming}) {
    poison(parallel.view().data);
    ASSERT_TRUE(simd::run_parallel(BlockedForwardKinematicsJob<float>{kParents, in.local.view(), parallel.view(), 0, 3, stores}, 2, 1).ok());
    for (std::size_t i = 0; i < serial.view().data.size(); ++i) ASSERT_TRUE(same_bits(serial.view().data[i], parallel.view().data[i])) << i;
  }

  DualQuaternionBlockStorage<double> local(kParents.size(), kPoses), a(kParents.size(), kPoses), b(kParents.size(), kPoses);
  for (std::size_t j = 0; j < kParents.size(); ++j)
    for (std::size_t p = 0; p < kPoses; ++p) local.view().set(j, p, in.local.view().get(j, p).cast<double>());
  BlockedForwardKinematicsJob<double>{kParents, local.view(), a.view(), 0, 3}.run();
  ASSERT_TRUE(simd::run_parallel(BlockedForwardKinematicsJob<double>{kParents, local.view(), b.view(), 0, 3}, 0, 1).ok());
  for (std::size_t i = 0; i < a.view().data.size(); ++i) ASSERT_EQ(a.view().data[i], b.view().data[i]) << i;
}

TEST(PoseBlocks, ValidationSaysWhatIsWrong) {
  Poses in(5);
  DualQuaternionBlockStorage<float> model(kParents.size(), kPoses), fewer(kParents.size(), 16), other(kParents.size() + 1, kPoses);
  auto error_of = [](const BlockedForwardKinematicsJob<float>& job) {
    const Status s = job.validate();
    return s ? std::string() : s.error().message;
  };
  const BlockedForwardKinematicsJob<float> good{kParents, in.local.view(), model.view(), 0, 3};
  EXPECT_EQ(error_of(good), "");
  std::vector<int> late = kParents;
  late[4] = 5;
  EXPECT_EQ(error_of({late, in.local.view(), model.view(), 0, 3}), "joint 4: parent does not come before it");
  EXPECT_EQ(error_of({kParents, in.local.view(), other.view(), 0, 3}), "the local and model blocks must have one joint per parent entry");
  EXPECT_EQ(error_of({kParents, in.local.view(), fewer.view(), 0, 1}), "local and model hold different numbers of blocks");
  EXPECT_EQ(error_of({kParents, in.local.view(), model.view(), 2, 2}), "block range exceeds the blocks held");
  EXPECT_EQ(error_of({kParents, in.local.view(), model.view(), 4, 0}), "block range exceeds the blocks held");
  // A block count whose size in values wraps around: refused before any size comparison.
  const DualQuaternionBlocks<const float> huge{{}, kParents.size(), std::size_t{1} << 60};
  const DualQuaternionBlocks<float> huge_model{{}, kParents.size(), std::size_t{1} << 60};
  EXPECT_EQ(error_of({kParents, huge, huge_model, 0, 1}), "blocks × joints × 128 values overflow the address range");
  DualQuaternionBlocks<float> short_model = model.view();
  short_model.data = short_model.data.first(short_model.data.size() - 1);
  EXPECT_EQ(error_of({kParents, in.local.view(), short_model, 0, 3}), "a block array is shorter than blocks × joints × 128");
  EXPECT_EQ(error_of({kParents, in.local.view(), in.local.view(), 0, 3}), "the model blocks overlap the local ones");
  DualQuaternionBlockStorage<float> both(kParents.size(), 2 * kPoses + 16);  // room for two, shifted by one value
  const DualQuaternionBlocks<float> all = both.view();
  const DualQuaternionBlocks<float> first{all.data.first(model.view().data.size()), kParents.size(), 3};
  const DualQuaternionBlocks<float> shifted{all.data.subspan(1, model.view().data.size()), kParents.size(), 3};
  EXPECT_EQ(error_of({kParents, first, shifted, 0, 3}), "the model blocks overlap the local ones");
  EXPECT_FALSE(simd::run_parallel(BlockedForwardKinematicsJob<float>{kParents, in.local.view(), in.local.view(), 0, 3}).ok());
}

}  // namespace
