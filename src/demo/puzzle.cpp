#include "dq/demo/puzzle.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include "dq/util/assert.hpp"

namespace dq::demo {
namespace {

int face_axis(int slot) { return slot / 8; }
int face_sign(int slot) { return (slot / 4) % 2 == 0 ? 1 : -1; }

CubeRotation multiply(const CubeRotation& a, const CubeRotation& b) {
  CubeRotation c{};
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t k = 0; k < 3; ++k)
      for (std::size_t j = 0; j < 3; ++j) c[i][k] += a[i][j] * b[j][k];
  return c;
}

Quaternion<double> to_quaternion(const CubeRotation& r) {
  Mat3<double> m;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) m(i, k) = r[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)];
  return Quaternion<double>::from_matrix(m);
}

/// Unit vector along an axis, times a sign.
Vec3<double> axis_vector(int axis, int sign) {
  Vec3<double> v{};
  v[axis] = sign;
  return v;
}

struct Turn {
  int axis = -1;  ///< −1: a slide
  int sign = 0;   ///< of the quarter turn about +axis
  Vec3<double> point{}, slide{};
};

Turn turn_of(int from, int to) {
  DQ_PRECONDITION(slots_adjacent(from, to), "a move needs a piece next to the hole", {});
  Turn t;
  const int a = face_axis(from), b = face_axis(to);
  if (a == b) {
    t.slide = slot_center(to) - slot_center(from);
    return t;
  }
  // Turning n_from onto n_to is a quarter turn about n_from × n_to.
  t.axis = 3 - a - b;
  const Vec3<double> c = cross(axis_vector(a, face_sign(from)), axis_vector(b, face_sign(to)));
  t.sign = c[t.axis] > 0 ? 1 : -1;
  t.point = (axis_vector(a, face_sign(from)) + axis_vector(b, face_sign(to))) * slot_offset;  // 2.1 · transVec
  return t;
}

}  // namespace

std::array<int, 3> slot_cell(int slot) {
  DQ_PRECONDITION(slot >= 0 && slot < puzzle_slots, "slot out of range", {});
  const int a = face_axis(slot), q = slot % 4;
  std::array<int, 3> c{};
  c[static_cast<std::size_t>(a)] = 2 * face_sign(slot);
  c[static_cast<std::size_t>((a + 1) % 3)] = (q & 1) ? -1 : 1;
  c[static_cast<std::size_t>((a + 2) % 3)] = (q & 2) ? -1 : 1;
  return c;
}

Vec3<double> slot_center(int slot) {
  const auto c = slot_cell(slot);
  Vec3<double> p;
  for (int i = 0; i < 3; ++i) {
    const int v = c[static_cast<std::size_t>(i)];
    p[i] = (v > 0 ? 1 : -1) * (std::abs(v) == 2 ? face_distance : slot_offset);
  }
  return p;
}

Vec3<double> slot_normal(int slot) {
  DQ_PRECONDITION(slot >= 0 && slot < puzzle_slots, "slot out of range", {});
  return axis_vector(face_axis(slot), face_sign(slot));
}

bool slots_adjacent(int from, int to) {
  if (from < 0 || to < 0 || from >= puzzle_slots || to >= puzzle_slots || from == to) return false;
  const auto p = slot_cell(from), h = slot_cell(to);
  const int a = face_axis(from), b = face_axis(to);
  if (from / 4 == to / 4) {  // same face: one of the two in-face coordinates differs
    int differing = 0;
    for (std::size_t i = 0; i < 3; ++i) differing += p[i] != h[i];
    return differing == 1;
  }
  if (a == b) return false;  // opposite faces
  // Neighbouring faces: the piece lies at the edge towards the hole's face, the hole at the edge
  // towards the piece's face, and both in the same row along the edge.
  const std::size_t ua = static_cast<std::size_t>(a), ub = static_cast<std::size_t>(b), uc = static_cast<std::size_t>(3 - a - b);
  return p[ub] == face_sign(to) && h[ua] == face_sign(from) && p[uc] == h[uc];
}

DualQuaternion<double> move_motion(int from, int to, double t) {
  const Turn turn = turn_of(from, to);
  using DQ = DualQuaternion<double>;
  if (turn.axis < 0) return DQ::from_translation(turn.slide * t);
  const DQ rel_a = DQ::from_translation(-turn.point);
  const DQ rel_b = DQ::from_rotation_translation(
      Quaternion<double>::from_axis_angle(axis_vector(turn.axis, 1), turn.sign * t * std::numbers::pi / 2), turn.point);
  return rel_b * rel_a;
}

CubeRotation move_rotation(int from, int to) {
  const Turn turn = turn_of(from, to);
  CubeRotation r{};
  if (turn.axis < 0) {
    for (std::size_t i = 0; i < 3; ++i) r[i][i] = 1;
    return r;
  }
  // Quarter turn about axis k: e_{k+1} → s e_{k+2}, e_{k+2} → −s e_{k+1}.
  const auto k = static_cast<std::size_t>(turn.axis), i = (k + 1) % 3, j = (k + 2) % 3;
  r[k][k] = 1;
  r[j][i] = turn.sign;
  r[i][j] = -turn.sign;
  return r;
}

CubeRotation home_rotation(int slot) {
  DQ_PRECONDITION(slot >= 0 && slot < puzzle_slots, "slot out of range", {});
  const auto a = static_cast<std::size_t>(face_axis(slot));
  const int s = face_sign(slot);
  CubeRotation r{};
  // Columns: local x → s e_a, local y → s e_{a+1}, local z → e_{a+2} (a half turn about local z for s = −1).
  r[a][0] = s;
  r[(a + 1) % 3][1] = s;
  r[(a + 2) % 3][2] = 1;
  return r;
}

Puzzle::Puzzle() {
  for (int s = 0; s < puzzle_slots; ++s) occupant_[static_cast<std::size_t>(s)] = s < puzzle_pieces ? s : -1;
  for (int p = 0; p < puzzle_pieces; ++p) {
    slot_[static_cast<std::size_t>(p)] = p;
    rotation_[static_cast<std::size_t>(p)] = home_rotation(p);
  }
}

DualQuaternion<double> Puzzle::pose(int piece) const {
  DQ_PRECONDITION(piece >= 0 && piece < puzzle_pieces, "piece out of range", {});
  return DualQuaternion<double>::from_rotation_translation(to_quaternion(rotation_of(piece)), slot_center(slot_of(piece)));
}

std::vector<int> Puzzle::movable() const {
  std::vector<int> out;
  for (int s = 0; s < puzzle_slots; ++s)
    if (slots_adjacent(s, hole_)) out.push_back(piece_at(s));
  return out;
}

bool Puzzle::can_move(int piece) const {
  return piece >= 0 && piece < puzzle_pieces && slots_adjacent(slot_of(piece), hole_);
}

std::optional<PuzzleMove> Puzzle::move_of(int piece) const {
  if (!can_move(piece)) return std::nullopt;
  return PuzzleMove{piece, slot_of(piece), hole_};
}

void Puzzle::apply(const PuzzleMove& m) {
  auto& r = rotation_[static_cast<std::size_t>(m.piece)];
  r = multiply(move_rotation(m.from, m.to), r);
  slot_[static_cast<std::size_t>(m.piece)] = m.to;
  occupant_[static_cast<std::size_t>(m.to)] = m.piece;
  occupant_[static_cast<std::size_t>(m.from)] = -1;
  hole_ = m.from;
}

bool Puzzle::move(int piece) {
  const auto m = move_of(piece);
  if (!m) return false;
  apply(*m);
  history_.push_back(*m);
  redo_.clear();
  return true;
}

bool Puzzle::undo() {
  if (history_.empty()) return false;
  const PuzzleMove m = history_.back();
  history_.pop_back();
  apply({m.piece, m.to, m.from});
  redo_.push_back(m);
  return true;
}

bool Puzzle::redo() {
  if (redo_.empty()) return false;
  const PuzzleMove m = redo_.back();
  redo_.pop_back();
  apply(m);
  history_.push_back(m);
  return true;
}

bool Puzzle::solved() const {
  for (int p = 0; p < puzzle_pieces; ++p)
    if (slot_of(p) != p || rotation_of(p) != home_rotation(p)) return false;
  return true;
}

std::vector<int> Puzzle::scramble(std::uint64_t seed, int count) {
  std::uint64_t state = seed;
  auto next = [&state] {  // splitmix64: the same sequence on every platform
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  };
  std::vector<int> moved;
  int last = -1;
  for (int i = 0; i < count; ++i) {
    std::vector<int> options = movable();
    std::erase(options, last);  // moving it again would undo its move
    last = options[static_cast<std::size_t>(next() % options.size())];
    move(last);
    moved.push_back(last);
  }
  return moved;
}

std::uint64_t Puzzle::key() const {
  // FNV-1a over the slots and rotation matrices.
  std::uint64_t h = std::uint64_t{1469598103934665603};
  auto mix = [&h](int v) { h = (h ^ static_cast<std::uint64_t>(v + 2)) * std::uint64_t{1099511628211}; };
  for (int p = 0; p < puzzle_pieces; ++p) {
    mix(slot_of(p));
    for (const auto& row : rotation_of(p))
      for (int v : row) mix(v);
  }
  return h;
}

namespace {

/// Moves between every two slots (breadth-first over the slot graph).
std::array<std::array<int, puzzle_slots>, puzzle_slots> slot_distances() {
  std::array<std::array<int, puzzle_slots>, puzzle_slots> d{};
  for (int s = 0; s < puzzle_slots; ++s) {
    auto& row = d[static_cast<std::size_t>(s)];
    row.fill(-1);
    row[static_cast<std::size_t>(s)] = 0;
    std::vector<int> queue{s};
    for (std::size_t i = 0; i < queue.size(); ++i)
      for (int n = 0; n < puzzle_slots; ++n)
        if (row[static_cast<std::size_t>(n)] < 0 && slots_adjacent(queue[i], n)) {
          row[static_cast<std::size_t>(n)] = row[static_cast<std::size_t>(queue[i])] + 1;
          queue.push_back(n);
        }
  }
  return d;
}

struct Search {
  Puzzle puzzle;
  std::array<std::array<int, puzzle_slots>, puzzle_slots> distance = slot_distances();
  std::vector<int> path;

  int heuristic() const {  // each move moves one piece one step: admissible
    int h = 0;
    for (int p = 0; p < puzzle_pieces; ++p) h += distance[static_cast<std::size_t>(puzzle.slot_of(p))][static_cast<std::size_t>(p)];
    return h;
  }
  /// The smallest f over the bound, or −1 when solved.
  int dfs(int g, int bound, int last) {
    const int f = g + heuristic();
    if (f > bound) return f;
    if (puzzle.solved()) return -1;
    int next_bound = std::numeric_limits<int>::max();
    for (int piece : puzzle.movable()) {
      if (piece == last) continue;
      puzzle.move(piece);
      path.push_back(piece);
      const int t = dfs(g + 1, bound, piece);
      if (t < 0) return -1;
      next_bound = std::min(next_bound, t);
      path.pop_back();
      puzzle.undo();
    }
    return next_bound;
  }
};

}  // namespace

std::optional<std::vector<int>> solve(const Puzzle& puzzle, int max_depth) {
  Search s{puzzle, slot_distances(), {}};
  int bound = s.heuristic();
  while (bound <= max_depth) {
    const int t = s.dfs(0, bound, -1);
    if (t < 0) return s.path;
    if (t == std::numeric_limits<int>::max()) break;
    bound = t;
  }
  return std::nullopt;
}

std::string to_x3d(const Puzzle& puzzle) {
  std::string out =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<!DOCTYPE X3D PUBLIC \"ISO//Web3D//DTD X3D 3.3//EN\" \"http://www.web3d.org/specifications/x3d-3.3.dtd\">\n"
      "<X3D profile=\"Interchange\" version=\"3.3\">\n"
      "  <head><meta name=\"generator\" content=\"dqkit-puzzle\"/></head>\n"
      "  <Scene>\n";
  char line[512];
  for (int p = 0; p < puzzle_pieces; ++p) {
    const VrmlTransform<double> v = puzzle.vrml(p);
    std::snprintf(line, sizeof line,
                  "    <Transform DEF=\"piece_%02d\" translation=\"%.17g %.17g %.17g\" rotation=\"%.17g %.17g %.17g %.17g\">\n"
                  "      <Shape><Appearance><Material diffuseColor=\"0.8 0.4 0\"/></Appearance>"
                  "<Box size=\"%g %g %g\"/></Shape>\n"
                  "    </Transform>\n",
                  p, v.translation.x, v.translation.y, v.translation.z, v.axis.x, v.axis.y, v.axis.z, v.angle, piece_thickness,
                  piece_size, piece_size);
    out += line;
  }
  out += "  </Scene>\n</X3D>\n";
  return out;
}

}  // namespace dq::demo
