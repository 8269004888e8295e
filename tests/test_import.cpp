// Import through Assimp: real files from Debian's assimp-testmodels (glTF 2.0 skin, DirectX X,
// FBX, Collada, IQM, BVH), checked for structure and against dqkit's own BVH reader.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "dq/anim/forward_kinematics.hpp"
#include "dq/io/scene.hpp"
#include "dq/util/sanitizers.hpp"
#include "models.hpp"
#include "support.hpp"

namespace {

using namespace dq;
const std::filesystem::path kModels = dq::test::assimp_models();

TEST(Import, GltfSimpleSkin) {
  DQKIT_REQUIRE_MODELS();
  const Expected<ImportedScene> s = import_scene(kModels / "glTF2/simple_skin/simple_skin.gltf");
  ASSERT_TRUE(s) << s.error().message;
  EXPECT_GE(s->skeleton.size(), 3u);
  ASSERT_EQ(s->meshes.size(), 1u);
  const ImportedMesh& mesh = s->meshes[0];
  ASSERT_FALSE(mesh.influences.empty());
  EXPECT_EQ(mesh.influence_offsets.size(), mesh.positions.size() + 1);
  EXPECT_EQ(mesh.bone_joints.size(), 2u);
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {  // weights sum to one per vertex
    double sum = 0;
    for (std::uint32_t k = mesh.influence_offsets[v]; k < mesh.influence_offsets[v + 1]; ++k) sum += double(mesh.influences[k].weight);
    EXPECT_NEAR(sum, 1.0, 1e-6);
  }
  ASSERT_EQ(s->animations.size(), 1u);
  const Animation& a = s->animations[0].animation;
  EXPECT_EQ(a.joint_count, s->skeleton.size());
  EXPECT_NEAR(a.duration(), 5.5, 1e-9);  // the file's keys span 5.5 s
  for (const auto& q : a.locals) EXPECT_TRUE(q.is_unit(1e-9));
}

TEST(Import, DirectXFbxColladaIqmLoad) {
  DQKIT_REQUIRE_MODELS();
  struct Case {
    const char* file;
    std::size_t min_joints;
    bool skinned, animated;
  };
  for (const Case& c : {Case{"X/BCN_Epileptic.X", 50, true, true}, Case{"FBX/animation_with_skeleton.fbx", 10, true, true},
                        Case{"Collada/human.zae", 2, false, false}, Case{"IQM/mrfixit.iqm", 1, false, false}}) {
    const Expected<ImportedScene> s = import_scene(kModels / c.file);
    ASSERT_TRUE(s) << c.file << ": " << s.error().message;
    EXPECT_GE(s->skeleton.size(), c.min_joints) << c.file;
    bool skinned = false;
    for (const ImportedMesh& m : s->meshes) skinned |= !m.influences.empty();
    EXPECT_EQ(skinned, c.skinned) << c.file;
    EXPECT_EQ(!s->animations.empty(), c.animated) << c.file;
    for (const ImportedAnimation& a : s->animations)
      for (const auto& q : a.animation.locals) ASSERT_TRUE(q.is_unit(1e-6)) << c.file;
  }
}

TEST(Import, AssimpBvhAgreesWithDqkitsReader) {
  DQKIT_REQUIRE_MODELS();
  // Two independent readers of 01_01.bvh: world positions of every joint present in both, at
  // frames that fall on the 120 Hz grid of the 30 Hz resampling (every 4th file frame).
  const Expected<Motion> ours = load_motion(kModels / "BVH/01_01.bvh");
  ASSERT_TRUE(ours) << ours.error().message;
  const Expected<ImportedScene> theirs = import_scene(kModels / "BVH/01_01.bvh", {.sample_rate = 30, .meshes = false});
  ASSERT_TRUE(theirs) << theirs.error().message;
  ASSERT_FALSE(theirs->animations.empty());
  const Animation& ta = theirs->animations[0].animation;
  std::vector<DualQuaternion<double>> a(ours->skeleton.size()), b(theirs->skeleton.size());
  std::size_t compared = 0;
  for (std::size_t f : {std::size_t{0}, std::size_t{10}, std::size_t{100}}) {
    local_to_model<DualQuaternion<double>>(ours->skeleton, ours->animation.frame(4 * f), a);
    local_to_model<DualQuaternion<double>>(theirs->skeleton, ta.frame(f), b);
    for (std::size_t j = 0; j < ours->skeleton.size(); ++j) {
      if (ours->skeleton.is_end_site(j)) continue;
      const int k = theirs->skeleton.find(ours->skeleton.names()[j]);
      if (k < 0) continue;
      // Assimp keeps keys in float: agreement to float precision of the positions (~1e-5 · 40).
      EXPECT_LE(dq::test::max_abs_diff(a[j].translation(), b[static_cast<std::size_t>(k)].translation()), 2e-3)
          << ours->skeleton.names()[j] << " frame " << f;
      ++compared;
    }
  }
  EXPECT_GE(compared, 3u * 30u);
}

TEST(Import, LoadMotionReadsBvhOnlyImportMotionEveryFormat) {
  DQKIT_REQUIRE_MODELS();
  const std::filesystem::path gltf = kModels / "glTF2/simple_skin/simple_skin.gltf", bvh = kModels / "BVH/01_03.bvh";
  const Expected<Motion> not_bvh = load_motion(gltf);
  ASSERT_FALSE(not_bvh);
  EXPECT_EQ(not_bvh.error().message, gltf.string() + ": not a BVH file (other formats are read by dq::import_motion, in dqkit::import, built with Assimp)");
  const Expected<Motion> imported = import_motion(gltf);
  ASSERT_TRUE(imported) << imported.error().message;
  EXPECT_EQ(imported->format, "gltf");
  EXPECT_TRUE(imported->scene && !imported->bvh);
  const Expected<Motion> a = load_motion(bvh), b = import_motion(bvh);  // BVH: dqkit's reader either way
  ASSERT_TRUE(a && b);
  EXPECT_TRUE(b->bvh && !b->scene);
  EXPECT_EQ(a->animation.locals, b->animation.locals);
}

TEST(Import, ErrorsNameTheFile) {
  const Expected<ImportedScene> missing = import_scene("/nonexistent/model.gltf");
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().message.find("/nonexistent/model.gltf: no such file"), std::string::npos);
  const std::filesystem::path junk = std::filesystem::temp_directory_path() / "dqkit_junk.gltf";
  std::ofstream(junk) << "{ this is not glTF";
  const Expected<ImportedScene> bad = import_scene(junk);
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().message.find(junk.string()), std::string::npos);
  std::filesystem::remove(junk);
  const std::string text = "not a model at all";
  const Expected<ImportedScene> mem = import_scene_from_memory(std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()), "fbx");
  EXPECT_FALSE(mem);
}

TEST(Import, RunningOutOfMemoryIsSaidInWords) {
  // Assimp's test file that declares more than memory holds: not a bare std::bad_alloc.
  // (Sanitized builds set no memory limit on the worker: there the allocation succeeds, slowly.)
  if (kSanitizedBuild) GTEST_SKIP() << "no address-space limit on the importer under sanitizers";
  DQKIT_REQUIRE_MODELS();
  const Expected<ImportedScene> oom = import_scene(kModels / "invalid/OutOfMemory.off");
  ASSERT_FALSE(oom);
  EXPECT_NE(oom.error().message.find("OutOfMemory.off: the importer ran out of memory on this file (std::bad_alloc)"), std::string::npos)
      << oom.error().message;
}

}  // namespace

namespace {

TEST(Import, IsolationTurnsImporterCrashesAndHangsIntoErrors) {
  DQKIT_REQUIRE_MODELS();
  // An IQM header found by fuzzing that makes Assimp 5.2 dereference a wild pointer.
  const std::filesystem::path crasher = std::filesystem::path(DQKIT_SOURCE_DIR) / "fuzz/regressions/assimp_crashers/assimp_iqm_header_crash.iqm";
  const Expected<ImportedScene> s = import_scene(crasher);
  ASSERT_FALSE(s);
  // With Debian's Assimp 5.2 this is "...: the importer (Assimp) crashed on this file (...)"; a
  // fixed Assimp would reject the file with its own message. Either way: an error naming the file.
  EXPECT_NE(s.error().message.find("assimp_iqm_header_crash.iqm: "), std::string::npos) << s.error().message;
  // A deadline that cannot be met: the child is killed and the caller told.
  ImportOptions quick;
  quick.timeout_seconds = 1e-6;
  const Expected<ImportedScene> t = import_scene(kModels / "X/BCN_Epileptic.X", quick);
  ASSERT_FALSE(t);
  EXPECT_NE(t.error().message.find("did not finish within"), std::string::npos) << t.error().message;
}

TEST(Import, IsolatedAndInProcessResultsAreIdentical) {
  DQKIT_REQUIRE_MODELS();
  ImportOptions in_process;
  in_process.isolate = false;
  for (const char* file : {"glTF2/simple_skin/simple_skin.gltf", "X/BCN_Epileptic.X"}) {
    const Expected<ImportedScene> a = import_scene(kModels / file), b = import_scene(kModels / file, in_process);
    ASSERT_TRUE(a && b) << file;
    ASSERT_EQ(a->skeleton.size(), b->skeleton.size());
    for (std::size_t j = 0; j < a->skeleton.size(); ++j) {
      EXPECT_EQ(a->skeleton.names()[j], b->skeleton.names()[j]);
      EXPECT_EQ(a->skeleton.parents()[j], b->skeleton.parents()[j]);
      EXPECT_EQ(a->skeleton.rest_pose()[j], b->skeleton.rest_pose()[j]);
    }
    ASSERT_EQ(a->meshes.size(), b->meshes.size());
    for (std::size_t m = 0; m < a->meshes.size(); ++m) {
      EXPECT_EQ(a->meshes[m].positions, b->meshes[m].positions);
      EXPECT_EQ(a->meshes[m].indices, b->meshes[m].indices);
      EXPECT_EQ(a->meshes[m].influence_offsets, b->meshes[m].influence_offsets);
    }
    ASSERT_EQ(a->animations.size(), b->animations.size());
    for (std::size_t k = 0; k < a->animations.size(); ++k) EXPECT_EQ(a->animations[k].animation.locals, b->animations[k].animation.locals);
  }
}

}  // namespace

// ---- importer results a user can trust (issue 9) ------------------------------------------------
namespace {

bool has_joint(const Skeleton& s, std::string_view part) {
  for (const std::string& n : s.names())
    if (n.find(part) != std::string::npos) return true;
  return false;
}

TEST(ImportTrust, MorphAnimationIsReportedNotSilentlyDropped) {
  DQKIT_REQUIRE_MODELS();
  // AnimatedMorphCube animates morph-target weights only: its meshes keep their base shape in
  // dqkit, which says so (the clip alone, with its 127 frames, looked like motion).
  const Expected<ImportedScene> s = import_scene(kModels / "glTF2/glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf");
  ASSERT_TRUE(s) << s.error().message;
  bool warned = false;
  for (const std::string& w : s->warnings) warned = warned || w.find("changes mesh shapes") != std::string::npos;
  EXPECT_TRUE(warned);
  const Expected<ImportedScene> skinned = import_scene(kModels / "glTF2/simple_skin/simple_skin.gltf");
  ASSERT_TRUE(skinned) << skinned.error().message;
  for (const std::string& w : skinned->warnings) EXPECT_EQ(w.find("changes mesh shapes"), std::string::npos) << w;
}

TEST(ImportTrust, OneBrokenSkinDoesNotFailTheFile) {
  DQKIT_REQUIRE_MODELS();
  // anim_test.x: a mesh whose bone names no node. Assimp loads it; the mesh is left out with a
  // warning and the skeleton and animation load.
  const Expected<ImportedScene> s = import_scene(kModels / "X/anim_test.x");
  ASSERT_TRUE(s) << s.error().message;
  EXPECT_EQ(s->animations.size(), 1u);
  bool warned = false;
  for (const std::string& w : s->warnings) warned = warned || w.find("with no node; the mesh is left out") != std::string::npos;
  EXPECT_TRUE(warned);
}

TEST(ImportTrust, LightsCamerasAndPivotsAreNotJoints) {
  DQKIT_REQUIRE_MODELS();
  const Expected<ImportedScene> s = import_scene(kModels / "FBX/huesitos.fbx");
  ASSERT_TRUE(s) << s.error().message;
  EXPECT_FALSE(has_joint(s->skeleton, "Lamp"));
  EXPECT_FALSE(has_joint(s->skeleton, "Camera"));
  EXPECT_FALSE(has_joint(s->skeleton, "$AssimpFbx$"));
  ImportOptions keep;
  keep.lights_and_cameras = true;
  const Expected<ImportedScene> all = import_scene(kModels / "FBX/huesitos.fbx", keep);
  ASSERT_TRUE(all) << all.error().message;
  EXPECT_TRUE(has_joint(all->skeleton, "Lamp"));
  EXPECT_EQ(all->skeleton.size(), s->skeleton.size() + 2);
}

TEST(ImportTrust, ResampledClipsEndOnTheirLastKey) {
  DQKIT_REQUIRE_MODELS();
  for (double rate : {24.0, 30.0, 7.0}) {
    ImportOptions o;
    o.sample_rate = rate;
    const Expected<ImportedScene> s = import_scene(kModels / "glTF2/simple_skin/simple_skin.gltf", o);
    ASSERT_TRUE(s) << s.error().message;
    const Animation& a = s->animations[0].animation;
    EXPECT_EQ(a.frame_count, resampled_frame_count(5.5, rate)) << rate;  // the keys span 5.5 s
    EXPECT_GE(a.duration(), 5.5 - 1e-9) << rate;
  }
}

TEST(ImportTrust, DegenerateNodeTransformsAreErrors) {
  // A glTF node with an all-zero matrix, and one with a mirror: both would decompose into an
  // arbitrary rotation; they are errors that name the node.
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("dqkit_degenerate_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string head = R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"name":"bad","matrix":[)";
  for (const auto& [name, matrix] : std::vector<std::pair<std::string, std::string>>{
           {"zero", "0,0,0,0, 0,0,0,0, 0,0,0,0, 0,0,0,1"}, {"mirror", "-1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1"},
           {"huge", "1e30,0,0,0, 0,1e30,0,0, 0,0,1e30,0, 0,0,0,1"}}) {
    const std::filesystem::path file = dir / (name + ".gltf");
    std::ofstream(file) << head << matrix << "]}]}";
    const Expected<ImportedScene> s = import_scene(file);
    ASSERT_FALSE(s) << name;
    EXPECT_NE(s.error().message.find("node 'bad' has a transform that is not a rotation and a scale"), std::string::npos)
        << name << ": " << s.error().message;
  }
  std::filesystem::remove_all(dir);
}

TEST(ImportTrust, ImportMotionRecognizesBvhByContentAndRefusesFifos) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("dqkit_bycontent_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "capture.mocap") << "HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 0\n}\nMOTION\nFrames: 0\nFrame Time: 1\n";
  const Expected<Motion> m = import_motion(dir / "capture.mocap");
  ASSERT_TRUE(m) << m.error().message;
  EXPECT_EQ(m->format, "bvh");
  ASSERT_EQ(::mkfifo((dir / "pipe.gltf").c_str(), 0600), 0);
  const Expected<Motion> f = import_motion(dir / "pipe.gltf");
  ASSERT_FALSE(f);
  EXPECT_NE(f.error().message.find("is not a regular file"), std::string::npos) << f.error().message;
  std::filesystem::remove_all(dir);
}

}  // namespace
