// Images, bounds, normals and viewports of dqkit::render (no OpenGL here).
#include <stb_image_write.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "dq/io/file.hpp"
#include "dq/render/render.hpp"

namespace dq::render {

void Bounds::add(const Vec3<double>& p) {
  lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
  hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
}

void Bounds::add(const Bounds& b) {
  if (b.empty()) return;
  add(b.lo);
  add(b.hi);
}

Bounds Mesh::bounds() const {
  Bounds b;
  for (const Vec3<float>& p : positions) b.add(p.cast<double>());
  return b;
}

Bounds Scene::bounds() const {
  Bounds b;
  for (const Mesh& m : meshes) b.add(m.bounds());
  for (const Lines& l : lines)
    for (const Vec3<float>& p : l.points) b.add(p.cast<double>());
  for (const Points& s : points)
    for (const Vec3<float>& p : s.positions) b.add(p.cast<double>());
  return b;
}

std::array<std::uint8_t, 4> Image::pixel(int x, int y) const {
  const std::size_t i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) * 4;
  return {rgba[i], rgba[i + 1], rgba[i + 2], rgba[i + 3]};
}

Status Image::write_png(const std::filesystem::path& path) const {
  if (width <= 0 || height <= 0 || rgba.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4)
    return Error{path.string() + ": the image is empty or inconsistent"};
  // Encoded in memory, then written as every dqkit output is (OutputFile: nothing left behind on
  // an error or a kill, only a regular file replaced).
  std::string png;
  const auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
  };
  if (!stbi_write_png_to_func(append, &png, width, height, 4, rgba.data(), width * 4)) return Error{path.string() + ": cannot encode the PNG"};
  return write_file_atomically(path, png, Overwrite::allow);
}

std::vector<Vec3<float>> vertex_normals(const std::vector<Vec3<float>>& positions, const std::vector<std::uint32_t>& triangles) {
  std::vector<Vec3<float>> n(positions.size(), Vec3<float>{0, 0, 0});
  for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
    const std::uint32_t a = triangles[t], b = triangles[t + 1], c = triangles[t + 2];
    if (a >= positions.size() || b >= positions.size() || c >= positions.size()) continue;
    const Vec3<float> face = cross(positions[b] - positions[a], positions[c] - positions[a]);  // length: twice the area
    n[a] += face, n[b] += face, n[c] += face;
  }
  for (Vec3<float>& v : n) {
    const float l = norm(v);
    v = l > 0 ? v / l : Vec3<float>{0, 0, 1};
  }
  return n;
}

std::vector<Viewport> columns(int width, int height, int count) {
  std::vector<Viewport> out;
  for (int i = 0; i < count; ++i) out.push_back({i * width / count, 0, (i + 1) * width / count - i * width / count, height});
  return out;
}

}  // namespace dq::render
