// Writing a skinned frame: CSV, OBJ, PLY and glTF 2.0 (through tinygltf, Debian libtinygltf-dev).
#if !defined(DQKIT_NO_TINYGLTF)
#include <tiny_gltf.h>
#endif

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <limits>
#include <sstream>

#include "dq/skin/scene_skin.hpp"

namespace dq {

Expected<MeshFormat> parse_mesh_format(const std::string& name) {
  if (name == "csv") return MeshFormat::csv;
  if (name == "obj") return MeshFormat::obj;
  if (name == "ply") return MeshFormat::ply;
  if (name == "gltf") return MeshFormat::gltf;
  return Error{"unknown format '" + name + "' (use csv, obj, ply or gltf)"};
}

namespace {

void append(std::string& out, const char* format, auto... values) {
  char line[160];
  const int n = std::snprintf(line, sizeof line, format, values...);
  out.append(line, static_cast<std::size_t>(std::max(0, n)));
}

#if defined(DQKIT_NO_TINYGLTF)
Expected<std::string> to_gltf(const SkinnedFrame&) { return Error{"glTF output needs tinygltf (Debian libtinygltf-dev) when dqkit is built"}; }
#else
Expected<std::string> to_gltf(const SkinnedFrame& f) {
  const std::size_t n = f.size();
  const bool normals = !f.nx.empty();
  tinygltf::Model model;
  tinygltf::Buffer buffer;
  auto push = [&](const void* data, std::size_t bytes) {
    const std::size_t at = buffer.data.size();
    buffer.data.resize(at + bytes);
    std::memcpy(buffer.data.data() + at, data, bytes);
    return at;
  };
  std::vector<float> xyz(3 * n);
  float lo[3] = {std::numeric_limits<float>::max(), std::numeric_limits<float>::max(), std::numeric_limits<float>::max()};
  float hi[3] = {-lo[0], -lo[1], -lo[2]};
  for (std::size_t v = 0; v < n; ++v) {
    const float p[3] = {f.px[v], f.py[v], f.pz[v]};
    for (int c = 0; c < 3; ++c) {
      xyz[3 * v + static_cast<std::size_t>(c)] = p[c];
      lo[c] = std::min(lo[c], p[c]);
      hi[c] = std::max(hi[c], p[c]);
    }
  }
  auto view = [&](std::size_t offset, std::size_t bytes, int target) {
    tinygltf::BufferView bv;
    bv.buffer = 0;
    bv.byteOffset = offset;
    bv.byteLength = bytes;
    bv.target = target;
    model.bufferViews.push_back(bv);
    return static_cast<int>(model.bufferViews.size() - 1);
  };
  auto accessor = [&](int view_index, int component, std::size_t count, int type) {
    tinygltf::Accessor a;
    a.bufferView = view_index;
    a.componentType = component;
    a.count = count;
    a.type = type;
    model.accessors.push_back(a);
    return static_cast<int>(model.accessors.size() - 1);
  };
  tinygltf::Primitive prim;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  const int pos = accessor(view(push(xyz.data(), xyz.size() * sizeof(float)), xyz.size() * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER),
                           TINYGLTF_COMPONENT_TYPE_FLOAT, n, TINYGLTF_TYPE_VEC3);
  model.accessors[static_cast<std::size_t>(pos)].minValues = {static_cast<double>(lo[0]), static_cast<double>(lo[1]), static_cast<double>(lo[2])};
  model.accessors[static_cast<std::size_t>(pos)].maxValues = {static_cast<double>(hi[0]), static_cast<double>(hi[1]), static_cast<double>(hi[2])};
  prim.attributes["POSITION"] = pos;
  if (normals) {
    for (std::size_t v = 0; v < n; ++v) xyz[3 * v] = f.nx[v], xyz[3 * v + 1] = f.ny[v], xyz[3 * v + 2] = f.nz[v];
    prim.attributes["NORMAL"] = accessor(view(push(xyz.data(), xyz.size() * sizeof(float)), xyz.size() * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER),
                                         TINYGLTF_COMPONENT_TYPE_FLOAT, n, TINYGLTF_TYPE_VEC3);
  }
  if (!f.triangles.empty()) {
    const std::size_t bytes = f.triangles.size() * sizeof(std::uint32_t);
    prim.indices = accessor(view(push(f.triangles.data(), bytes), bytes, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
                            TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, f.triangles.size(), TINYGLTF_TYPE_SCALAR);
  }
  model.buffers.push_back(std::move(buffer));
  tinygltf::Mesh mesh;
  mesh.name = "skinned";
  mesh.primitives.push_back(prim);
  model.meshes.push_back(mesh);
  tinygltf::Node node;
  node.mesh = 0;
  model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes.push_back(0);
  model.scenes.push_back(scene);
  model.defaultScene = 0;
  model.asset.version = "2.0";
  model.asset.generator = "dqkit";
  std::ostringstream out;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&model, out, true, false)) return Error{"tinygltf could not write the glTF"};
  return out.str();
}
#endif

}  // namespace

Expected<std::string> format_frame(const SkinnedFrame& f, MeshFormat format) {
  const std::size_t n = f.size();
  const bool normals = !f.nx.empty();
  std::string out;
  switch (format) {
    case MeshFormat::csv:
      out = "vertex,x,y,z\r\n";  // CRLF, as RFC 4180 and dqkit fk's CSV
      for (std::size_t v = 0; v < n; ++v) append(out, "%zu,%.9g,%.9g,%.9g\r\n", v, double(f.px[v]), double(f.py[v]), double(f.pz[v]));
      return out;
    case MeshFormat::obj:
      out = "# dqkit skinned frame\n";
      for (std::size_t v = 0; v < n; ++v) append(out, "v %.9g %.9g %.9g\n", double(f.px[v]), double(f.py[v]), double(f.pz[v]));
      if (normals)
        for (std::size_t v = 0; v < n; ++v) append(out, "vn %.9g %.9g %.9g\n", double(f.nx[v]), double(f.ny[v]), double(f.nz[v]));
      for (std::size_t t = 0; t + 2 < f.triangles.size(); t += 3) {
        const std::uint32_t a = f.triangles[t] + 1, b = f.triangles[t + 1] + 1, c = f.triangles[t + 2] + 1;
        if (normals)
          append(out, "f %u//%u %u//%u %u//%u\n", a, a, b, b, c, c);
        else
          append(out, "f %u %u %u\n", a, b, c);
      }
      return out;
    case MeshFormat::ply:
      out = "ply\nformat ascii 1.0\ncomment dqkit skinned frame\nelement vertex " + std::to_string(n) +
            "\nproperty float x\nproperty float y\nproperty float z\n";
      if (normals) out += "property float nx\nproperty float ny\nproperty float nz\n";
      out += "element face " + std::to_string(f.triangles.size() / 3) + "\nproperty list uchar uint vertex_indices\nend_header\n";
      for (std::size_t v = 0; v < n; ++v) {
        append(out, "%.9g %.9g %.9g", double(f.px[v]), double(f.py[v]), double(f.pz[v]));
        if (normals) append(out, " %.9g %.9g %.9g", double(f.nx[v]), double(f.ny[v]), double(f.nz[v]));
        out += '\n';
      }
      for (std::size_t t = 0; t + 2 < f.triangles.size(); t += 3) append(out, "3 %u %u %u\n", f.triangles[t], f.triangles[t + 1], f.triangles[t + 2]);
      return out;
    case MeshFormat::gltf:
      return to_gltf(f);
  }
  return Error{"unknown format"};
}

}  // namespace dq
