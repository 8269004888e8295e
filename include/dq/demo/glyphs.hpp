// A stroke font for labels drawn as line segments (the demos' text in 3D and in headless pictures,
// where the renderer has no text): digits, letters (upper case; lower case is drawn as upper),
// space and . : - / ( ) = + , each on a grid 4 wide and 6 high.
#pragma once

#include <string_view>
#include <vector>

#include "dq/core/vec3.hpp"

namespace dq::demo {

/// Appends the segments (pairs of points) of `text`, its baseline starting at `origin`, advancing
/// along `right`, with `up` the direction of the strokes' height; `height` is the capital height.
/// Characters without a glyph advance without drawing. `right` and `up` need not be unit (they
/// are normalized) but must not be parallel.
void add_text(std::vector<Vec3<float>>& segments, std::string_view text, const Vec3<double>& origin, const Vec3<double>& right,
              const Vec3<double>& up, double height);

/// The width of `text` at capital height `height`.
double text_width(std::string_view text, double height);

}  // namespace dq::demo
