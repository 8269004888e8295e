// dqkit-puzzle: the 3D slider puzzle of the VRML dual quaternion tutorial (docs/demos.md).
#include <deque>
#include <iostream>

#include "common.hpp"
#include "dq/io/file.hpp"

#if defined(DQKIT_DEMO_WINDOW)
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#endif

using namespace dq;

int main(int argc, char** argv) {
  CLI::App app{"dqkit-puzzle: the VRML tutorial's 3D slider puzzle (click a piece next to the hole to move it; drag to turn the cube)"};
  apps::Options o;
  apps::add_options(app, o);
  std::uint64_t seed = 1;
  int scramble = 0, max_depth = 18;
  bool solve = false;
  std::filesystem::path x3d;
  app.add_option("--seed", seed, "Seed of the scramble");
  app.add_option("--scramble", scramble, "Random legal moves from the solved puzzle (none undoing the one before)")->check(CLI::NonNegativeNumber);
  app.add_flag("--solve", solve, "Append the solver's shortest solution (animated)");
  app.add_option("--max-depth", max_depth, "Longest solution the solver looks for")->check(CLI::Range(0, 40));
  app.add_option("--export-x3d", x3d, "Write the state after all moves as X3D (each piece a Transform DEF=\"piece_NN\")");
  CLI11_PARSE(app, argc, argv);

  demo::PuzzleScript script;
  script.start.scramble(seed, scramble);
  if (solve) {
    const auto solution = demo::solve(script.start, max_depth);
    if (!solution) {
      std::cerr << "error: no solution of at most " << max_depth << " moves (raise --max-depth, or scramble less)\n";
      return 1;
    }
    script.moves = *solution;
    std::cout << "solution: " << solution->size() << " moves\n";
  }
  if (!x3d.empty()) {
    demo::Puzzle end = script.start;
    for (int piece : script.moves) end.move(piece);
    if (const Status s = write_file_atomically(x3d, demo::to_x3d(end), Overwrite::allow); !s) {
      std::cerr << "error: " << s.error().message << "\n";
      return 1;
    }
    std::cout << "wrote " << x3d.string() << (end.solved() ? " (solved)" : " (not solved)") << "\n";
  }
  const double aspect = double(o.width) / o.height;
  if (o.headless) {
    return apps::run_headless(o, [&](int f) {
      const demo::PuzzleFrameState s = demo::puzzle_frame(script, f, o.frames);
      return std::vector<demo::View>{demo::puzzle_view(s.puzzle, s.animation, demo::puzzle_camera(aspect), {})};
    });
  }

  // Interactive: click a piece to move it, drag to turn the cube, buttons (or keys S, U, R,
  // Space) to scramble, undo, redo and solve (animated).
  demo::Puzzle puzzle = script.start;
  std::deque<int> pending(script.moves.begin(), script.moves.end());
  std::optional<demo::PuzzleAnimation> animation;
  double yaw = 0.6, pitch = 0.45;
  std::uint64_t next_seed = seed + 1;
  std::string message;
  auto act = [&](char what) {
    pending.clear();
    animation.reset();
    if (what == 's') puzzle.scramble(next_seed++, 20), message = "scrambled";
    if (what == 'u') message = puzzle.undo() ? "undone" : "nothing to undo";
    if (what == 'r') message = puzzle.redo() ? "redone" : "nothing to redo";
    if (what == 'v') {
      const auto solution = demo::solve(puzzle, max_depth);
      if (solution) pending.assign(solution->begin(), solution->end()), message = std::to_string(solution->size()) + " moves";
      else message = "too far to solve (more than " + std::to_string(max_depth) + " moves)";
    }
  };
  return apps::run_window(o, "dqkit-puzzle", [&](const apps::Input& in, render::Renderer&) {
    yaw -= in.drag_x * 0.01;
    pitch = std::clamp(pitch + in.drag_y * 0.01, -1.4, 1.4);
    const render::Camera camera = demo::puzzle_camera(aspect, yaw, pitch);
#if defined(DQKIT_DEMO_WINDOW)
    for (int key : in.keys) {
      if (key == GLFW_KEY_S) act('s');
      if (key == GLFW_KEY_U) act('u');
      if (key == GLFW_KEY_R) act('r');
      if (key == GLFW_KEY_SPACE) act('v');
    }
    ImGui::SetNextWindowPos({8, 8}, ImGuiCond_Once);
    ImGui::Begin("Puzzle", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
    if (ImGui::Button("Scramble")) act('s');
    ImGui::SameLine();
    if (ImGui::Button("Undo")) act('u');
    ImGui::SameLine();
    if (ImGui::Button("Redo")) act('r');
    ImGui::SameLine();
    if (ImGui::Button("Solve")) act('v');
    ImGui::Text("%s, %zu moves, %s", puzzle.solved() ? "solved" : "not solved", puzzle.history().size(), message.c_str());
    ImGui::End();
#endif
    if (in.clicked && !animation) {
      const int piece = demo::pick_piece(puzzle, camera, o.width, o.height, in.mouse_x, in.mouse_y);
      if (piece >= 0 && puzzle.can_move(piece)) pending.push_back(piece);
    }
    if (!animation && !pending.empty()) {
      if (const auto m = puzzle.move_of(pending.front())) animation = demo::PuzzleAnimation{*m, 0};
      pending.pop_front();
    }
    std::vector<demo::View> views{demo::puzzle_view(puzzle, animation, camera, {})};
    if (animation && (animation->t += 1.0 / 12) >= 1) {
      puzzle.move(animation->move.piece);
      animation.reset();
    }
    return views;
  });
}
