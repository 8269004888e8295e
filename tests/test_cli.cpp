// The command-line tool, run as a user would: outputs, exit codes, error messages, safe writing.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "dq/anim/forward_kinematics.hpp"
#include "dq/io/motion.hpp"
#ifdef DQKIT_HAVE_IMPORT
#include "dq/io/scene.hpp"
#endif
#include "models.hpp"

namespace {

using namespace dq;
namespace fs = std::filesystem;
const fs::path kModels = dq::test::assimp_models();
const std::string kTool = DQKIT_CLI;

struct Outcome {
  int code;
  std::string out, err;
};

Outcome run(const std::string& args) {
  const fs::path err_file = fs::temp_directory_path() / "dqkit_cli_stderr.txt";
  const std::string command = kTool + " " + args + " 2>" + err_file.string();
  Outcome r{};
  FILE* p = popen(command.c_str(), "r");
  if (!p) return {-1, "", "popen failed"};
  char buf[65536];
  std::size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, n);
  const int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream e(err_file);
  std::stringstream ss;
  ss << e.rdbuf();
  r.err = ss.str();
  return r;
}

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    DQKIT_REQUIRE_MODELS();
    dir_ = fs::temp_directory_path() / ("dqkit_cli_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!dir_.empty()) fs::remove_all(dir_);
  }
  fs::path dir_;
};

TEST_F(Cli, Info) {
  const Outcome r = run("info " + (kModels / "BVH/01_01.bvh").string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("joints: 38 (7 end sites)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("channels: 96"), std::string::npos);
  EXPECT_NE(r.out.find("frames: 2752, frame time 0.0083333 s"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Hips [Xposition Yposition Zposition Zrotation Yrotation Xrotation]"), std::string::npos);
}

TEST_F(Cli, FkCsvMatchesTheLibrary) {
  const fs::path file = kModels / "BVH/01_03.bvh";
  const Outcome r = run("fk " + file.string() + " --frames 0,7,100");
  ASSERT_EQ(r.code, 0) << r.err;
  std::istringstream lines(r.out);
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line, "frame,joint,x,y,z,qw,qx,qy,qz\r");  // RFC 4180: CRLF
  const Expected<Motion> m = load_motion(file);
  ASSERT_TRUE(m);
  std::vector<DualQuaternion<double>> model(m->skeleton.size());
  for (std::size_t f : {std::size_t{0}, std::size_t{7}, std::size_t{100}}) {
    local_to_model<DualQuaternion<double>>(m->skeleton, m->animation.frame(f), model);
    for (std::size_t j = 0; j < model.size(); ++j) {
      ASSERT_TRUE(std::getline(lines, line));
      std::istringstream cells(line);
      std::string frame, joint, v;
      std::getline(cells, frame, ',');
      std::getline(cells, joint, ',');
      EXPECT_EQ(std::stoul(frame), f);
      EXPECT_EQ(joint, m->skeleton.names()[j]);
      std::vector<double> values;
      while (std::getline(cells, v, ',')) values.push_back(std::stod(v));
      ASSERT_EQ(values.size(), 7u);
      const Vec3<double> p = model[j].translation();
      const Quaternion<double> q = model[j].real.canonical();
      EXPECT_EQ(values[0], p.x);  // %.17g round-trips exactly
      EXPECT_EQ(values[1], p.y);
      EXPECT_EQ(values[2], p.z);
      EXPECT_EQ(values[3], q.w);
      EXPECT_GE(values[3], 0.0);
      EXPECT_EQ(values[6], q.z);
    }
  }
  EXPECT_FALSE(std::getline(lines, line));
  EXPECT_NE(r.out.find(",LeftToeBase_End,"), std::string::npos);  // End Sites included
}

TEST_F(Cli, FkJsonAndAll) {
  const Outcome r = run("fk " + (kModels / "BVH/01_01.bvh").string() + " --frames 3 --format json");
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["frames"].size(), 1u);
  EXPECT_EQ(j["frames"][0]["frame"], 3);
  EXPECT_EQ(j["frames"][0]["joints"].size(), 38u);
  EXPECT_EQ(j["frames"][0]["joints"][0]["joint"], "Hips");
  const Outcome all = run("fk " + (kModels / "BVH/01_01.bvh").string() + " --all -o " + (dir_ / "all.csv").string());
  ASSERT_EQ(all.code, 0) << all.err;
  const std::string csv = read_file(dir_ / "all.csv");
  EXPECT_EQ(static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n')), 1 + 2752u * 38u);
}

TEST_F(Cli, BadArgumentsAndFilesGiveClearErrors) {
  const std::string bvh = (kModels / "BVH/01_01.bvh").string();
  Outcome r = run("fk " + bvh + " --frames 99999");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("--frames: frame 99999 out of range (the file has 2752 frames"), std::string::npos) << r.err;
  r = run("fk " + bvh + " --frames 1,x2");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("'x2' is not a frame number"), std::string::npos) << r.err;
  r = run("fk " + bvh + " --frames 1 --all");
  EXPECT_NE(r.code, 0);
  r = run("fk " + bvh + " --format xml");
  EXPECT_NE(r.code, 0);
  r = run("info /nonexistent.bvh");
  EXPECT_EQ(r.code, 1);
#ifdef DQKIT_HAVE_IMPORT
  EXPECT_NE(r.err.find("/nonexistent.bvh: no such file"), std::string::npos) << r.err;
#else
  EXPECT_NE(r.err.find("/nonexistent.bvh: cannot open"), std::string::npos) << r.err;
#endif
  std::ofstream(dir_ / "broken.bvh") << "HIERARCHY\nROOT A\n{\nOFFSET 0 0\n";
  r = run("info " + (dir_ / "broken.bvh").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("broken.bvh:5: expected a finite number, found end of file"), std::string::npos) << r.err;
  r = run("frobnicate");
  EXPECT_NE(r.code, 0);
  r = run("");
  EXPECT_NE(r.code, 0);
}

TEST_F(Cli, ConvertChangesRotationOrderAndWritesSafely) {
  const fs::path in = kModels / "BVH/01_01.bvh", out = dir_ / "zxy.bvh";
  Outcome r = run("convert " + in.string() + " " + out.string() + " --rotation-order ZXY");
  ASSERT_EQ(r.code, 0) << r.err;
  const Expected<Motion> a = load_motion(in), b = load_motion(out);
  ASSERT_TRUE(b) << b.error().message;
  EXPECT_NE(read_file(out).find("CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation"), std::string::npos);
  std::vector<DualQuaternion<double>> ma(a->skeleton.size()), mb(b->skeleton.size());
  for (std::size_t f : {std::size_t{0}, std::size_t{1000}}) {
    local_to_model<DualQuaternion<double>>(a->skeleton, a->animation.frame(f), ma);
    local_to_model<DualQuaternion<double>>(b->skeleton, b->animation.frame(f), mb);
    for (std::size_t j = 0; j < ma.size(); ++j) EXPECT_TRUE(approx_equal(ma[j], mb[j], 1e-9, SignPolicy::same_rotation));
  }
  // Refuses to overwrite without --force; the existing file is untouched.
  const std::string before = read_file(out);
  r = run("convert " + in.string() + " " + out.string() + " --rotation-order XYZ");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("already exists (use --force"), std::string::npos) << r.err;
  EXPECT_EQ(read_file(out), before);
  r = run("convert " + in.string() + " " + out.string() + " --rotation-order XYZ --force");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(read_file(out), before);
  // A failed conversion leaves the target as it was.
  std::ofstream(dir_ / "broken.bvh") << "HIERARCHY\n";
  const std::string kept = read_file(out);
  r = run("convert " + (dir_ / "broken.bvh").string() + " " + out.string() + " --force");
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(read_file(out), kept);
  // Not onto the input, and only to BVH.
  r = run("convert " + out.string() + " " + out.string() + " --force");
  EXPECT_NE(r.err.find("is the input file"), std::string::npos) << r.err;
  r = run("convert " + in.string() + " " + (dir_ / "x.fbx").string());
  EXPECT_NE(r.err.find("only BVH output"), std::string::npos);
  // No temporary files are left behind.
  for (const auto& e : fs::directory_iterator(dir_)) EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos);
}

#ifdef DQKIT_HAVE_IMPORT
TEST_F(Cli, ConvertImportedAnimationToBvh) {
  const fs::path in = kModels / "X/BCN_Epileptic.X", out = dir_ / "epileptic.bvh";
  const Outcome r = run("convert " + in.string() + " " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const Expected<Motion> a = import_motion(in), b = load_motion(out);
  ASSERT_TRUE(a) << a.error().message;
  ASSERT_TRUE(b) << b.error().message;
  ASSERT_EQ(a->animation.frame_count, b->animation.frame_count);
  std::vector<DualQuaternion<double>> ma(a->skeleton.size()), mb(b->skeleton.size());
  for (std::size_t f = 0; f < a->animation.frame_count; f += 33) {
    local_to_model<DualQuaternion<double>>(a->skeleton, a->animation.frame(f), ma);
    local_to_model<DualQuaternion<double>>(b->skeleton, b->animation.frame(f), mb);
    for (std::size_t j = 0; j < ma.size(); ++j)
      EXPECT_LE(std::max({std::abs(ma[j].translation().x - mb[j].translation().x), std::abs(ma[j].translation().y - mb[j].translation().y),
                          std::abs(ma[j].translation().z - mb[j].translation().z)}),
                1e-9 * (1 + std::abs(ma[j].translation().x) + std::abs(ma[j].translation().y) + std::abs(ma[j].translation().z)))
          << a->skeleton.names()[j];
  }
}
#endif

}  // namespace
