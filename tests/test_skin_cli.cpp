// dqkit skin and dqkit render, run as a user runs them: outputs, files, sequences, errors.
#include <gtest/gtest.h>
#include <stb_image.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "cli.hpp"
#include "models.hpp"

namespace {

namespace fs = std::filesystem;

using Outcome = dq::test::CliOutcome;

/// Runs the tool (shell syntax).
Outcome run(const std::string& args) { return dq::test::run_shell(std::string(DQKIT_CLI) + " " + args); }

class SkinCli : public ::testing::Test {
 protected:
  void SetUp() override {
    DQKIT_REQUIRE_MODELS();
    dir_ = fs::temp_directory_path() / ("dqkit_skin_cli_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  std::string model(const char* relative) const { return "'" + (dq::test::assimp_models() / relative).string() + "'"; }
  fs::path dir_;
};

TEST_F(SkinCli, CsvOfSimpleSkin) {
  const Outcome r = run("skin " + model("glTF2/simple_skin/simple_skin.gltf") + " --time 1 --method lbs");
  ASSERT_EQ(r.code, 0) << r.err;
  // Ten vertices; vertex 0, (0, 0, 0) in the file, is bound to joint 0 only, which stays at its
  // bind offset: inverse bind translate(−0.5, −1, 0) after joint translate(0, 1, 0).
  EXPECT_EQ(r.out.substr(0, r.out.find('\n')), "vertex,x,y,z\r");
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 11);
  EXPECT_NE(r.out.find("\n0,-0.5,0,0\r\n"), std::string::npos) << r.out;
}

TEST_F(SkinCli, FilesAreNotReplacedWithoutForce) {
  const std::string out = (dir_ / "frame.obj").string();
  ASSERT_EQ(run("skin " + model("X/Testwuson.X") + " --format obj -o " + out).code, 0);
  ASSERT_TRUE(fs::exists(out));
  const Outcome again = run("skin " + model("X/Testwuson.X") + " --format obj -o " + out);
  EXPECT_EQ(again.code, 1);
  EXPECT_NE(again.err.find("frame.obj"), std::string::npos) << again.err;
  EXPECT_EQ(run("skin " + model("X/Testwuson.X") + " --method lbs -o " + out + " --force").code, 0);
  // A format that contradicts the name is refused (it wrote PLY into frame.obj).
  EXPECT_EQ(run("skin " + model("X/Testwuson.X") + " --format ply -o " + out + " --force").code, 1);
}

TEST_F(SkinCli, RenderAllThreeSideBySide) {
  const std::string out = (dir_ / "all.png").string();
  const Outcome r = run("render " + model("X/BCN_Epileptic.X") + " --time 1 --method all --width 300 --height 120 --out " + out);
  ASSERT_EQ(r.code, 0) << r.err;
  int w = 0, h = 0, n = 0;
  unsigned char* data = stbi_load(out.c_str(), &w, &h, &n, 4);
  ASSERT_NE(data, nullptr);
  EXPECT_EQ(w, 300);
  EXPECT_EQ(h, 120);
  // Each third shows the character: pixels other than the white background, mostly of its colour
  // (LBS red, DQS blue, CoR green dominate their thirds).
  for (int third = 0; third < 3; ++third) {
    long covered = 0, r_sum = 0, g_sum = 0, b_sum = 0;
    for (int y = 0; y < h; ++y)
      for (int x = third * 100; x < third * 100 + 100; ++x) {
        const unsigned char* p = data + 4 * (y * w + x);
        if (p[0] == 255 && p[1] == 255 && p[2] == 255) continue;
        ++covered, r_sum += p[0], g_sum += p[1], b_sum += p[2];
      }
    EXPECT_GT(covered, 100) << "third " << third;
    const long channel[3] = {r_sum, g_sum, b_sum};
    EXPECT_EQ(std::max_element(channel, channel + 3) - channel, third == 0 ? 0 : third == 1 ? 2 : 1) << "third " << third;
  }
  // Each third is captioned with its method's name at its top left: dark strokes there, as in
  // no picture of one method alone.
  const auto dark_top_left = [](const unsigned char* pixels, int width, int x0) {
    int dark = 0;
    for (int y = 0; y < 30; ++y)
      for (int x = x0; x < x0 + 50; ++x) {
        const unsigned char* p = pixels + 4 * (y * width + x);
        dark += std::max({p[0], p[1], p[2]}) < 160;
      }
    return dark;
  };
  for (int third = 0; third < 3; ++third) EXPECT_GT(dark_top_left(data, w, third * 100), 20) << "third " << third << " has no caption";
  stbi_image_free(data);
  const std::string one = (dir_ / "one.png").string();
  ASSERT_EQ(run("render " + model("X/BCN_Epileptic.X") + " --time 1 --method dqs --width 100 --height 120 --out " + one).code, 0);
  data = stbi_load(one.c_str(), &w, &h, &n, 4);
  ASSERT_NE(data, nullptr);
  EXPECT_EQ(dark_top_left(data, w, 0), 0);
  stbi_image_free(data);
}

TEST_F(SkinCli, RenderSequenceIsNumbered) {
  const std::string out = (dir_ / "seq.png").string();
  const Outcome r = run("render " + model("Collada/box_nested_animation.dae") + " --method dqs --time 0 --until 0.2 --fps 10 --width 64 --height 48 --out " + out);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "seq_0000.png"));
  EXPECT_TRUE(fs::exists(dir_ / "seq_0002.png"));
  EXPECT_FALSE(fs::exists(dir_ / "seq_0003.png"));
  EXPECT_FALSE(fs::exists(dir_ / "seq.png"));
}

TEST_F(SkinCli, RenderSequenceStopsAtTheClipsEnd) {
  // BCN_Epileptic.X's clip ends at 3.3 s: frames after it would all show its last pose.
  const std::string out = (dir_ / "end.png").string();
  const Outcome r = run("render " + model("X/BCN_Epileptic.X") + " --time 3 --until 5 --fps 10 --width 32 --height 32 --out " + out);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("--until: the clip ends at 3.3 s; the sequence stops there (4 of 21 frames)"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "end_0003.png"));
  EXPECT_FALSE(fs::exists(dir_ / "end_0004.png"));
  // With --until the names are numbered even when one frame remains (a script knows them).
  const std::string one = (dir_ / "one.png").string();
  ASSERT_EQ(run("render " + model("X/BCN_Epileptic.X") + " --time 1 --until 1 --width 32 --height 32 --out " + one).code, 0);
  EXPECT_TRUE(fs::exists(dir_ / "one_0000.png"));
  EXPECT_FALSE(fs::exists(dir_ / "one.png"));
  // A directory in the way is named as one, with or without --force.
  fs::create_directory(dir_ / "dir.png");
  for (const char* force : {"", " --force"}) {
    const Outcome d = run("render " + model("X/BCN_Epileptic.X") + " --width 32 --height 32 --out " + (dir_ / "dir.png").string() + force);
    EXPECT_EQ(d.code, 1);
    EXPECT_NE(d.err.find("dir.png: is a directory"), std::string::npos) << d.err;
  }
}

TEST_F(SkinCli, InfoOfAModelWithoutAnimationSaysSo) {
  const Outcome r = run("info " + model("OBJ/box.obj"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("frames: 0 (no animation: the rest pose)"), std::string::npos) << r.out;  // not a 30 Hz rate of nothing
}

TEST_F(SkinCli, LightsAndCamerasAreJointsOnlyWhenAsked) {
  const auto joints = [](const std::string& info) { return std::stoul(info.substr(info.find("joints: ") + 8)); };
  const Outcome left_out = run("info " + model("FBX/huesitos.fbx"));
  ASSERT_EQ(left_out.code, 0) << left_out.err;
  EXPECT_NE(left_out.err.find("light 'Lamp' is not a joint; left out (the option lights_and_cameras, dqkit's --lights-and-cameras, keeps it)"),
            std::string::npos) << left_out.err;
  const Outcome kept = run("info " + model("FBX/huesitos.fbx") + " --lights-and-cameras");
  ASSERT_EQ(kept.code, 0) << kept.err;
  EXPECT_EQ(kept.err.find("is not a joint"), std::string::npos) << kept.err;
  EXPECT_EQ(joints(kept.out), joints(left_out.out) + 2);  // the lamp and the camera
  const Outcome skinned = run("skin " + model("X/Testwuson.X") + " --lights-and-cameras --format csv -o " + (dir_ / "w.csv").string());
  EXPECT_EQ(skinned.code, 0) << skinned.err;
}

TEST_F(SkinCli, ErrorsSayWhat) {
  Outcome r = run("render " + model("X/Testwuson.X") + " --out " + (dir_ / "x.jpg").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("--out must name a .png file"), std::string::npos) << r.err;
  r = run("render " + model("X/Testwuson.X") + " --out " + (dir_ / ".png").string());  // no name before the extension
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("--out must name a .png file"), std::string::npos) << r.err;
  r = run("render " + model("X/Testwuson.X") + " --width 16 --height 16 --out " + (dir_ / "upper.PNG").string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "upper.PNG"));
  r = run("skin " + model("X/Testwuson.X") + " --animation 7");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("animation 7 requested, the file has 3"), std::string::npos) << r.err;
  // --camera: two or three finite numbers and nothing else (sscanf let '10,20,' and '10,20,5,' through);
  // a pitch beyond the orbit camera's ±86° was clamped silently.
  for (const auto& [camera, message] : {std::pair{"10", "--camera must be"}, std::pair{"10,20,", "--camera must be"},
                                        std::pair{"10,,20", "--camera must be"}, std::pair{"10,20,5,1", "--camera must be"},
                                        std::pair{"10,20x", "--camera must be"}, std::pair{"nan,20", "--camera must be"},
                                        std::pair{"10,90", "the pitch 90° is beyond ±85.94°"},
                                        std::pair{"10,20,-1", "the distance -1 is negative"},
                                        std::pair{"10,20,1e308", "the model would be smaller than a pixel"}}) {
    r = run("render " + model("X/Testwuson.X") + " --camera=" + camera + " --out " + (dir_ / "y.png").string());
    EXPECT_EQ(r.code, 1) << camera;
    EXPECT_NE(r.err.find(message), std::string::npos) << camera << ": " << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "y.png")) << camera;
  }
  r = run("render " + model("X/Testwuson.X") + " --window");  // CTest runs without a display
  if (!std::getenv("DISPLAY") && !std::getenv("WAYLAND_DISPLAY")) {
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("no window"), std::string::npos) << r.err;
  }
  // The output's extension chooses the format (out.obj held CSV).
  r = run("skin " + model("X/Testwuson.X") + " -o " + (dir_ / "frame.obj").string());
  ASSERT_EQ(r.code, 0) << r.err;
  std::ifstream obj(dir_ / "frame.obj");
  std::string first;
  std::getline(obj, first);
  EXPECT_EQ(first, "# dqkit skinned frame");
  r = run("skin -");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("standard input is not supported"), std::string::npos) << r.err;
  r = run("skin " + (dir_ / "missing.gltf").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("missing.gltf"), std::string::npos) << r.err;
  r = run("skin " + model("BVH/01_01.bvh"));  // Assimp's bone-drawing mesh is not a skin
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("01_01.bvh: a BVH capture has no mesh to skin"), std::string::npos) << r.err;
  r = run("render " + model("X/Testwuson.X") + " --time 2 --until 1 --out " + (dir_ / "z.png").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("--until (1 s) is before --time (2 s)"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "z.png"));
  r = run("render " + model("X/Testwuson.X") + " --fps 10 --out " + (dir_ / "f.png").string());  // one picture: --fps would be ignored
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("--fps requires --until"), std::string::npos) << r.err;
  r = run("render " + model("X/Testwuson.X") + " --window --out " + (dir_ / "w.png").string());
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("--out excludes --window"), std::string::npos) << r.err;
  r = run("skin " + model("X/Testwuson.X") + " --import-timeout 0");  // the same validators as the other commands
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("--import-timeout: '0' is out of range (0, 86400]"), std::string::npos) << r.err;
}

}  // namespace
