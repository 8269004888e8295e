// The command-line tool, run as a user would: outputs, exit codes, error messages, safe writing.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <thread>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "dq/anim/forward_kinematics.hpp"
#include "dq/io/motion.hpp"
#ifdef DQKIT_HAVE_IMPORT
#include "dq/io/scene.hpp"
#endif
#include "cli.hpp"
#include "models.hpp"

namespace {

using namespace dq;
namespace fs = std::filesystem;
const fs::path kModels = dq::test::assimp_models();
// DQKIT_CLI_UNDER_TEST runs these tests against another build of the tool (e.g. an older one, to
// check that a test fails without its fix).
const std::string kTool = std::getenv("DQKIT_CLI_UNDER_TEST") ? std::getenv("DQKIT_CLI_UNDER_TEST") : DQKIT_CLI;

using Outcome = dq::test::CliOutcome;
using dq::test::read_file;
/// Runs the tool with these arguments (shell syntax).
Outcome run(const std::string& args) { return dq::test::run_shell(kTool + " " + args); }

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
  r = run("info /nonexistent.bvh");  // named .bvh: the BVH reader's error, with or without the importer
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("/nonexistent.bvh: cannot open for reading: No such file or directory"), std::string::npos) << r.err;
#ifdef DQKIT_HAVE_IMPORT
  r = run("info /nonexistent.gltf");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("/nonexistent.gltf: no such file"), std::string::npos) << r.err;
  // Names are printed with their control characters as '?': an escape sequence in a joint name
  // reached the terminal.
  std::ofstream(dir_ / "escape.bvh") << "HIERARCHY\nROOT a\x1b[31mred\n{\nOFFSET 0 0 0\nCHANNELS 1 Xposition\nEnd Site\n{\nOFFSET 0 1 0\n}\n}\n"
                                        "MOTION\nFrames: 1\nFrame Time: 0.1\n0\n";
  r = run("info " + (dir_ / "escape.bvh").string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("a?[31mred [Xposition]"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find('\x1b'), std::string::npos);
  // A file without animations has only animation 0, its rest pose: 7 was ignored without a word.
  const std::string still = std::string(DQKIT_ASSIMP_MODELS) + "/glTF2/BoxTextured-glTF-Binary/BoxTextured.glb";
  if (fs::exists(still)) {
    r = run("fk " + still + " --animation 7");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("animation 7 requested, the file has 0"), std::string::npos) << r.err;
    EXPECT_EQ(run("fk " + still + " --animation 0").code, 0);
  }
#endif
  // A file named .bvh that is not BVH (here empty) gets the BVH reader's error, not the importer's.
  std::ofstream(dir_ / "empty.bvh").flush();
  r = run("info " + (dir_ / "empty.bvh").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("empty.bvh:1: expected 'HIERARCHY'"), std::string::npos) << r.err;
  // A BVH file has one animation.
  r = run("info " + bvh + " --animation 1");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("animation 1 requested, a BVH file has 1"), std::string::npos) << r.err;
  // Empty file names are errors, not standard output.
  r = run("fk " + bvh + " -o ''");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("an empty file name"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
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
  EXPECT_NE(r.err.find("already exists; it is replaced only when asked (--force"), std::string::npos) << r.err;
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


// ---- hostile input, lost data, scripting (issue 9); these need no sample files -----------------

/// A fixture with its own directory and small generated captures.
class CliScript : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("dqkit_cli_script_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name, std::ios::binary) << text;
    return dir_ / name;
  }
  std::string p(const std::string& name) const { return "'" + (dir_ / name).string() + "'"; }
  bool no_temporaries() const {
    for (const auto& e : fs::directory_iterator(dir_))
      if (e.path().filename().string().find(".tmp") != std::string::npos) return false;
    return true;
  }
  fs::path dir_;
};

/// Two joints with awkward names, 5 frames at 0.1 s.
const std::string kAwkward =
    "HIERARCHY\nROOT left,arm\n{\nOFFSET 1 2 3\nCHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"
    "JOINT say \"hi\"\n{\nOFFSET 0 1 0\nCHANNELS 3 Zrotation Xrotation Yrotation\nEnd Site\n{\nOFFSET 0 1 0\n}\n}\n}\n"
    "MOTION\nFrames: 5\nFrame Time: 0.1\n"
    "0 0 0 0 0 0 0 0 0\n1 0 0 10 0 0 20 0 0\n2 0 0 20 0 0 40 0 0\n3 0 0 30 0 0 60 0 0\n4 0 0 40 0 0 80 0 0\n";

/// RFC 4180 records (CRLF between records, quoted fields may hold anything).
std::vector<std::vector<std::string>> parse_csv(const std::string& text) {
  std::vector<std::vector<std::string>> rows(1, std::vector<std::string>(1));
  bool quoted = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        rows.back().back() += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        rows.back().back() += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      rows.back().emplace_back();
    } else if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') {
      rows.emplace_back(1);
      ++i;
    } else {
      rows.back().back() += c;
    }
  }
  if (rows.back().size() == 1 && rows.back()[0].empty()) rows.pop_back();
  return rows;
}

TEST_F(CliScript, AnyNameRoundTripsThroughCsvAndJson) {
  write("a.bvh", kAwkward);
  const Outcome csv = run("fk " + p("a.bvh") + " --all --parents");
  ASSERT_EQ(csv.code, 0) << csv.err;
  const auto rows = parse_csv(csv.out);
  ASSERT_EQ(rows.size(), 1 + 5 * 3u);
  for (const auto& row : rows) EXPECT_EQ(row.size(), 11u);  // a comma in a name adds no column
  EXPECT_EQ(rows[1][1], "left,arm");
  EXPECT_EQ(rows[2][1], "say \"hi\"");
  EXPECT_EQ(rows[3][1], "say \"hi\"_End");
  EXPECT_EQ(rows[3][3], "1");  // parent index
  const Outcome json = run("fk " + p("a.bvh") + " --all --format json");
  ASSERT_EQ(json.code, 0) << json.err;
  const nlohmann::json j = nlohmann::json::parse(json.out);
  EXPECT_EQ(j["frames"][4]["joints"][0]["joint"], "left,arm");
  EXPECT_EQ(j["frames"][4]["joints"][1]["joint"], "say \"hi\"");
  EXPECT_EQ(j["frames"][4]["joints"][1]["parent"], 0);
  EXPECT_DOUBLE_EQ(j["frames"][4]["time"].get<double>(), 0.4);
}

TEST_F(CliScript, StandardInputAndOutput) {
  write("a.bvh", kAwkward);
  const Outcome from_file = run("fk " + p("a.bvh") + " --frames 2");
  const Outcome from_stdin = run("fk - --frames 2 < " + p("a.bvh"));
  ASSERT_EQ(from_stdin.code, 0) << from_stdin.err;
  EXPECT_EQ(from_stdin.out, from_file.out);
  const Outcome to_stdout = run("convert - - < " + p("a.bvh"));
  ASSERT_EQ(to_stdout.code, 0) << to_stdout.err;
  EXPECT_EQ(to_stdout.out.rfind("HIERARCHY\n", 0), 0u);
  EXPECT_TRUE(read_motion(to_stdout.out, "out"));
  const Outcome not_bvh = run("info - < /dev/null");
  EXPECT_EQ(not_bvh.code, 1);
  EXPECT_NE(not_bvh.err.find("standard input: not BVH"), std::string::npos) << not_bvh.err;
}

std::vector<std::string> frames_of(const std::string& csv) {
  std::vector<std::string> out;
  for (const auto& row : parse_csv(csv)) out.push_back(row[0]);
  return out;
}

TEST_F(CliScript, FramesTakePythonSlicesMixedWithLists) {
  write("a.bvh", kAwkward);
  const std::string hips = " --joint left,arm --frames ";
  EXPECT_EQ(frames_of(run("fk " + p("a.bvh") + hips + "0:5:2,-1").out), (std::vector<std::string>{"frame", "0", "2", "4", "4"}));
  EXPECT_EQ(frames_of(run("fk " + p("a.bvh") + hips + "::-2").out), (std::vector<std::string>{"frame", "4", "2", "0"}));
  EXPECT_EQ(frames_of(run("fk " + p("a.bvh") + hips + "3:,1").out), (std::vector<std::string>{"frame", "3", "4", "1"}));
  EXPECT_EQ(frames_of(run("fk " + p("a.bvh") + hips + "-2:100").out), (std::vector<std::string>{"frame", "3", "4"}));
  Outcome r = run("fk " + p("a.bvh") + " --frames 1:3:0");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("the step of a slice cannot be zero"), std::string::npos) << r.err;
  r = run("fk " + p("a.bvh") + " --frames ''");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("--frames: empty"), std::string::npos) << r.err;
  r = run("fk " + p("a.bvh") + " --frames 5");
  EXPECT_NE(r.err.find("frame 5 out of range (the file has 5 frames, numbered from 0)"), std::string::npos) << r.err;
}

TEST_F(CliScript, RateIsHonoured) {
  write("a.bvh", kAwkward);  // 5 frames at 10 Hz: 0.4 s
  Outcome r = run("convert " + p("a.bvh") + " " + p("b.bvh") + " --rate 25");
  ASSERT_EQ(r.code, 0) << r.err;
  const Expected<Motion> b = load_motion(dir_ / "b.bvh");
  ASSERT_TRUE(b) << b.error().message;
  EXPECT_EQ(b->animation.frame_count, 11u);
  EXPECT_DOUBLE_EQ(b->animation.frame_time, 0.04);
  r = run("fk " + p("a.bvh") + " --rate 20 --all --time --joint left,arm");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto rows = parse_csv(r.out);
  ASSERT_EQ(rows.size(), 1 + 9u);
  EXPECT_EQ(rows[0][1], "time");
  EXPECT_EQ(rows[3][1], "0.10000000000000001");
  EXPECT_DOUBLE_EQ(std::stod(rows[3][3]), 2.0);  // root x at 0.1 s (frame 1): OFFSET 1 + Xposition 1
  // A capture without frames gets the rate asked for too (it kept its own frame time, 1 s).
  write("still.bvh", "HIERARCHY\nROOT Hips\n{\nOFFSET 0 0 0\nCHANNELS 3 Zrotation Xrotation Yrotation\nEnd Site\n{\nOFFSET 0 1 0\n}\n}\n"
                     "MOTION\nFrames: 0\nFrame Time: 1\n");
  r = run("convert " + p("still.bvh") + " " + p("still10.bvh") + " --rate 10");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_DOUBLE_EQ(read_bvh_file(dir_ / "still10.bvh")->frame_time, 0.1);
  r = run("info " + p("still.bvh"));  // its MOTION section is an animation, of no frames
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("animations: 1\nframes: 0 (an empty animation: the rest pose)\n"), std::string::npos) << r.out;
  // A clip of two frames 1e-14 s apart keeps its last pose: 2 frames, the second the file's second.
  write("blink.bvh", "HIERARCHY\nROOT Hips\n{\nOFFSET 0 0 0\nCHANNELS 1 Xposition\nEnd Site\n{\nOFFSET 0 1 0\n}\n}\n"
                     "MOTION\nFrames: 2\nFrame Time: 1e-14\n0\n1\n");
  r = run("fk " + p("blink.bvh") + " --rate 30 --all --joint Hips");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto blink = parse_csv(r.out);
  ASSERT_EQ(blink.size(), 1 + 2u);
  EXPECT_EQ(blink[2][2], "1");  // x of the second frame
}

TEST_F(CliScript, LocalTransformsMatricesEulerSubsetAndScale) {
  write("a.bvh", kAwkward);
  const Expected<Motion> m = load_motion(dir_ / "a.bvh");
  ASSERT_TRUE(m);
  const DualQuaternion<double> local = m->animation.frame(3)[1];
  Outcome r = run("fk " + p("a.bvh") + " --frames 3 --space local --rotation matrix --joint 'say \"hi\"' --scale 0.5");
  ASSERT_EQ(r.code, 0) << r.err;
  auto rows = parse_csv(r.out);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0], (std::vector<std::string>{"frame", "joint", "x", "y", "z", "r00", "r01", "r02", "r10", "r11", "r12", "r20", "r21", "r22"}));
  EXPECT_DOUBLE_EQ(std::stod(rows[1][3]), 0.5 * local.translation().y);
  const Mat3<double> mat = local.real.to_matrix();
  for (int k = 0; k < 9; ++k) EXPECT_DOUBLE_EQ(std::stod(rows[1][5 + static_cast<std::size_t>(k)]), mat(k / 3, k % 3)) << k;
  r = run("fk " + p("a.bvh") + " --frames 3 --space local --rotation euler --euler-order ZXY --degrees --joint 'say \"hi\"'");
  ASSERT_EQ(r.code, 0) << r.err;
  rows = parse_csv(r.out);
  EXPECT_EQ(rows[0][5], "z1");
  EXPECT_NEAR(std::stod(rows[1][5]), 60, 1e-9);  // the file's own Zrotation of frame 3
  r = run("fk " + p("a.bvh") + " --joint nosuch");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("--joint: the file has no joint named 'nosuch'"), std::string::npos) << r.err;
}

TEST_F(CliScript, InfoAsJson) {
  write("a.bvh", kAwkward);
  const Outcome r = run("info " + p("a.bvh") + " --format json");
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["joints"], 3);
  EXPECT_EQ(j["frames"], 5);
  EXPECT_EQ(j["hierarchy"][2]["name"], "say \"hi\"_End");
  EXPECT_EQ(j["hierarchy"][2]["parent"], 1);
  EXPECT_EQ(j["hierarchy"][0]["channels"].size(), 6u);
}

TEST_F(CliScript, TheOutputsExtensionChoosesItsFormat) {
  // fk -o x.json wrote CSV into x.json; now the extension decides when --format is not given,
  // and a --format that contradicts it is refused before anything is written.
  write("a.bvh", kAwkward);
  ASSERT_EQ(run("fk " + p("a.bvh") + " --all -o " + p("all.json")).code, 0);
  std::ifstream json_file(dir_ / "all.json");
  EXPECT_EQ(nlohmann::json::parse(json_file)["frames"].size(), 5u);
  ASSERT_EQ(run("info " + p("a.bvh") + " -o " + p("info.JSON")).code, 0);
  std::ifstream info_file(dir_ / "info.JSON");
  EXPECT_EQ(nlohmann::json::parse(info_file)["joints"], 3);
  ASSERT_EQ(run("fk " + p("a.bvh") + " -o " + p("frame0.dat")).code, 0);  // another extension: the default, CSV
  std::ifstream dat(dir_ / "frame0.dat");
  std::string header;
  std::getline(dat, header);
  EXPECT_EQ(header.rfind("frame,joint,", 0), 0u) << header;
  const Outcome r = run("fk " + p("a.bvh") + " --format csv -o " + p("clash.json"));
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("--format csv, but the output " + (dir_ / "clash.json").string() + " is named as json"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "clash.json"));
}

TEST_F(CliScript, ValuesBeyondDoubleAreErrorsNotUnreadableOutput) {
  // Offsets of 1e300, finite in the file, overflow once scaled: convert and fk refuse to write ∞,
  // which neither BVH nor JSON can read back, and leave no file.
  write("big.bvh", "HIERARCHY\nROOT A\n{\nOFFSET 1e300 1e300 1e300\nCHANNELS 3 Xposition Yposition Zposition\nJOINT B\n{\n"
                   "OFFSET 1e300 1e300 1e300\nCHANNELS 0\n}\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\n1e300 1e300 1e300\n");
  Outcome r = run("convert " + p("big.bvh") + " " + p("out.bvh") + " --scale 1e12");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("big.bvh: cannot write BVH: joint 0 ('A'): the offset is not finite (after --scale)"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "out.bvh"));
  r = run("fk " + p("big.bvh") + " --scale 1e12 --format json -o " + p("out.json"));
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("big.bvh: frame 0, joint 'A': the transform is not finite (its lengths times --scale overflow a double)"),
            std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "out.json"));
  EXPECT_TRUE(no_temporaries());
  // A denormal frame time is a valid file whose rate is beyond double: JSON says null.
  write("fast.bvh", "HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 1 Xrotation\n}\nMOTION\nFrames: 2\nFrame Time: 5e-324\n0\n1\n");
  r = run("info " + p("fast.bvh") + " --format json");
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["rate"].is_null());
  EXPECT_EQ(j["frame_time"].get<double>(), 5e-324);
}

TEST_F(CliScript, EveryMisuseGetsAClearMessage) {
  write("a.bvh", kAwkward);
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"info " + dir_.string(), ": is a directory"},
      {"info /dev/zero", "/dev/zero: is not a regular file"},
      {"fk " + p("a.bvh") + " -o /dev/null", "/dev/null: is not a regular file (a symbolic link, device, FIFO or socket): dqkit writes only regular files"},
      {"fk ''", "an empty file name"},
      {"fk " + p("a.bvh") + " --degrees", "--degrees applies to Euler angles: add --rotation euler"},
      {"fk " + p("a.bvh") + " --euler-order XYZ", "--euler-order applies to Euler angles: add --rotation euler"},
      {"fk " + p("a.bvh") + " --joint left,arm --joint left,arm", "--joint: 'left,arm' is given twice"},
      {"frobnicate x", "unknown command 'frobnicate' (commands: info, fk, convert"},
      {"fk " + p("a.bvh") + " --rate nan", "--rate: 'nan' is not a finite number"},
      {"fk " + p("a.bvh") + " --import-timeout nan", "--import-timeout: 'nan' is not a finite number"},
      {"fk " + p("a.bvh") + " --animation -1", "'-1' is not an animation number"},
      {"fk " + p("a.bvh") + " --scale 0", "--scale: '0' is out of range"},
      {"convert " + p("a.bvh") + " " + p("b.bvh") + " --rotation-order XYX", "--rotation-order"},
  };
  for (const auto& [args, expected] : cases) {
    const Outcome r = run(args);
    EXPECT_NE(r.code, 0) << args;
    EXPECT_NE(r.err.find(expected), std::string::npos) << args << "\ngot: " << r.err;
  }
}

TEST_F(CliScript, OutputsNeverReplaceWhatTheyShouldNot) {
  const std::string original = kAwkward;
  write("in.bvh", original);
  // The input, also through a hard link or a symbolic link, for every command.
  fs::create_hard_link(dir_ / "in.bvh", dir_ / "hard.csv");
  fs::create_symlink(dir_ / "in.bvh", dir_ / "soft.csv");
  for (const char* out : {"in.bvh", "hard.csv", "soft.csv"}) {
    for (const std::string& cmd : {"fk " + p("in.bvh") + " -o " + p(out), "info " + p("in.bvh") + " -o " + p(out)}) {
      const Outcome r = run(cmd + " --force");
      EXPECT_EQ(r.code, 1) << cmd;
      EXPECT_NE(r.err.find("is the input file"), std::string::npos) << cmd << ": " << r.err;
    }
  }
  const Outcome c = run("convert " + p("in.bvh") + " " + p("in.bvh") + " --force");
  EXPECT_NE(c.err.find("is the input file"), std::string::npos) << c.err;
  EXPECT_EQ(read_file(dir_ / "in.bvh"), original);
  // --force replaces regular files only: not a FIFO, not a symbolic link.
  ASSERT_EQ(::mkfifo((dir_ / "fifo.csv").c_str(), 0600), 0);
  Outcome r = run("fk " + p("in.bvh") + " -o " + p("fifo.csv") + " --force");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("is not a regular file"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_fifo(dir_ / "fifo.csv"));
  write("target.csv", "keep");
  fs::create_symlink(dir_ / "target.csv", dir_ / "link.csv");
  r = run("fk " + p("in.bvh") + " -o " + p("link.csv") + " --force");
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(fs::is_symlink(dir_ / "link.csv"));
  EXPECT_EQ(read_file(dir_ / "target.csv"), "keep");
  // Permissions of a replaced file are kept.
  ::chmod((dir_ / "target.csv").c_str(), 0604);
  r = run("fk " + p("in.bvh") + " -o " + p("target.csv") + " --force");
  ASSERT_EQ(r.code, 0) << r.err;
  struct stat st {};
  ::stat((dir_ / "target.csv").c_str(), &st);
  EXPECT_EQ(st.st_mode & 07777, 0604u);
  // Write errors are errors.
  r = run("fk " + p("in.bvh") + " --all > /dev/full");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("standard output: write failed: No space left on device"), std::string::npos) << r.err;
  EXPECT_TRUE(no_temporaries());
}

/// A capture of `frames` frames of `joints` chained joints (3 rotation channels each).
std::string generated_capture(std::size_t joints, std::size_t frames) {
  std::string t = "HIERARCHY\nROOT j0\n{\nOFFSET 0 0 0\nCHANNELS 3 Zrotation Xrotation Yrotation\n";
  for (std::size_t j = 1; j < joints; ++j) t += "JOINT j" + std::to_string(j) + "\n{\nOFFSET 0 1 0\nCHANNELS 3 Zrotation Xrotation Yrotation\n";
  for (std::size_t j = 0; j < joints; ++j) t += "}\n";
  t += "MOTION\nFrames: " + std::to_string(frames) + "\nFrame Time: 0.01\n";
  std::string line;
  for (std::size_t c = 0; c < 3 * joints; ++c) line += c ? " 1.5" : "1.5";
  line += '\n';
  for (std::size_t f = 0; f < frames; ++f) t += line;
  return t;
}

TEST_F(CliScript, ASignalLeavesNoTemporaryFileAndRacingWritersDoNotReplaceEachOther) {
  write("big.bvh", generated_capture(50, 20000));  // a million CSV rows: long enough to interrupt
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const std::string in = (dir_ / "big.bvh").string(), out = (dir_ / "out.csv").string();
    ::signal(SIGINT, SIG_DFL);  // as in a terminal (a shell's background job would ignore it)
    ::execl(kTool.c_str(), kTool.c_str(), "fk", in.c_str(), "--all", "-o", out.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  for (int i = 0; i < 20000 && !dq::test::writes_output_in(child, dir_); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  ASSERT_TRUE(dq::test::writes_output_in(child, dir_)) << "the tool never started writing";
  ::kill(child, SIGINT);
  int status = 0;
  ::waitpid(child, &status, 0);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGINT);
  EXPECT_TRUE(no_temporaries());
  EXPECT_FALSE(fs::exists(dir_ / "out.csv"));
  // SIGKILL runs no handler: the output, an anonymous file until complete (O_TMPFILE), leaves nothing.
  if (dq::test::has_anonymous_files(dir_)) {
    const pid_t killed = ::fork();
    ASSERT_GE(killed, 0);
    if (killed == 0) {
      const std::string in = (dir_ / "big.bvh").string(), out = (dir_ / "out.csv").string();
      ::execl(kTool.c_str(), kTool.c_str(), "fk", in.c_str(), "--all", "-o", out.c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
    for (int i = 0; i < 20000 && !dq::test::writes_output_in(killed, dir_); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    ASSERT_TRUE(dq::test::writes_output_in(killed, dir_)) << "the tool never started writing";
    ::kill(killed, SIGKILL);
    ::waitpid(killed, &status, 0);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
    std::size_t entries = 0;
    for (const auto& e : fs::directory_iterator(dir_)) entries += e.path().filename() != "big.bvh";
    EXPECT_EQ(entries, 0u) << "something was left behind";
  }
  // Two writers to one new path without --force: one wins, the other is told, nothing is mixed.
  write("small.bvh", generated_capture(5, 2000));
  const Outcome both = dq::test::run_shell(kTool + " fk " + p("small.bvh") + " --all -o " + p("race.csv") + " & " + kTool + " fk " + p("small.bvh") +
                             " --all -o " + p("race.csv") + "; wait");
  EXPECT_NE(both.err.find("race.csv: already exists; it is replaced only when asked (--force on the command line, overwrite=True in Python, Overwrite::allow in C++)"), std::string::npos) << both.err;
  const Outcome reference = run("fk " + p("small.bvh") + " --all");
  EXPECT_EQ(read_file(dir_ / "race.csv"), reference.out);
  EXPECT_TRUE(no_temporaries());
}

TEST_F(CliScript, ProgressIsShownOnlyOnATerminal) {
  write("big.bvh", generated_capture(50, 4000));
  const Outcome r = run("fk " + p("big.bvh") + " --all -o " + p("out.csv"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err, "");  // standard error is a file here: no progress lines in it
}

TEST_F(CliScript, CostsAreLinearInDepth) {
  // A 20000-joint chain: info and convert used to indent per level (depth² output).
  write("chain.bvh", generated_capture(20000, 2));
  const auto start = std::chrono::steady_clock::now();
  Outcome r = run("info " + p("chain.bvh") + " -o " + p("info.txt"));
  ASSERT_EQ(r.code, 0) << r.err;
  r = run("convert " + p("chain.bvh") + " " + p("out.bvh") + " --rotation-order XYZ");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_LT(fs::file_size(dir_ / "info.txt"), 200u * 20000);
  EXPECT_LT(fs::file_size(dir_ / "out.bvh"), 4 * fs::file_size(dir_ / "chain.bvh") + 32u * 8 * 20000);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(20));
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
