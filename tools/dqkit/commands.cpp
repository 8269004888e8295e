#include "commands.hpp"

namespace dq::cli {

namespace {
// The command table: add new commands here (see commands.hpp).
constexpr Command kCommands[] = {
    {"info", "Joints, hierarchy, channels, frames and frame time of a motion file", define_info},
    {"fk", "Forward kinematics: each joint's position and rotation per frame (world or local), as CSV or JSON", define_fk},
    {"convert", "Convert a motion file to BVH (rotation order, rate, unit scale)", define_convert},
#if defined(DQKIT_HAVE_SKIN)
    {"skin", "A skinned model at a time (LBS, DQS or CoR): every vertex in world space as CSV, OBJ, PLY or glTF", define_skin},
#endif
#if defined(DQKIT_HAVE_RENDER)
    {"render", "Pictures of a skinned model (LBS, DQS, CoR side by side; frame sequences) as PNG, without a display", define_render},
#endif
#if defined(DQKIT_HAVE_IK)
    {"fix-feet", "Remove foot sliding from a BVH capture (IK on the legs; every other channel kept exactly)", define_fix_feet},
#endif
};
}  // namespace

std::span<const Command> commands() { return kCommands; }

}  // namespace dq::cli
