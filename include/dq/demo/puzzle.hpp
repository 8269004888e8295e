// The 3D slider puzzle of the VRML dual quaternion tutorial (§2.1, §2.6): 23 pieces and one hole
// on the six faces of a cube, four slots per face.
//
// Geometry, as the tutorial's PROTO Element: a piece is a slab 0.4 × 4 × 4 in its own frame
// (x ∈ [−0.2, 0.2] is the thickness, its picture on the +x side), placed on a face 4.5 from the
// centre, at ±2.1 on the face's two other axes. A piece next to the hole moves into it:
//   - on the same face: a slide by 4.2 (the tutorial's onSameFace),
//   - across an edge: a quarter turn onto the neighbouring face about the axis parallel to the
//     edge through the point 2.1 from both faces (the tutorial's transVec is the diagonal
//     n_piece + n_hole, the axis point is 2.1 · transVec), by exactly π/2 (the tutorial's 1.5708
//     leaves pieces 9e-6 off their slots).
//
// The state is exact: each piece's slot and its rotation as an integer matrix (a rotation of the
// cube group), so that no error accumulates over moves; the dual quaternions are derived from it.
//
// Slot numbering: slot s is on face s / 4, the faces in the order +x, −x, +y, −y, +z, −z; on the
// face with normal axis a, bit 0 of s % 4 set means − on axis (a + 1) % 3, bit 1 set means − on
// axis (a + 2) % 3. Piece p starts (solved) in slot p, the hole in slot 23, each piece rotated by
// the cyclic permutation taking (x, y, z) to (a, a + 1, a + 2) (faces with a − normal: then a half
// turn about that frame's z). `undo`/`redo` replay the history; a scramble never undoes the move
// before.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "dq/convert/vrml.hpp"
#include "dq/core/dual_quaternion.hpp"

namespace dq::demo {

inline constexpr int puzzle_slots = 24;
inline constexpr int puzzle_pieces = 23;
inline constexpr double face_distance = 4.5;  ///< of a face (and a piece's centre) from the cube's centre
inline constexpr double slot_offset = 2.1;    ///< of a slot's centre on the face's two other axes
inline constexpr double slide_distance = 4.2;
inline constexpr double piece_size = 4.0;       ///< the slab's edge
inline constexpr double piece_thickness = 0.4;  ///< the slab's thickness (local x)

/// A rotation of the cube group: an integer matrix (column vectors), entries −1, 0 or 1.
using CubeRotation = std::array<std::array<int, 3>, 3>;

/// Integer coordinates of a slot's centre: ±2 on the face's normal axis (4.5), ±1 on the others (2.1).
std::array<int, 3> slot_cell(int slot);
/// The centre of a slot (world units).
Vec3<double> slot_center(int slot);
/// The outward unit normal of a slot's face.
Vec3<double> slot_normal(int slot);
/// Whether a piece in slot `from` can move into a hole in slot `to` (same face and a side apart,
/// or on neighbouring faces across the edge they share, in the same row).
bool slots_adjacent(int from, int to);

/// The rigid motion of a piece moving from slot `from` into the hole at `to`, at fraction t ∈ [0, 1]
/// of the move, composed as the tutorial's calcCurPos does: a slide by 4.2 t along the face, or
/// translate the axis point to the origin (relQuatA), rotate by t·π/2 and translate back (relQuatB),
/// relQuatB · relQuatA. The piece's pose during the move is this times its pose before.
/// Precondition: slots_adjacent(from, to).
DualQuaternion<double> move_motion(int from, int to, double t = 1);

struct PuzzleMove {
  int piece = -1;
  int from = -1;  ///< the piece's slot before (the hole's after)
  int to = -1;    ///< the hole's slot before (the piece's after)
};

class Puzzle {
 public:
  /// The solved puzzle.
  Puzzle();

  int hole() const noexcept { return hole_; }
  /// The piece in a slot, or −1 for the hole.
  int piece_at(int slot) const { return occupant_[static_cast<std::size_t>(slot)]; }
  int slot_of(int piece) const { return slot_[static_cast<std::size_t>(piece)]; }
  const CubeRotation& rotation_of(int piece) const { return rotation_[static_cast<std::size_t>(piece)]; }
  /// A piece's transform (its frame to the world), exact up to the rounding of cos(π/4).
  DualQuaternion<double> pose(int piece) const;
  /// As a VRML Transform (rotation + translation), through dq::to_vrml.
  VrmlTransform<double> vrml(int piece) const { return to_vrml(pose(piece)); }

  /// The pieces that can move (next to the hole), in slot order.
  std::vector<int> movable() const;
  bool can_move(int piece) const;
  /// The move of a piece (its slots), or nothing if it is not next to the hole.
  std::optional<PuzzleMove> move_of(int piece) const;
  /// Moves a piece into the hole; false (and nothing changes) if it cannot move. Clears the redo list.
  bool move(int piece);
  bool undo();
  bool redo();
  const std::vector<PuzzleMove>& history() const noexcept { return history_; }

  /// Every piece in its home slot with its home rotation.
  bool solved() const;
  /// `count` random legal moves from `seed` (reproducible), none undoing the one before. Returns
  /// the pieces moved, in order (also appended to the history).
  std::vector<int> scramble(std::uint64_t seed, int count);

  /// A hash of the state (slots and rotations), for search.
  std::uint64_t key() const;

 private:
  void apply(const PuzzleMove& m);
  std::array<int, puzzle_slots> occupant_{};
  std::array<int, puzzle_pieces> slot_{};
  std::array<CubeRotation, puzzle_pieces> rotation_{};
  int hole_ = puzzle_slots - 1;
  std::vector<PuzzleMove> history_, redo_;
};

/// The home rotation of the piece of a slot (see the header comment).
CubeRotation home_rotation(int slot);
/// The rotation part of move_motion(from, to, 1), as an integer matrix.
CubeRotation move_rotation(int from, int to);

/// A shortest sequence of pieces to move that solves the puzzle (IDA* with, as heuristic, the sum
/// of each piece's distance in moves to its home slot), or nothing if none has at most
/// `max_depth` moves. Empty when already solved.
std::optional<std::vector<int>> solve(const Puzzle& puzzle, int max_depth);

/// The state as an X3D document: each piece a Transform DEF="piece_NN" (NN its number, from 00)
/// with the VRML rotation and translation of its pose and a Box slab; the hole is not exported.
std::string to_x3d(const Puzzle& puzzle);

}  // namespace dq::demo
