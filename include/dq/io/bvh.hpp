// BVH motion capture files: reading (any channel order, End Sites, 6-channel joints anywhere, any
// whitespace and line endings), writing (exact round trip, optional change of rotation order),
// and conversion to a skeleton and an animation.
//
// Conventions: `CHANNELS ... Zrotation Xrotation Yrotation` means the local rotation
// Rz(a) Rx(b) Ry(c), angles in the order listed (intrinsic), in degrees in the file and radians in
// dqkit; the local transform is translate(OFFSET + position channels) · rotation. End Sites are
// joints without channels, named "<parent name>_End" (or "<parent name>_End_2", "_3", ... where
// the file has a joint of that name, so that names never collide). Frames are numbered from 0.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "dq/anim/animation_data.hpp"
#include "dq/anim/skeleton.hpp"
#include "dq/convert/euler.hpp"
#include "dq/util/expected.hpp"

namespace dq {

enum class BvhChannel : std::uint8_t { Xposition, Yposition, Zposition, Xrotation, Yrotation, Zrotation };

std::string_view to_string(BvhChannel c) noexcept;

/// What the reader accepts: larger inputs are errors that say which limit was hit. Every cost of
/// reading is linear in the size of the text (docs/reliability.md has the measurements).
struct BvhLimits {
  static constexpr std::size_t max_file_bytes = std::size_t{1} << 30;  ///< read_bvh_file: 1 GiB
  static constexpr std::size_t max_joints = std::size_t{1} << 16;      ///< End Sites included
  static constexpr std::size_t max_frames = std::size_t{1} << 26;      ///< declared in 'Frames:'
  static constexpr std::size_t max_name_bytes = 1024;                  ///< a joint name (UTF-8)
};

struct BvhJoint {
  std::string name;
  int parent = -1;  ///< index into BvhFile::joints, −1 for a root; parents come first
  Vec3<double> offset{};
  std::vector<BvhChannel> channels;  ///< empty for End Sites
  bool end_site = false;
  std::size_t first_channel = 0;  ///< index of this joint's first value in a frame
};

struct BvhFile {
  std::vector<BvhJoint> joints;  ///< in file order (depth first)
  std::size_t frame_count = 0;
  double frame_time = 0;       ///< seconds
  std::vector<double> motion;  ///< frame_count × channel_count values, frame by frame, as in the file
  std::vector<std::string> warnings;  ///< things the reader accepted but the caller should hear ("file:line: ...")

  std::size_t channel_count() const noexcept;
  std::span<const double> frame(std::size_t f) const { return std::span(motion).subspan(f * channel_count(), channel_count()); }
};

/// Parses BVH text. `source` names the input in error messages ("source:line: what was expected").
/// Never throws or crashes on malformed input; rejects non-finite numbers, channel counts other
/// than 0–6, unknown channel names, joint names that are not UTF-8 or contain braces, inputs
/// beyond BvhLimits, and motion data with fewer frames than the header declares
/// or frames of the wrong length. Whole frames beyond the declared count are ignored with a
/// warning (BvhFile::warnings), as some published files have one.
Expected<BvhFile> read_bvh(std::string_view text, std::string_view source = "<bvh>");
/// Reads and parses a regular file of at most BvhLimits::max_file_bytes (a directory, device,
/// FIFO or socket is an error, found without blocking); errors name the file.
Expected<BvhFile> read_bvh_file(const std::filesystem::path& path);

/// Whether write_bvh can write `bvh` as text that read_bvh reads back as the same file: a root
/// first, parents before their children, at most 6 channels per joint, End Sites without channels
/// or children, names read_bvh accepts (UTF-8, no braces, single spaces between words), finite
/// offsets and motion values, a finite positive frame time, and frame_count × channel_count()
/// motion values. The error names the joint, or the frame and channel.
Status check_writable(const BvhFile& bvh);
/// The BVH text of a file: numbers in shortest round-trip form, so reading it back gives the same
/// values bit for bit; tabs for indentation, '\n' line endings. An error (check_writable) where
/// the text could not be read back.
Expected<std::string> write_bvh(const BvhFile& bvh);
/// The same text in pieces of about 64 KiB, for writing a long capture without holding it whole;
/// check_writable first, so that on an error nothing reaches `sink`.
Status write_bvh(const BvhFile& bvh, const std::function<void(std::string_view)>& sink);

/// Changes every joint's rotation channels to `order` (intrinsic, as BVH means it), converting
/// each frame's angles so that every local rotation is the same (to rounding). Joints with fewer
/// than three rotation channels get three. Position channels are kept, before the rotations.
/// Only the six Tait–Bryan orders are BVH orders: a proper Euler order (XYX, ...) is an error.
Expected<BvhFile> with_rotation_order(const BvhFile& bvh, EulerOrder order);

/// The local transform of joint j in frame f (translate(OFFSET + positions) · rotation).
/// Precondition: j < joints.size(), f < frame_count.
DualQuaternion<double> bvh_local_transform(const BvhFile& bvh, std::size_t joint, std::size_t frame);
/// The local transform of joint j from OFFSET alone (the rest pose).
DualQuaternion<double> bvh_rest_transform(const BvhFile& bvh, std::size_t joint);

/// A BVH file for a skeleton and its animation (from any source): every joint gets rotation
/// channels in `order` (degrees), the roots and every joint whose translation moves also get
/// position channels; OFFSET is the rest translation. Names have whitespace replaced by '_'.
/// End Sites (skeleton joints marked so) become End Site blocks; names changed by the replacement
/// are made unique again (suffix "_2", ...), each with a warning in BvhFile::warnings. A skeleton without animation is written with one
/// frame, its rest pose (OFFSET alone cannot hold rest rotations). Proper Euler orders are errors,
/// as is an animation of another joint count than the skeleton's.
Expected<BvhFile> to_bvh(const Skeleton& skeleton, const Animation& animation, EulerOrder order = EulerOrder::ZXY);

/// The skeleton of a BVH file (joint order preserved; End Sites included).
Expected<Skeleton> bvh_skeleton(const BvhFile& bvh);
/// Whether `skeleton` is bvh_skeleton(bvh): as many joints, each naming the file's joint it reads
/// (and the motion has frame_count × channel_count values).
bool is_skeleton_of(const Skeleton& skeleton, const BvhFile& bvh);
/// Every frame's local transforms, in skeleton order (frame_count × joints × 64 bytes: callers that
/// bound memory check that first, as load_motion does). Precondition: is_skeleton_of(skeleton, bvh).
Animation bvh_animation(const BvhFile& bvh, const Skeleton& skeleton);

}  // namespace dq
