// Hostile input and safe output in the library (dqkit::io): bounded time and memory on whatever a
// file declares, clear errors for what is not a regular file, names that round-trip, and writers
// that never corrupt or replace what they should not. The CLI's side is in test_cli.cpp.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <thread>
#include <vector>

#include "dq/io/bvh.hpp"
#include "dq/io/file.hpp"
#include "cli.hpp"
#include "dq/io/motion.hpp"
#include "dq/util/assert.hpp"

namespace {

using namespace dq;
namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

class HostileIo : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("dqkit_hostile_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  bool no_temporaries() const {
    for (const auto& e : fs::directory_iterator(dir_))
      if (e.path().filename().string().find(".tmp") != std::string::npos) return false;
    return true;
  }
  fs::path dir_;
};

const std::string kOneJoint = "HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 1 Xrotation\n}\nMOTION\n";

TEST(Hostile, DeclaredCountsDoNotAllocate) {
  // 60 million declared frames of a channel-less skeleton: the text holds nothing, the reader
  // keeps nothing, and load's memory budget refuses the animation before allocating it.
  const std::string no_channels = "HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 0\nEnd Site\n{\nOFFSET 0 1 0\n}\n}\nMOTION\nFrames: 60000000\nFrame Time: 0.1\n";
  const Expected<BvhFile> b = read_bvh(no_channels, "empty");
  ASSERT_TRUE(b) << b.error().message;
  EXPECT_LE(b->motion.capacity(), no_channels.size());
  MotionOptions small;
  small.memory_limit_mb = 100;
  const Expected<Motion> m = read_motion(no_channels, "empty", small);
  ASSERT_FALSE(m);
  EXPECT_NE(m.error().message.find("empty: 60000000 frames of 2 joints need 7324 MB, more than the 100 MB allowed"), std::string::npos)
      << m.error().message;
  // A declared count much larger than the text: the reservation follows the text.
  const Expected<BvhFile> c = read_bvh(kOneJoint + "Frames: 60000000\nFrame Time: 0.1\n1\n", "short");
  ASSERT_FALSE(c);
  EXPECT_NE(c.error().message.find("short:11: expected 60000000 frames, found 1"), std::string::npos) << c.error().message;
}

TEST(Hostile, HugeLinesAreNotTokenizedWhole) {
  // A frame line of 5 million values where one is expected: an error that counts them, without
  // storing them (the old reader built a vector of every token first).
  std::string text = kOneJoint + "Frames: 1\nFrame Time: 0.1\n";
  text.reserve(text.size() + 10'000'000);
  for (int i = 0; i < 5'000'000; ++i) text += "1 ";
  const Expected<BvhFile> b = read_bvh(text, "wide");
  ASSERT_FALSE(b);
  EXPECT_NE(b.error().message.find("wide:10: frame 0 has 5000000 values, expected 1"), std::string::npos) << b.error().message;
  // A name longer than the limit.
  const Expected<BvhFile> n = read_bvh("HIERARCHY\nROOT " + std::string(5000, 'x') + "\n", "long");
  ASSERT_FALSE(n);
  EXPECT_NE(n.error().message.find("long:2: a joint name longer than 1024 bytes"), std::string::npos) << n.error().message;
}

TEST(Hostile, JointNamesAreUtf8) {
  const Expected<BvhFile> latin1 = read_bvh("HIERARCHY\nROOT H\xfc""fte\n{\nOFFSET 0 0 0\nCHANNELS 0\n}\nMOTION\nFrames: 0\nFrame Time: 1\n", "l1");
  ASSERT_FALSE(latin1);
  EXPECT_NE(latin1.error().message.find("l1:2: a joint name must be UTF-8 text"), std::string::npos);
  const Expected<BvhFile> utf8 = read_bvh("HIERARCHY\nROOT H\xc3\xbc""fte\n{\nOFFSET 0 0 0\nCHANNELS 0\n}\nMOTION\nFrames: 0\nFrame Time: 1\n", "u");
  ASSERT_TRUE(utf8) << utf8.error().message;
  EXPECT_EQ(utf8->joints[0].name, "H\xc3\xbc""fte");
}

TEST(Hostile, EndSiteNamesNeverCollide) {
  // A joint named Chest_End beside Chest's End Site (and one named Chest_End_2 too).
  const std::string text =
      "HIERARCHY\nROOT Chest\n{\nOFFSET 0 0 0\nCHANNELS 0\nJOINT Chest_End\n{\nOFFSET 0 1 0\nCHANNELS 0\nEnd Site\n{\nOFFSET 0 1 0\n}\n}\n"
      "JOINT Chest_End_2\n{\nOFFSET 1 0 0\nCHANNELS 0\nEnd Site\n{\nOFFSET 0 1 0\n}\n}\nEnd Site\n{\nOFFSET 0 0 1\n}\n}\nMOTION\nFrames: 0\nFrame Time: 1\n";
  const Expected<BvhFile> b = read_bvh(text, "collide");
  ASSERT_TRUE(b) << b.error().message;
  std::vector<std::string> names;
  for (const BvhJoint& j : b->joints) names.push_back(j.name);
  EXPECT_EQ(names, (std::vector<std::string>{"Chest", "Chest_End", "Chest_End_End", "Chest_End_2", "Chest_End_2_End", "Chest_End_3"}));
  const Expected<Skeleton> s = bvh_skeleton(*b);
  EXPECT_TRUE(s) << s.error().message;  // unique names: a valid file
}

TEST_F(HostileIo, OnlyRegularFilesAreRead) {
  const Expected<BvhFile> d = read_bvh_file(dir_);
  ASSERT_FALSE(d);
  EXPECT_NE(d.error().message.find(": is a directory"), std::string::npos) << d.error().message;
  const Expected<BvhFile> z = read_bvh_file("/dev/zero");
  ASSERT_FALSE(z);
  EXPECT_EQ(z.error().message, "/dev/zero: is not a regular file (a device, FIFO or socket)");
  // A FIFO nobody writes to: refused at once, not waited on.
  const fs::path fifo = dir_ / "fifo.bvh";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const auto start = std::chrono::steady_clock::now();
  const Expected<BvhFile> f = read_bvh_file(fifo);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
  ASSERT_FALSE(f);
  EXPECT_NE(f.error().message.find("is not a regular file"), std::string::npos);
  EXPECT_FALSE(load_motion(fifo));
  // A sparse 8 GB file: refused from its size, nothing read.
  const fs::path sparse = dir_ / "sparse.bvh";
  { std::ofstream(sparse) << "HIERARCHY\n"; }
  fs::resize_file(sparse, std::uintmax_t{8} << 30);
  const Expected<BvhFile> s = read_bvh_file(sparse);
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().message.find("8589934592 bytes, more than the 1073741824 a BVH file may have"), std::string::npos) << s.error().message;
}

TEST_F(HostileIo, BvhIsRecognizedByContent) {
  const fs::path named_txt = dir_ / "capture.txt";
  std::ofstream(named_txt) << "\xEF\xBB\xBF  hierarchy\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 0\n}\nMOTION\nFrames: 0\nFrame Time: 1\n";
  EXPECT_TRUE(is_bvh_file(named_txt));
  EXPECT_TRUE(load_motion(named_txt));
  const fs::path fake = dir_ / "model.bvh";
  std::ofstream(fake) << "{\"asset\": {}}";
  EXPECT_FALSE(is_bvh_file(fake));
  const Expected<Motion> m = load_motion(fake);  // named .bvh: the BVH reader says what is wrong
  ASSERT_FALSE(m);
  EXPECT_NE(m.error().message.find("model.bvh:1: expected 'HIERARCHY'"), std::string::npos) << m.error().message;
  const fs::path other = dir_ / "model.gltf";
  std::ofstream(other) << "{\"asset\": {}}";
  const Expected<Motion> o = load_motion(other);
  ASSERT_FALSE(o);
  EXPECT_NE(o.error().message.find("not a BVH file"), std::string::npos) << o.error().message;
}

TEST(Hostile, WrittenTextIsLinearInDepth) {
  // A chain of 20000 joints: with one tab per level the text would be 200 million tabs.
  std::string text = "HIERARCHY\nROOT j0\n{\nOFFSET 0 0 0\nCHANNELS 0\n";
  for (int i = 1; i < 20000; ++i) text += "JOINT j" + std::to_string(i) + "\n{\nOFFSET 0 0 1\nCHANNELS 0\n";
  for (int i = 0; i < 20000; ++i) text += "}\n";
  text += "MOTION\nFrames: 0\nFrame Time: 1\n";
  const Expected<BvhFile> b = read_bvh(text, "chain");
  ASSERT_TRUE(b) << b.error().message;
  const std::string written = write_bvh(*b).value();
  EXPECT_LT(written.size(), 3 * text.size() + 32 * 6 * 20000);
  const Expected<BvhFile> again = read_bvh(written, "again");
  ASSERT_TRUE(again) << again.error().message;
  EXPECT_EQ(write_bvh(*again).value(), written);
}

TEST(Hostile, TheWriterRefusesWhatWouldNotReadBack) {
  const Expected<BvhFile> good = read_bvh(
      "HIERARCHY\nROOT hip\n{\nOFFSET 0 0 0\nCHANNELS 3 Xposition Yposition Zrotation\nJOINT knee\n{\nOFFSET 0 -1 0\n"
      "CHANNELS 1 Xrotation\nEnd Site\n{\nOFFSET 0 -1 0\n}\n}\n}\nMOTION\nFrames: 2\nFrame Time: 0.5\n1 2 3 4\n5 6 7 8\n",
      "good");
  ASSERT_TRUE(good) << good.error().message;
  ASSERT_TRUE(check_writable(*good));
  const auto refusal = [&](auto&& damage) {
    BvhFile b = *good;
    damage(b);
    bool sink_called = false;
    const Status s = write_bvh(b, [&](std::string_view) { sink_called = true; });
    EXPECT_FALSE(sink_called) << "nothing is written before the check";
    EXPECT_FALSE(write_bvh(b).has_value());
    return s ? std::string("(written)") : s.error().message;
  };
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(refusal([&](BvhFile& b) { b.motion[7] = nan; }), "cannot write BVH: frame 1, joint 1 ('knee') Xrotation: the value is not finite");
  EXPECT_EQ(refusal([&](BvhFile& b) { b.motion[2] = -inf; }), "cannot write BVH: frame 0, joint 0 ('hip') Zrotation: the value is not finite");
  EXPECT_EQ(refusal([&](BvhFile& b) { b.joints[1].offset.y = inf; }), "cannot write BVH: joint 1 ('knee'): the offset is not finite");
  EXPECT_EQ(refusal([&](BvhFile& b) { b.frame_time = 0; }), "cannot write BVH: the frame time must be finite and positive");
  EXPECT_EQ(refusal([&](BvhFile& b) { b.motion.pop_back(); }), "cannot write BVH: 7 motion values for 2 frames of 4 channels");
  EXPECT_EQ(refusal([&](BvhFile& b) { b.joints[1].name = "kn{ee"; }),
            "cannot write BVH: joint 1 ('kn{ee'): the name would not read back (empty, not UTF-8, braces, line breaks or runs of spaces)");
  EXPECT_NE(refusal([&](BvhFile& b) { b.joints[0].name = "two  spaces"; }).find("would not read back"), std::string::npos);
  EXPECT_NE(refusal([&](BvhFile& b) { b.joints[1].parent = 1; }).find("joint 1 ('knee'): its parent must come before it"), std::string::npos);
  EXPECT_NE(refusal([&](BvhFile& b) { b.joints[2].channels.push_back(BvhChannel::Xrotation); }).find("an End Site has no channels"), std::string::npos);
  EXPECT_NE(refusal([&](BvhFile& b) { b.joints[1].channels = {BvhChannel::Xrotation, BvhChannel::Xrotation}; }).find(
                "joint 1 ('knee'): channel Xrotation repeated"),
            std::string::npos);
  // Parents before children, but not depth first: hip, knee (hip), toe (hip), End Site (knee).
  // The writer would close knee's block before toe and could not reopen it for the End Site.
  EXPECT_NE(refusal([&](BvhFile& b) {
              b.joints[2].end_site = false;
              b.joints[2].name = "toe";
              b.joints[2].parent = 0;
              b.joints.push_back({"knee_End", 1, {0, -1, 0}, {}, true, 4});
            }).find("joint 3 ('knee_End'): the joints are not in depth-first order"),
            std::string::npos);
  // Names with single inner spaces read back as they were.
  BvhFile spaced = *good;
  spaced.joints[1].name = "left knee";
  const Expected<BvhFile> back = read_bvh(write_bvh(spaced).value(), "spaced");
  ASSERT_TRUE(back) << back.error().message;
  EXPECT_EQ(back->joints[1].name, "left knee");
}

TEST(Hostile, ConvertersWriteOnlyWhatReadsBack) {
  // A static rig (no animation) with rest rotations: written with its rest pose as one frame.
  RawSkeleton raw;
  const auto turn = Quaternion<double>::from_axis_angle({0, 0, 1}, 0.5);
  raw.add("root", -1, DualQuaternion<double>::from_rotation_translation(turn, {1, 2, 3}));
  raw.add("left arm", 0, DualQuaternion<double>::from_rotation_translation(turn, {0, 1, 0}));
  raw.add("left_arm", 0, DualQuaternion<double>::from_translation({0, 2, 0}));  // collides once spaces become '_'
  const Expected<Skeleton> s = build_skeleton(raw);
  ASSERT_TRUE(s);
  const Expected<BvhFile> b = to_bvh(*s, Animation{}, EulerOrder::ZXY);
  ASSERT_TRUE(b) << b.error().message;
  EXPECT_EQ(b->frame_count, 1u);
  const Expected<Motion> back = read_motion(write_bvh(*b).value(), "rig");
  ASSERT_TRUE(back) << back.error().message;
  ASSERT_EQ(back->animation.frame_count, 1u);
  for (std::size_t j = 0; j < 3; ++j)
    EXPECT_TRUE(approx_equal(back->animation.frame(0)[j], s->rest_pose()[j], 1e-12, SignPolicy::same_rotation)) << j;
  EXPECT_EQ(back->skeleton.names()[1], "left_arm_2");
  // Orders that repeat an axis cannot be BVH channels: an error, not an unreadable file.
  const Expected<BvhFile> zxz = to_bvh(*s, Animation{}, EulerOrder::ZXZ);
  ASSERT_FALSE(zxz);
  EXPECT_NE(zxz.error().message.find("ZXZ repeats an axis"), std::string::npos) << zxz.error().message;
  EXPECT_FALSE(with_rotation_order(*b, EulerOrder::XYX));
  // Another character's animation: an error, where the writer read past the animation's joints.
  Animation two_joints;
  two_joints.frame_count = 2, two_joints.joint_count = 2, two_joints.frame_time = 0.1;
  two_joints.locals.assign(4, DualQuaternion<double>{});
  const Expected<BvhFile> mismatch = to_bvh(*s, two_joints, EulerOrder::ZXY);
  ASSERT_FALSE(mismatch);
  EXPECT_EQ(mismatch.error().message, "the animation has 2 joints (4 transforms), the skeleton 3: they are not one character's");
  // bvh_animation needs the file's own skeleton, and bvh_local_transform a joint and frame of it.
  EXPECT_TRUE(is_skeleton_of(*bvh_skeleton(*b), *b));
  EXPECT_FALSE(is_skeleton_of(*s, *b));  // the same joints under other names ("left arm" became "left_arm_2")
  int violations = 0;
  static int* counter = nullptr;
  counter = &violations;
  const PreconditionHandler previous = set_precondition_handler([](const PreconditionViolation&) { ++*counter; });
  EXPECT_EQ(bvh_animation(*b, *s).frame_count, 0u);
  EXPECT_EQ(bvh_local_transform(*b, 3, 0), DualQuaternion<double>{});
  EXPECT_EQ(bvh_local_transform(*b, 0, 1), DualQuaternion<double>{});
  set_precondition_handler(previous);
  EXPECT_EQ(violations, 3);
}

TEST(Hostile, ResamplingEndsOnTheLastKey) {
  EXPECT_EQ(resampled_frame_count(1.0, 30), 31u);
  EXPECT_EQ(resampled_frame_count(1.03, 30), 32u);  // the old floor gave 31 and lost the end
  EXPECT_EQ(resampled_frame_count(0, 30), 1u);
  EXPECT_EQ(resampled_frame_count(1e-14, 30), 2u);  // any positive length keeps its last pose
  // Counts beyond any memory saturate instead of wrapping (a cast of 2^64 or more is undefined).
  EXPECT_EQ(resampled_frame_count(1e13, 1e7), std::numeric_limits<std::size_t>::max());
  EXPECT_EQ(resampled_frame_count(std::numeric_limits<double>::quiet_NaN(), 30), std::numeric_limits<std::size_t>::max());
  // A BVH capture resampled: the end kept by the last frame, which holds the clip's last pose.
  std::string text = kOneJoint + "Frames: 4\nFrame Time: 0.1\n0\n10\n20\n30\n";
  MotionOptions o;
  o.sample_rate = 25;
  const Expected<Motion> m = read_motion(text, "r", o);
  ASSERT_TRUE(m) << m.error().message;
  EXPECT_EQ(m->animation.frame_count, 9u);  // 0.3 s at 25 Hz: 7.5 frames, 8 steps, 9 with both ends
  EXPECT_DOUBLE_EQ(m->animation.frame_time, 0.04);
  for (std::size_t f = 0; f < 9; ++f) {  // the channel turns 100 degrees per second, held after 0.3 s
    const double degrees = std::min(100 * static_cast<double>(f) * 0.04, 30.0);
    EXPECT_NEAR(std::abs(m->animation.frame(f)[0].real.w), std::cos(degrees * std::numbers::pi / 360), 1e-9) << f;
  }
  // A frame time so long that the count overflows: the budget refuses it.
  o.sample_rate = 1000;
  const Expected<Motion> huge = read_motion(kOneJoint + "Frames: 2\nFrame Time: 1e17\n0\n10\n", "huge", o);
  ASSERT_FALSE(huge);
  EXPECT_NE(huge.error().message.find("MB allowed"), std::string::npos) << huge.error().message;
}

// ---- writing ----------------------------------------------------------------------------------

TEST_F(HostileIo, ExclusiveCreateNeverReplacesAConcurrentWriter) {
  const fs::path target = dir_ / "out.txt";
  Expected<OutputFile> a = OutputFile::create(target, Overwrite::refuse);
  Expected<OutputFile> b = OutputFile::create(target, Overwrite::refuse);  // both see no file yet
  ASSERT_TRUE(a && b);
  ASSERT_TRUE(a->write("first"));
  ASSERT_TRUE(b->write("second"));
  ASSERT_TRUE(a->commit());
  const Status second = b->commit();
  ASSERT_FALSE(second);
  EXPECT_EQ(second.error().message, target.string() + ": already exists; it is replaced only when asked (--force on the command line, overwrite=True in Python, Overwrite::allow in C++)");
  EXPECT_EQ(slurp(target), "first");
  EXPECT_TRUE(no_temporaries());
}

TEST_F(HostileIo, ForceReplacesOnlyRegularFilesAndKeepsTheirPermissions) {
  const fs::path file = dir_ / "data.csv";
  std::ofstream(file) << "old";
  ::chmod(file.c_str(), 0640);
  ASSERT_TRUE(write_file_atomically(file, "new", Overwrite::allow));
  EXPECT_EQ(slurp(file), "new");
  struct stat st {};
  ASSERT_EQ(::stat(file.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 07777, 0640u);
  // A symbolic link is not replaced (nor is what it points to).
  const fs::path link = dir_ / "link.csv";
  fs::create_symlink(file, link);
  const Status l = write_file_atomically(link, "via link", Overwrite::allow);
  ASSERT_FALSE(l);
  EXPECT_NE(l.error().message.find("link.csv: is not a regular file"), std::string::npos) << l.error().message;
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_EQ(slurp(file), "new");
  // A FIFO and a device are never replaced.
  const fs::path fifo = dir_ / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_FALSE(write_file_atomically(fifo, "x", Overwrite::allow));
  EXPECT_TRUE(fs::is_fifo(fifo));
  const Status dev = write_file_atomically("/dev/null", "x", Overwrite::allow);
  ASSERT_FALSE(dev);
  EXPECT_NE(dev.error().message.find("/dev/null: is not a regular file"), std::string::npos);
  EXPECT_TRUE(no_temporaries());
}

TEST_F(HostileIo, ErrorsNameTheTargetAndLeaveNothingBehind) {
  const Status s = write_file_atomically(dir_ / "missing" / "out.bvh", "x", Overwrite::refuse);
  ASSERT_FALSE(s);
  EXPECT_EQ(s.error().message.find((dir_ / "missing" / "out.bvh").string() + ": cannot create a file in "), 0u) << s.error().message;
  EXPECT_EQ(s.error().message.find(".tmp"), std::string::npos) << s.error().message;
  {  // abandoned without commit: nothing left
    Expected<OutputFile> f = OutputFile::create(dir_ / "abandoned.txt", Overwrite::refuse);
    ASSERT_TRUE(f);
    ASSERT_TRUE(f->write(std::string(3 << 20, 'x')));
  }
  EXPECT_FALSE(fs::exists(dir_ / "abandoned.txt"));
  EXPECT_TRUE(no_temporaries());
}

/// Forks a child that writes `name` in `dir` forever, and returns once it is writing.
pid_t start_endless_writer(const fs::path& dir, const char* name) {
  const pid_t child = ::fork();
  if (child == 0) {  // writes forever until killed
    remove_temporary_files_on_signals();
    Expected<OutputFile> f = OutputFile::create(dir / name, Overwrite::refuse);
    if (!f) ::_exit(2);
    const std::string chunk(1 << 16, 'x');
    while (f->write(chunk)) {}
    ::_exit(3);
  }
  for (int i = 0; i < 5000 && child > 0 && !dq::test::writes_output_in(child, dir); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  return child;
}

/// Starts an endless writer of `name`, and once it writes, stops it with `signal`, which must be
/// what ended it.
void interrupt_endless_writer(const fs::path& dir, const char* name, int signal) {
  const pid_t child = start_endless_writer(dir, name);
  ASSERT_GT(child, 0);
  ASSERT_TRUE(dq::test::writes_output_in(child, dir)) << "the child never started writing";
  ::kill(child, signal);
  int status = 0;
  ::waitpid(child, &status, 0);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == signal);
}

TEST_F(HostileIo, ASignalDuringAWriteLeavesNoTemporaryFile) {
  ASSERT_NO_FATAL_FAILURE(interrupt_endless_writer(dir_, "big.csv", SIGTERM));
  EXPECT_TRUE(no_temporaries());
  EXPECT_FALSE(fs::exists(dir_ / "big.csv"));
}

TEST_F(HostileIo, AnonymousFilesLeaveNothingEvenAfterSigkill) {
  // SIGKILL runs no handler: only a file without a name (O_TMPFILE) leaves nothing behind.
  if (!dq::test::has_anonymous_files(dir_)) GTEST_SKIP() << "this file system has no O_TMPFILE";
  {  // while being written, the file has no name in the directory
    Expected<OutputFile> f = OutputFile::create(dir_ / "out.txt", Overwrite::refuse);
    ASSERT_TRUE(f);
    ASSERT_TRUE(f->write("data"));
    EXPECT_TRUE(fs::is_empty(dir_));
    ASSERT_TRUE(f->commit());
  }
  EXPECT_EQ(slurp(dir_ / "out.txt"), "data");
  ASSERT_NO_FATAL_FAILURE(interrupt_endless_writer(dir_, "big.csv", SIGKILL));
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(dir_)) left.push_back(e.path().filename().string());
  EXPECT_EQ(left, std::vector<std::string>{"out.txt"});
}

}  // namespace
