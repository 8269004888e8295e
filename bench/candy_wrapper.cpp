// The candy-wrapper comparison (docs/skinning.md): a capped cylinder on two bones, twisted from 0°
// to 180° and bent to 90° and 150°, skinned by LBS, DQS and CoR. Prints the table as Markdown:
// enclosed volume relative to the rest pose, and the smallest and largest distance of the
// cylinder's surface from the bones (the two segments; both are the radius for a rigid tube:
// below it the skin collapses, the candy wrapper; above it, it bulges). With --pictures DIR,
// renders each pose side by side (LBS, DQS, CoR).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <string>

#include "dq/skin/shapes.hpp"
#include "dq/skin/skinning.hpp"
#if defined(DQKIT_HAVE_RENDER)
#include "dq/render/render.hpp"
#include "dq/render/text.hpp"
#endif

using namespace dq;

namespace {

struct Pose {
  const char* name;
  double twist_degrees, bend_degrees;
};

struct Measure {
  double volume, min_radius, max_radius;
};

/// Signed volume enclosed by the triangles (divergence theorem), in double.
double volume(const std::vector<float>& x, const std::vector<float>& y, const std::vector<float>& z, std::span<const std::uint32_t> tri) {
  double v = 0;
  for (std::size_t t = 0; t + 2 < tri.size(); t += 3) {
    const Vec3<double> a{x[tri[t]], y[tri[t]], z[tri[t]]}, b{x[tri[t + 1]], y[tri[t + 1]], z[tri[t + 1]]}, c{x[tri[t + 2]], y[tri[t + 2]], z[tri[t + 2]]};
    v += dot(a, cross(b, c)) / 6;
  }
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  const char* pictures = nullptr;
  for (int i = 1; i < argc; ++i)
    if (std::strcmp(argv[i], "--pictures") == 0 && i + 1 < argc) pictures = argv[++i];
  const CylinderShape shape;
  const Expected<Skin> skin = build_skin(two_bone_cylinder(shape));
  if (!skin) {
    std::fprintf(stderr, "candy_wrapper: %s\n", skin.error().message.c_str());
    return 1;
  }
  const std::size_t n = skin->vertex_count();
  const double joint = shape.length / 2;
  const auto side = static_cast<std::size_t>(shape.rings) * static_cast<std::size_t>(shape.segments);  // the caps come after
  SkinPalette palette(2);
  SkinningThreads threads(1);
  std::vector<float> px(n), py(n), pz(n);
  const SkinnedVertices out{.px = px, .py = py, .pz = pz};
  const Pose poses[] = {{"rest", 0, 0},           {"twist 30°", 30, 0},   {"twist 60°", 60, 0},  {"twist 90°", 90, 0},
                        {"twist 120°", 120, 0},   {"twist 150°", 150, 0}, {"twist 180°", 180, 0}, {"bend 90°", 0, 90},
                        {"bend 150°", 0, 150},    {"bend 90° + twist 90°", 90, 90}};
  const SkinningMethod methods[] = {SkinningMethod::lbs, SkinningMethod::dqs, SkinningMethod::cor};
  const double deg = std::numbers::pi / 180;
  double rest_volume = 0;
  std::printf("| pose | LBS volume | DQS volume | CoR volume | LBS distance min / max | DQS distance min / max | CoR distance min / max |\n");
  std::printf("| --- | ---: | ---: | ---: | ---: | ---: | ---: |\n");
  auto pose_world = [&](const Pose& p) {
    // Bone 1 turns about the joint: twist about the bone's axis (x), then bend about z.
    const Quaternion<double> r = Quaternion<double>::from_axis_angle({0, 0, 1}, p.bend_degrees * deg) *
                                 Quaternion<double>::from_axis_angle({1, 0, 0}, p.twist_degrees * deg);
    const DualQuaternion<double> about_joint = DualQuaternion<double>::from_translation({joint, 0, 0}) * DualQuaternion<double>::from_rotation(r);
    return std::vector<DualQuaternion<double>>{DualQuaternion<double>{}, about_joint};
  };
  // Distance from the bones: segment 0 from the origin to the joint, segment 1 from the joint
  // along the posed bone 1 for half the length.
  auto distance_to_bones = [&](const DualQuaternion<double>& bone1, const Vec3<double>& p) {
    auto to_segment = [&](const Vec3<double>& a, const Vec3<double>& b) {
      const Vec3<double> d = b - a;
      const double t = std::clamp(dot(p - a, d) / dot(d, d), 0.0, 1.0);
      return norm(p - (a + d * t));
    };
    const Vec3<double> j{joint, 0, 0};
    return std::min(to_segment({0, 0, 0}, j), to_segment(j, bone1.transform_point({2 * joint, 0, 0}) - Vec3<double>{0, 0, 0}));
  };
  for (const Pose& p : poses) {
    update_palette(*skin, pose_world(p), palette);
    Measure m[3];
    for (int k = 0; k < 3; ++k) {
      if (!threads.run({&*skin, &palette, methods[k], out, 0, n})) return 1;
      m[k].volume = volume(px, py, pz, skin->triangles());
      m[k].min_radius = 1e300, m[k].max_radius = 0;
      const DualQuaternion<double> bone1 = pose_world(p)[1] * DualQuaternion<double>::from_translation({-joint, 0, 0});
      for (std::size_t v = 0; v < side; ++v) {
        const double r = distance_to_bones(bone1, {double(px[v]), double(py[v]), double(pz[v])});
        m[k].min_radius = std::min(m[k].min_radius, r), m[k].max_radius = std::max(m[k].max_radius, r);
      }
    }
    if (p.twist_degrees == 0 && p.bend_degrees == 0) rest_volume = m[0].volume;
    std::printf("| %s | %.3f | %.3f | %.3f | %.3f / %.3f | %.3f / %.3f | %.3f / %.3f |\n", p.name, m[0].volume / rest_volume,
                m[1].volume / rest_volume, m[2].volume / rest_volume, m[0].min_radius, m[0].max_radius, m[1].min_radius, m[1].max_radius,
                m[2].min_radius, m[2].max_radius);
  }
  std::printf("\nCylinder: radius %g, length %g, %d rings of %d vertices, weights blended over ±%g about the joint (smoothstep); "
              "volume relative to the rest pose (%.4f; the exact cylinder: %.4f); distance: of the side surface's vertices from the two bone segments (a rigid tube: %g).\n",
              shape.radius, shape.length, shape.rings, shape.segments, shape.blend, rest_volume,
              std::numbers::pi * shape.radius * shape.radius * shape.length, shape.radius);
#if defined(DQKIT_HAVE_RENDER)
  if (pictures) {
    Expected<render::Renderer> renderer = render::Renderer::create({1200, 400, 4, {1, 1, 1, 1}});
    if (!renderer) {
      std::fprintf(stderr, "candy_wrapper: %s\n", renderer.error().message.c_str());
      return 1;
    }
    const render::Color colors[] = {{0.85f, 0.45f, 0.35f, 1}, {0.35f, 0.55f, 0.85f, 1}, {0.40f, 0.72f, 0.42f, 1}};
    const Pose shown[] = {{"twist180", 180, 0}, {"bend90", 0, 90}, {"bend150", 0, 150}, {"bend90_twist90", 90, 90}};
    const auto viewports = render::columns(1200, 400, 3);
    for (const Pose& p : shown) {
      update_palette(*skin, pose_world(p), palette);
      renderer->clear();
      std::vector<render::Scene> scenes(3);
      render::Bounds bounds;  // all three, so that they are drawn at the same scale
      for (std::size_t k = 0; k < 3; ++k) {
        if (!threads.run({&*skin, &palette, methods[k], out, 0, n})) return 1;
        render::Mesh mesh;
        for (std::size_t v = 0; v < n; ++v) mesh.positions.push_back({px[v], py[v], pz[v]});
        mesh.triangles.assign(skin->triangles().begin(), skin->triangles().end());
        mesh.color = colors[k];
        bounds.add(mesh.bounds());
        scenes[k].meshes.push_back(std::move(mesh));
      }
      // From the front, slightly above (bends are in the xy plane).
      const render::Camera camera = render::Camera::framing(bounds, 1.0, 0.25, 0.3, 0.7, 0.0);
      const char* const names[] = {"LBS", "DQS", "COR"};
      for (std::size_t k = 0; k < 3; ++k) {
        render::Lines caption{{}, {0.1f, 0.1f, 0.1f, 1}, true};
        render::add_overlay_text(caption, camera, 1.0, names[k], -0.92, 0.82, 0.09);
        scenes[k].lines.push_back(std::move(caption));
        renderer->draw(scenes[k], camera, viewports[k]);
      }
      const std::string path = std::string(pictures) + "/candy_" + p.name + ".png";
      if (Status s = renderer->read().write_png(path); !s) {
        std::fprintf(stderr, "candy_wrapper: %s\n", s.error().message.c_str());
        return 1;
      }
      std::fprintf(stderr, "wrote %s\n", path.c_str());
    }
  }
#else
  if (pictures) std::fprintf(stderr, "candy_wrapper: built without dqkit::render: no pictures\n");
#endif
  return 0;
}
