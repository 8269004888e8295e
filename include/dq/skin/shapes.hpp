// A test shape for skinning (library dqkit::skin): the classic capped cylinder on two bones,
// used by the candy-wrapper comparison (docs/skinning.md), the tests and the benchmarks.
#pragma once

#include "dq/skin/skin.hpp"

namespace dq {

struct CylinderShape {
  double radius = 0.5;
  double length = 4;       ///< along +x from the origin; the joint is at the middle
  double blend = 0.5;      ///< half-width of the region around the joint where the weights blend (smoothstep)
  int rings = 41;          ///< circles of vertices along the length (odd: one ring at the joint)
  int segments = 32;       ///< vertices per circle
};

/// The closed (capped, outward-oriented) cylinder skinned to bone 0 (bind at the origin) and bone
/// 1 (bind at the joint, (length/2, 0, 0)), both unrotated. Vertex ring r, segment s is at
/// r * segments + s; the two cap centres come last.
RawSkin two_bone_cylinder(const CylinderShape& shape = {});

}  // namespace dq
