// Thread safety (run under ThreadSanitizer by scripts/test.sh): shared immutable data read from
// many threads, the batch job split across threads, lazily built singletons, and isolated imports
// started concurrently.
#include <gtest/gtest.h>

#include <thread>
#include <vector>

#include "dq/anim/biped.hpp"
#include "dq/anim/forward_kinematics.hpp"
#include "dq/simd/batch.hpp"
#include "dq/io/bvh.hpp"
#include "models.hpp"
#include "support.hpp"
#ifdef DQKIT_HAVE_IMPORT
#include "dq/io/scene.hpp"
#endif

namespace {

using namespace dq;

TEST(Threads, BipedSingletonAndSharedSkeletonFromManyThreads) {
  std::vector<std::jthread> threads;
  std::vector<Vec3<double>> heads(8);
  for (std::size_t t = 0; t < heads.size(); ++t)
    threads.emplace_back([&, t] {
      const Biped& biped = Biped::instance();  // first use races on construction: must be safe
      std::vector<double> q(Biped::dofs, 0.1 * static_cast<double>(t));
      std::vector<DualQuaternion<double>> local(Biped::links), model(Biped::links);
      biped.pose(q, local);
      local_to_model<DualQuaternion<double>>(biped.skeleton(), local, model);
      heads[t] = model[static_cast<std::size_t>(biped.skeleton().find("head"))].translation();
    });
  threads.clear();
  for (std::size_t t = 1; t < heads.size(); ++t) EXPECT_FALSE(heads[t] == heads[0]);
}

TEST(Threads, ParallelBatchJobWritesDisjointPoses) {
  const Biped& biped = Biped::instance();
  const std::size_t poses = 1000;
  DualQuaternionSoAStorage<double> local_store(Biped::links, poses), model_store(Biped::links, poses), serial_store(Biped::links, poses);
  auto local = local_store.view();
  std::vector<DualQuaternion<double>> l(Biped::links);
  std::vector<double> q(Biped::dofs);
  dq::test::Random rng(401);
  for (std::size_t p = 0; p < poses; ++p) {
    for (double& v : q) v = rng.uniform(-1.0, 1.0);
    biped.pose(q, l);
    for (std::size_t j = 0; j < Biped::links; ++j) local.set(j, p, l[j]);
  }
  ForwardKinematicsJob<double> parallel{biped.skeleton().parents(), local, model_store.view(), 0, poses};
  ForwardKinematicsJob<double> serial{biped.skeleton().parents(), local, serial_store.view(), 0, poses};
  ASSERT_TRUE(simd::run_parallel(parallel, 4, 8));
  serial.run();
  for (std::size_t p = 0; p < poses; p += 37)
    for (std::size_t j = 0; j < Biped::links; ++j) EXPECT_EQ(parallel.model.get(j, p), serial.model.get(j, p));
}

TEST(Threads, ConcurrentBvhParsing) {
  const std::string text = "HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 3 Zrotation Xrotation Yrotation\nEnd Site\n{\nOFFSET 0 1 0\n}\n}\n"
                           "MOTION\nFrames: 2\nFrame Time: 0.1\n1 2 3\n4 5 6\n";
  std::vector<std::jthread> threads;
  std::vector<int> ok(8, 0);
  for (std::size_t t = 0; t < ok.size(); ++t)
    threads.emplace_back([&, t] { ok[t] = read_bvh(text, "t").has_value() ? 1 : 0; });
  threads.clear();
  for (int v : ok) EXPECT_EQ(v, 1);
}

#ifdef DQKIT_HAVE_IMPORT
TEST(Threads, IsolatedImportsFromSeveralThreads) {
  DQKIT_REQUIRE_MODELS();
  std::vector<std::jthread> threads;
  std::vector<std::size_t> joints(4, 0);
  for (std::size_t t = 0; t < joints.size(); ++t)
    threads.emplace_back([&, t] {
      const Expected<ImportedScene> s = import_scene(dq::test::assimp_models() / "glTF2/simple_skin/simple_skin.gltf");
      joints[t] = s ? s->skeleton.size() : 0;
    });
  threads.clear();
  for (std::size_t n : joints) EXPECT_EQ(n, joints[0]);
  EXPECT_GT(joints[0], 0u);
}
#endif

}  // namespace
