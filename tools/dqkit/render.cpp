// dqkit render: pictures of a skinned model, headless (OpenGL 3.3 core on Mesa's EGL): LBS, DQS,
// CoR or all three side by side (each view captioned), one time or a sequence of numbered PNGs, with a camera that
// frames the whole animation so that the frames of a sequence line up; or shown in a window, where
// a drag turns the camera and the wheel moves it nearer or farther (render::orbit).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <optional>
#include <thread>

#include "commands.hpp"
#include "common.hpp"
#include "dq/render/render.hpp"
#include "dq/render/text.hpp"
#include "skinned_model.hpp"

namespace dq::cli {

namespace {

struct RenderArgs {
  SkinnedModelOptions model;
  std::optional<double> until;  ///< the last time of a sequence; none: one picture
  double fps = 30;
  std::string method = "all";
  std::string output;
  int width = 0, height = 0;
  std::string camera;
  bool skeleton = false;
  bool force = false;
  bool window = false;
};

struct CameraAngles {
  double yaw = 35, pitch = 20, distance = 0;  ///< degrees, degrees, model units (0: framing)
};

/// --camera 'yaw,pitch[,distance]': two or three finite numbers and nothing else, the pitch within
/// the orbit camera's range (render::orbit_max_pitch; it would be clamped there), the distance ≥ 0.
CameraAngles parse_camera(const std::string& text) {
  const std::string usage = "--camera must be 'yaw,pitch' or 'yaw,pitch,distance' (degrees, degrees, model units; 0 or none: "
                            "the distance that frames the animation), got '" + text + "'";
  double values[3] = {0, 0, 0};
  std::size_t count = 0, start = 0;
  for (;;) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    if (count == 3) throw Failure(usage);
    const char *first = text.data() + start, *last = text.data() + comma;
    const auto r = std::from_chars(first, last, values[count]);
    if (first == last || r.ec != std::errc() || r.ptr != last || !std::isfinite(values[count])) throw Failure(usage);
    ++count;
    if (comma == text.size()) break;
    start = comma + 1;
  }
  if (count < 2) throw Failure(usage);
  const double max_pitch = render::orbit_max_pitch * 180 / std::numbers::pi;
  if (std::abs(values[1]) > max_pitch) {
    char limit[32];
    std::snprintf(limit, sizeof limit, "%.2f", max_pitch);
    throw Failure("--camera: the pitch " + CLI::detail::to_string(values[1]) + "° is beyond ±" + limit +
                  "° (the orbit camera's range: straight down or up, the view's up would be undefined)");
  }
  if (values[2] < 0) throw Failure("--camera: the distance " + CLI::detail::to_string(values[2]) + " is negative");
  return {values[0], values[1], values[2]};
}

int run_render(const RenderArgs& a) {
  std::vector<SkinningMethod> methods{SkinningMethod::lbs, SkinningMethod::dqs, SkinningMethod::cor};
  if (a.method != "all") methods = {method_named(a.method)};
  // A .png name with a stem (".png" alone names a hidden file without one); the extension in any case.
  if (!a.window && lowercase_extension(a.output) != ".png") throw Failure("--out must name a .png file (or use --window)");
  const int width = a.width > 0 ? a.width : (methods.size() > 1 ? 1200 : 800);
  const int height = a.height > 0 ? a.height : (methods.size() > 1 ? 400 : 600);
  const CameraAngles view = a.camera.empty() ? CameraAngles{} : parse_camera(a.camera);
  const double yaw = view.yaw, pitch = view.pitch, distance = view.distance;
  // The times to draw; a sequence writes NAME_0000.png, NAME_0001.png, ...
  std::vector<double> times{a.model.time};
  if (a.until) {
    if (*a.until < a.model.time)
      throw Failure("--until (" + CLI::detail::to_string(*a.until) + " s) is before --time (" + CLI::detail::to_string(a.model.time) + " s)");
    const auto count = static_cast<std::size_t>(std::floor((*a.until - a.model.time) * a.fps + 1e-9)) + 1;
    if (count > 100000) throw Failure("--until: the sequence would have more than 100000 frames");
    times.clear();
    for (std::size_t i = 0; i < count; ++i) times.push_back(a.model.time + static_cast<double>(i) / a.fps);
  }
  const std::string stem = a.output.substr(0, a.output.size() - 4);
  // With --until, always NAME_0000.png ...: a script knows the names whatever the clip's length.
  const bool sequence = a.until.has_value();
  auto name_of = [&](std::size_t i) {
    if (!sequence) return a.output;
    char suffix[32];
    std::snprintf(suffix, sizeof suffix, "_%04zu.png", i);
    return stem + suffix;
  };
  if (!a.window)
    for (std::size_t i = 0; i < times.size(); ++i) {
      const std::string name = name_of(i);
      if (std::filesystem::is_directory(name)) throw Failure(name + ": is a directory");
      if (!a.force && std::filesystem::exists(name))
        throw Failure(name + ": already exists; it is replaced only when asked (--force: a regular file only)");
    }

  SkinnedModel m = load_skinned_model(a.model);
  SkinningThreads threads(std::max(1u, std::min(4u, std::thread::hardware_concurrency())));
  SkinnedFrame frame = m.skins.make_frame();
  std::vector<DualQuaternion<double>> world;
  auto skin_at = [&](double t, SkinningMethod method) {
    if (Status s = pose_at(m.scene, a.model.animation, t, world); !s) throw Failure(a.model.file + ": " + s.error().message);
    if (Status s = m.skins.skin(world, method, threads, frame); !s) throw Failure(a.model.file + ": " + s.error().message);
  };
  // The camera frames every frame of the animation with every method drawn.
  render::Bounds bounds;
  const Animation* anim = m.scene.animations.empty() ? nullptr : &m.scene.animations[a.model.animation].animation;
  const std::size_t frames = anim ? std::max<std::size_t>(anim->frame_count, 1) : 1;
  // Past the clip's end every frame would show its last pose: the sequence stops there.
  const double clip_end = anim ? static_cast<double>(frames - 1) * anim->frame_time : 0.0;
  if (a.until && *a.until > clip_end + 1e-9 && times.size() > 1) {
    const std::size_t before = times.size();
    while (times.size() > 1 && times.back() > clip_end + 1e-9) times.pop_back();
    std::fprintf(stderr, "dqkit: warning: --until: the %s at %s s; the sequence stops there (%zu of %zu frames)\n",
                 anim ? "clip ends" : "model has no animation: it is still", CLI::detail::to_string(anim ? clip_end : a.model.time).c_str(),
                 times.size(), before);
  }
  for (std::size_t f = 0; f < frames; ++f)
    for (SkinningMethod method : methods) {
      skin_at(anim ? static_cast<double>(f) * anim->frame_time : 0, method);
      for (std::size_t v = 0; v < frame.size(); ++v) bounds.add({static_cast<double>(frame.px[v]), static_cast<double>(frame.py[v]), static_cast<double>(frame.pz[v])});
    }
  const std::vector<render::Viewport> viewports = render::columns(width, height, static_cast<int>(methods.size()));
  const double aspect = double(viewports[0].width) / double(viewports[0].height);
  const double deg = std::numbers::pi / 180;
  render::Camera camera = render::Camera::framing(bounds, aspect, yaw * deg, pitch * deg);
  if (distance > 0) {
    // Beyond 10^4 times the framing distance the model is under a pixel (and at 1e308 the depth
    // range vanished: a blank picture); near it, the near plane keeps 1e-4 of the model's size
    // (inside the model, 1e-12 of it left no depth precision).
    if (distance > 1e4 * camera.distance)
      throw Failure("--camera: at the distance " + CLI::detail::to_string(distance) + " the model would be smaller than a pixel (it fills the view at " +
                    CLI::detail::to_string(camera.distance) + ")");
    camera.distance = distance;
    camera.near_plane = std::max({distance - 2 * bounds.radius(), distance * 1e-3, bounds.radius() * 1e-4});
    camera.far_plane = distance + 2 * bounds.radius();
  }
  const render::RenderOptions options{width, height, 4, {1, 1, 1, 1}};
  Expected<render::Renderer> renderer = a.window ? render::Renderer::create_window(options, "dqkit render " + a.model.file)
                                                 : render::Renderer::create(options);
  if (!renderer) throw Failure(renderer.error().message);
  // LBS red, DQS blue, CoR green (the order of SkinningMethod).
  const render::Color colors[] = {{0.85f, 0.45f, 0.35f, 1}, {0.35f, 0.55f, 0.85f, 1}, {0.40f, 0.72f, 0.42f, 1}};
  const char* const names[] = {"LBS", "DQS", "COR"};
  render::Scene drawn;
  drawn.meshes.resize(1);
  drawn.meshes[0].triangles = frame.triangles;
  Progress progress("dqkit: rendering", times.size());
  // In a window the frames play in a loop until the window is closed; the mouse orbits the camera.
  for (std::size_t i = 0; i < times.size(); i = a.window ? (i + 1) % times.size() : i + 1) {
    render::orbit(camera, renderer->input());
    renderer->clear();
    for (std::size_t k = 0; k < methods.size(); ++k) {
      skin_at(times[i], methods[k]);
      render::Mesh& mesh = drawn.meshes[0];
      mesh.positions.resize(frame.size());
      for (std::size_t v = 0; v < frame.size(); ++v) mesh.positions[v] = {frame.px[v], frame.py[v], frame.pz[v]};
      mesh.color = colors[static_cast<int>(methods[k])];
      drawn.lines.clear();
      if (a.skeleton) {
        render::Lines bones{{}, {0.1f, 0.1f, 0.1f, 1}, true};
        const auto parents = m.scene.skeleton.parents();
        for (std::size_t j = 0; j < parents.size(); ++j)
          if (parents[j] >= 0) {
            const Vec3<double> p = world[static_cast<std::size_t>(parents[j])].translation(), c = world[j].translation();
            bones.points.push_back({float(p.x), float(p.y), float(p.z)});
            bones.points.push_back({float(c.x), float(c.y), float(c.z)});
          }
        drawn.lines.push_back(std::move(bones));
      }
      if (methods.size() > 1) {  // side by side, each view says which method it shows
        render::Lines caption{{}, {0.1f, 0.1f, 0.1f, 1}, true};
        render::add_overlay_text(caption, camera, aspect, names[static_cast<int>(methods[k])], -0.92, 0.82, 0.09);
        drawn.lines.push_back(std::move(caption));
      }
      renderer->draw(drawn, camera, viewports[k]);
    }
    if (a.window) {
      if (!renderer->present()) return 0;
      continue;
    }
    if (Status s = renderer->read().write_png(name_of(i)); !s) throw Failure(s.error().message);
    progress.update(i + 1);
  }
  return 0;
}

}  // namespace

Runner define_render(CLI::App& c) {
  auto a = std::make_shared<RenderArgs>();
  add_skinned_model_options(c, a->model);
  CLI::Option* until = c.add_option("--until", a->until, "Last time of a frame sequence, written as OUT_0000.png, OUT_0001.png, ... (numbered even if one frame; at most to the clip's end)")
                          ->check(finite_in(-1e9, 1e9));
  c.add_option("--fps", a->fps, "Frames per second of a sequence")->check(finite_in(0, 1000))->needs(until);
  c.add_option("--method", a->method, "lbs, dqs, cor, or all: the three side by side (LBS, DQS, CoR from the left)")
      ->check(CLI::IsMember({"lbs", "dqs", "cor", "all"}));
  CLI::Option* out = c.add_option("--out", a->output, "PNG file to write (required unless --window)")->check(file_name());
  c.add_option("--width", a->width, "Image width in pixels (default 1200 for all, else 800)")->check(CLI::Range(1, render::max_image_side));
  c.add_option("--height", a->height, "Image height in pixels (default 400 for all, else 600)")->check(CLI::Range(1, render::max_image_side));
  c.add_option("--camera", a->camera, "Orbit camera 'yaw,pitch[,distance]', degrees (default 35,20 at the distance that frames the whole animation)");
  c.add_flag("--skeleton", a->skeleton, "Draw the bones as lines over the skin");
  c.add_flag("--force", a->force, "Replace the output files if they exist");
  c.add_flag("--window", a->window, "Show the frames in a window, in a loop until it is closed or Escape (needs a display), instead of writing PNGs; drag to turn the camera, wheel to zoom")
      ->excludes(out);
  return [a] { return run_render(*a); };
}

}  // namespace dq::cli
