// A consumer of dqkit: the algebra (header-only), a skeleton (dqkit::anim), BVH (dqkit::io), a
// skin (dqkit::skin), when built with DQKIT_CONSUMER_RENDER a headless picture (dqkit::render)
// and, with DQKIT_CONSUMER_IMPORT, an isolated import of the file given as argument
// (dqkit::import; the worker is looked up as an installed program would).
#include <dq/dq.hpp>
#include <dq/io/bvh.hpp>
#include <dq/skin/shapes.hpp>
#include <dq/skin/skinning.hpp>
#include <dq/simd/batch.hpp>
#ifdef DQKIT_CONSUMER_RENDER
#include <dq/render/render.hpp>
#endif
#ifdef DQKIT_CONSUMER_IMPORT
#include <dq/io/scene.hpp>
#endif

#include <cmath>
#include <cstdio>
#include <vector>

int main(int argc, char** argv) {
  const auto turn = dq::DualQuaternion<double>::from_rotation(
      dq::Quaternion<double>::from_axis_angle({0, 0, 1}, std::numbers::pi / 2));
  const auto shift = dq::DualQuaternion<double>::from_translation({1, 0, 0});
  const dq::Vec3<double> p = (shift * turn).transform_point({1, 0, 0});
  if (!(std::abs(p.x - 1) < 1e-15 && std::abs(p.y - 1) < 1e-15)) return 1;
  dq::RawSkeleton raw;
  raw.add("root", -1);
  raw.add("child", 0, shift);
  if (!dq::build_skeleton(raw)) return 2;
  const auto bvh = dq::read_bvh("HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 3 Zrotation Xrotation Yrotation\n"
                                "End Site\n{\nOFFSET 0 1 0\n}\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\n90 0 0\n");
  if (!bvh || !dq::bvh_skeleton(*bvh)) return 3;
  const dq::CylinderShape cylinder;
  const auto skin = dq::build_skin(dq::two_bone_cylinder(cylinder));
  if (!skin || skin->vertex_count() != static_cast<std::size_t>(cylinder.rings * cylinder.segments + 2)) return 5;
  // Both bones moved by (0, 1, 0): every vertex moves by it, with DQS as with any method.
  const std::vector<dq::DualQuaternion<double>> bones(2, dq::DualQuaternion<double>::from_translation({0, 1, 0}));
  dq::SkinPalette palette(2);
  dq::update_palette(*skin, bones, palette);
  std::vector<float> x(skin->vertex_count()), y(x.size()), z(x.size());
  const dq::SkinningJob job{.skin = &*skin, .palette = &palette, .out = {.px = x, .py = y, .pz = z}, .count = x.size()};
  if (!job.validate()) return 5;
  job.run();
  if (!(std::abs(y[0] - (skin->py()[0] + 1)) < 1e-5f)) return 5;
  // The batch kernels of the CPU's widest instruction set: 37 compositions of a quarter turn about
  // z with itself (whole vectors and a tail) give the half turn (0, 0, 0, 1).
  const float c = std::sqrt(0.5f);
  std::vector<float> part(37, c), zero(37, 0), rw(37), rx(37), ry(37), rz(37), dw(37), dx(37), dy(37), dz(37);
  const dq::simd::ConstRows quarter{part.data(), zero.data(), zero.data(), part.data(), zero.data(), zero.data(), zero.data(), zero.data()};
  dq::simd::compose(quarter, quarter, {rw.data(), rx.data(), ry.data(), rz.data(), dw.data(), dx.data(), dy.data(), dz.data()}, 37);
  for (std::size_t i = 0; i < 37; ++i)
    if (!(std::abs(rz[i] - 1) < 1e-6f && std::abs(rw[i]) < 1e-6f)) return 8;
#ifdef DQKIT_CONSUMER_RENDER
  // A triangle over the image's centre, seen head-on: the centre pixel takes its colour.
  auto renderer = dq::render::Renderer::create({.width = 64, .height = 64, .samples = 1});
  if (!renderer) {
    std::printf("%s\n", renderer.error().message.c_str());
    return 6;
  }
  dq::render::Scene scene;
  scene.meshes.push_back({.positions = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}}, .triangles = {0, 1, 2}, .color = {1, 0, 0, 1}});
  renderer->clear();
  renderer->draw(scene, dq::render::Camera{.distance = 3, .yaw = 0, .pitch = 0});
  const auto centre = renderer->read().pixel(32, 32);
  if (!(centre[0] > 100 && centre[1] < 60 && centre[2] < 60)) return 7;
  std::printf("rendered\n");
#endif
#ifdef DQKIT_CONSUMER_IMPORT
  if (argc > 1) {
    const dq::Expected<dq::ImportedScene> scene = dq::import_scene(argv[1]);
    if (!scene) {
      std::printf("%s\n", scene.error().message.c_str());
      return 4;
    }
    std::printf("imported %zu joints\n", scene->skeleton.size());
  }
#endif
  (void)argc, (void)argv;
  std::printf("ok\n");
  return 0;
}
