#include "dq/skin/shapes.hpp"

#include <algorithm>
#include <cmath>

namespace dq {

RawSkin two_bone_cylinder(const CylinderShape& c) {
  RawSkin s;
  const double pi = std::acos(-1.0), joint = c.length / 2;
  const auto rings = static_cast<std::uint32_t>(c.rings), segments = static_cast<std::uint32_t>(c.segments);
  auto add = [&](Vec3<double> p, Vec3<double> n, double w1) {
    s.positions.push_back({float(p.x), float(p.y), float(p.z)});
    s.normals.push_back({float(n.x), float(n.y), float(n.z)});
    s.tangents.push_back({1, 0, 0});
    if (w1 < 1) s.influences.push_back({0, float(1 - w1)});
    if (w1 > 0) s.influences.push_back({1, float(w1)});
    s.influence_offsets.push_back(static_cast<std::uint32_t>(s.influences.size()));
  };
  auto weight1 = [&](double x) {
    const double u = std::clamp((x - (joint - c.blend)) / (2 * c.blend), 0.0, 1.0);
    return u * u * (3 - 2 * u);
  };
  s.influence_offsets.push_back(0);
  for (std::uint32_t r = 0; r < rings; ++r) {
    const double x = c.length * r / (rings - 1);
    for (std::uint32_t k = 0; k < segments; ++k) {
      const double a = 2 * pi * k / segments;
      add({x, c.radius * std::cos(a), c.radius * std::sin(a)}, {0, std::cos(a), std::sin(a)}, weight1(x));
    }
  }
  const std::uint32_t cap0 = rings * segments, cap1 = cap0 + 1;
  add({0, 0, 0}, {-1, 0, 0}, 0);
  add({c.length, 0, 0}, {1, 0, 0}, 1);
  auto tri = [&](std::uint32_t a, std::uint32_t b, std::uint32_t d) { s.triangles.insert(s.triangles.end(), {a, b, d}); };
  for (std::uint32_t r = 0; r + 1 < rings; ++r)
    for (std::uint32_t k = 0; k < segments; ++k) {
      const std::uint32_t a = r * segments + k, b = r * segments + (k + 1) % segments;
      tri(a, b, b + segments);  // outward (the ring turns from +y to +z)
      tri(a, b + segments, a + segments);
    }
  for (std::uint32_t k = 0; k < segments; ++k) {
    tri(cap0, (k + 1) % segments, k);
    const std::uint32_t last = (rings - 1) * segments;
    tri(cap1, last + k, last + (k + 1) % segments);
  }
  s.inverse_bind = {Mat4<double>::identity(), Mat4<double>::identity()};
  s.inverse_bind[1](0, 3) = -joint;
  return s;
}

}  // namespace dq
