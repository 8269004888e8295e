// IK on motion capture: a kinematic model made from a BVH file's own channels, and the removal of
// foot sliding (`dqkit fix-feet`): contacts detected from height and speed, the foot pinned through
// each contact with IK on its leg, blended in and out, every other channel left exactly as it was.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "dq/ik/kinematic_model.hpp"
#include "dq/io/bvh.hpp"
#include "dq/util/expected.hpp"

namespace dq {

/// One DOF per BVH channel: position channels are prismatic along the parent's axes, rotation
/// channels revolute about the joint's axes, in the order of the file (positions first, as BVH
/// means them). Parameters are in radians and model units; frames in the file's degrees.
struct BvhKinematics {
  KinematicModel model;
  std::vector<std::size_t> channel_of;  ///< for each parameter, its channel index in a frame

  /// A frame's channel values as model parameters (degrees to radians).
  void to_parameters(std::span<const double> frame, std::span<double> q) const;
  /// Writes the parameters flagged in `which` back into a frame (radians to degrees); the other
  /// channels are not touched.
  void to_frame(std::span<const double> q, std::span<const std::uint8_t> which, std::span<double> frame) const;
};

/// The channel model of a BVH file (joint order and names as bvh_skeleton gives them).
Expected<BvhKinematics> bvh_kinematics(const BvhFile& bvh);

struct FixFeetOptions {
  /// The foot joints (the toes in CMU captures). Empty: every joint whose name contains "Toe"
  /// (one per leg), else "Foot", else "Ankle".
  std::vector<std::string> feet;
  /// Contact: the foot below (lowest height in the clip + height) and slower than speed. Negative:
  /// chosen from the leg's length L (height 0.1 L, speed 1.0 L per second).
  double height = -1;
  double speed = -1;
  int min_contact_frames = 3;  ///< shorter contacts are dropped
  int merge_gap_frames = 3;    ///< gaps up to this long between contacts are bridged (debounce)
  int blend_frames = 6;        ///< frames over which the pin is blended in and out
};

struct FootContactReport {
  std::string joint;
  std::vector<std::pair<std::size_t, std::size_t>> contacts;  ///< [first, last] frames, inclusive
  double slide_before = 0;  ///< total horizontal travel of the foot during its contacts
  double slide_after = 0;
  double max_slide_step_before = 0;  ///< largest horizontal travel in one frame during a contact
  double max_slide_step_after = 0;
};

struct FixFeetReport {
  std::vector<FootContactReport> feet;
  std::vector<std::string> leg_joints;  ///< the joints whose channels IK changed
  double max_leg_joint_motion = 0;      ///< largest displacement of a leg joint (model units)
  double max_other_joint_motion = 0;    ///< the same for every other joint (0: untouched)
  double max_pin_error = 0;             ///< largest distance of a pinned foot from its pin (model units)
  int unconverged_frames = 0;           ///< frames where IK stopped short of 1e-9 leg lengths (a nearly
                                        ///< straight leg converges slowly; a pin may be out of reach)
};

/// Removes foot sliding from a capture in place: only the leg channels change.
Expected<FixFeetReport> fix_foot_sliding(BvhFile& bvh, const FixFeetOptions& options = {});

}  // namespace dq
