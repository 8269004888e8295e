#include "dq/render/text.hpp"

#include <cctype>
#include <cmath>
#include <string_view>

namespace dq::render {
namespace {

// Each glyph: polylines separated by spaces, each a sequence of points given as two digits
// (x in 0..4, y in 0..6).
std::string_view strokes(char c) {
  switch (std::toupper(static_cast<unsigned char>(c))) {
    case '0': case 'O': return "0040460600";
    case '1': return "152620 1030";
    case '2': return "064643030040";
    case '3': return "06464000 1343";
    case '4': return "060343 4640";
    case '5': case 'S': return "460603434000";
    case '6': return "460600404303";
    case '7': return "064640";
    case '8': return "0040460600 0343";
    case '9': return "430306464000";
    case 'A': return "0004264440 0242";
    case 'B': return "000636453303 3342413000";
    case 'C': return "4606000040";
    case 'D': return "00063645413000";
    case 'E': return "4606000040 0333";
    case 'F': return "460600 0333";
    case 'G': return "46060000404323";
    case 'H': return "0006 4640 0343";
    case 'I': return "0646 2620 0040";
    case 'J': return "4641301001";
    case 'K': return "0006 4602 1340";
    case 'L': return "060040";
    case 'M': return "0006234640";
    case 'N': return "00064046";
    case 'P': return "0006464303";
    case 'Q': return "0040460600 2240";
    case 'R': return "0006464303 2340";
    case 'T': return "0646 2620";
    case 'U': return "06004046";
    case 'V': return "062046";
    case 'W': return "0610233046";
    case 'X': return "0046 0640";
    case 'Y': return "0623 4623 2320";
    case 'Z': return "06460040";
    case '.': return "2021";
    case ':': return "2122 2425";
    case '-': return "1333";
    case '/': return "0046";
    case '(': return "36242230";
    case ')': return "16242210";
    case '=': return "0242 0444";
    case '+': return "0343 2125";
    default: return "";
  }
}

constexpr double advance = 5.5;  // grid units per character

}  // namespace

void add_text(std::vector<Vec3<float>>& segments, std::string_view text, const Vec3<double>& origin, const Vec3<double>& right,
              const Vec3<double>& up, double height) {
  const double unit = height / 6;
  const Vec3<double> r = right / norm(right) * unit, u = up / norm(up) * unit;
  Vec3<double> pen = origin;
  for (char c : text) {
    const std::string_view s = strokes(c);
    for (std::size_t i = 0; i + 3 < s.size(); i += 2) {
      if (s[i + 2] == ' ') {  // end of a polyline: skip the space
        i += 1;
        continue;
      }
      auto point = [&](std::size_t k) {
        const Vec3<double> p = pen + r * double(s[k] - '0') + u * double(s[k + 1] - '0');
        return Vec3<float>{float(p.x), float(p.y), float(p.z)};
      };
      segments.push_back(point(i));
      segments.push_back(point(i + 2));
    }
    pen = pen + r * advance;
  }
}

double text_width(std::string_view text, double height) { return double(text.size()) * advance * height / 6; }

Vec3<double> overlay_point(const Camera& c, double aspect, double u, double v) {
  const Vec3<double> forward = normalized(c.target - c.eye());
  const Vec3<double> right = normalized(cross(forward, {0, 1, 0}));
  const Vec3<double> up = cross(right, forward);
  const double half = c.distance * std::tan(c.fov_y / 2);
  return c.target + right * (u * half * aspect) + up * (v * half);
}

void add_overlay_text(Lines& lines, const Camera& c, double aspect, std::string_view text, double u, double v, double height) {
  const Vec3<double> origin = overlay_point(c, aspect, u, v);
  const Vec3<double> right = overlay_point(c, aspect, u + 1, v) - origin, up = overlay_point(c, aspect, u, v + 1) - origin;
  double world_height = height * norm(up);
  const double room = (0.95 - u) * norm(right), width = text_width(text, world_height);
  if (!(room > 0)) return;  // starting at or past the margin: no room (a negative scale would mirror it)
  if (width > room && width > 0) world_height *= room / width;
  add_text(lines.points, text, origin, right, up, world_height);
}

}  // namespace dq::render
