// dqkit-puzzle: the 3D slider puzzle of the VRML dual quaternion tutorial (docs/demos.md).
#include <deque>
#include <iostream>

#include "common.hpp"
#include "dq/io/file.hpp"

#if defined(DQKIT_DEMO_WINDOW)
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
  app.add_option("--seed", seed, "Seed of the scramble")->check(cli::whole_number_up_to(~0ull));
  app.add_option("--scramble", scramble, "Random legal moves from the solved puzzle (none undoing the one before)")
      ->check(cli::whole_number_up_to(1000000));
  app.add_flag("--solve", solve, "Append the solver's shortest solution (animated)");
  app.add_option("--max-depth", max_depth, "Longest solution the solver looks for")->check(CLI::Range(0, 40));
  const CLI::Option* export_x3d =
      app.add_option("--export-x3d", x3d, "Write the state after all moves as X3D (each piece a Transform DEF=\"piece_NN\"), a .x3d file; replaced only with --force");
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
  if (export_x3d->count() > 0) {
    if (x3d.extension() != ".x3d" || x3d.filename() == ".x3d") {
      std::cerr << "error: --export-x3d: '" << x3d.string() << "' must name a .x3d file (X3D's XML encoding; .wrl is VRML's)\n";
      return 1;
    }
    demo::Puzzle end = script.start;
    for (int piece : script.moves) end.move(piece);
    if (const Status s = write_file_atomically(x3d, demo::to_x3d(end), o.force ? Overwrite::allow : Overwrite::refuse); !s) {
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

  // Interactive: click a piece to move it, drag to turn the cube, wheel to zoom; buttons (or keys
  // S, U, R, Space) to scramble, undo, redo and solve (animated). A scramble in the window starts
  // from the current state with seed --seed + 1, then + 2, ...
  demo::Puzzle puzzle = script.start;
  std::deque<int> pending(script.moves.begin(), script.moves.end());
  std::optional<demo::PuzzleAnimation> animation;
  render::Camera camera = demo::puzzle_camera(aspect);
  std::uint64_t next_seed = seed + 1;
  std::string message;
  auto act = [&](char what) {
    // An animated move finishes first, so that the state is the one shown.
    if (animation) puzzle.move(animation->move.piece), animation.reset();
    pending.clear();
    if (what == 's') puzzle.scramble(next_seed++, 20), message = "scrambled";
    if (what == 'u') message = puzzle.undo() ? "undone" : "nothing to undo";
    if (what == 'r') message = puzzle.redo() ? "redone" : "nothing to redo";
    if (what == 'v') {
      const auto solution = demo::solve(puzzle, max_depth);
      if (solution) pending.assign(solution->begin(), solution->end()), message = "solving: " + std::to_string(solution->size()) + " moves";
      else message = "too far to solve (more than " + std::to_string(max_depth) + " moves)";
    }
  };
  return apps::run_window(o, "dqkit-puzzle", [&](const render::WindowInput& in) {
    render::orbit(camera, in);
    for (char32_t c : in.typed) {
      const char32_t key = apps::lower_case(c);
      if (key == U's' || key == U'u' || key == U'r') act(static_cast<char>(key));
      if (key == U' ') act('v');
    }
#if defined(DQKIT_DEMO_WINDOW)
    // A narrow column at the left, beside the cube.
    ImGui::SetNextWindowPos({8, 8}, ImGuiCond_Once);
    ImGui::SetNextWindowSizeConstraints({150, 0}, {150, 1e6f});
    ImGui::Begin("Puzzle", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
    const ImVec2 button{-1, 0};  // the panel's width
    if (ImGui::Button("Scramble (S)", button)) act('s');
    if (ImGui::Button("Undo (U)", button)) act('u');
    if (ImGui::Button("Redo (R)", button)) act('r');
    if (ImGui::Button("Solve (Space)", button)) act('v');
    ImGui::TextWrapped("%s, %zu moves made. %s", puzzle.solved() ? "Solved" : "Not solved", puzzle.history().size(), message.c_str());
    ImGui::Separator();
    ImGui::TextWrapped("Click a piece next to the hole to move it. Drag: turn the cube. Wheel: zoom. Esc: quit.");
    ImGui::End();
#endif
    if (in.clicked && !animation && pending.empty()) {
      const int piece = demo::pick_piece(puzzle, camera, o.width, o.height, in.click_x, in.click_y);
      if (piece >= 0 && puzzle.can_move(piece)) pending.push_back(piece), message.clear();
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
