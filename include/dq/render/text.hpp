// Labels as line segments: a stroke font (digits, letters, space and . : - / ( ) = + , each on a grid
// 4 wide and 6 high; lower case is drawn as upper), set anywhere in 3D or on the plane that faces
// the camera, so that pictures carry their own captions (the renderer draws no other text).
#pragma once

#include <string_view>
#include <vector>

#include "dq/core/vec3.hpp"
#include "dq/render/render.hpp"

namespace dq::render {

/// Appends the segments (pairs of points) of `text`, its baseline starting at `origin`, advancing
/// along `right`, with `up` the direction of the strokes' height; `height` is the capital height.
/// Characters without a glyph advance without drawing. `right` and `up` need not be unit (they
/// are normalized) but must not be parallel.
void add_text(std::vector<Vec3<float>>& segments, std::string_view text, const Vec3<double>& origin, const Vec3<double>& right,
              const Vec3<double>& up, double height);

/// The width of `text` at capital height `height`.
double text_width(std::string_view text, double height);

/// The point of the plane through the camera's target facing the camera that a viewport of this
/// aspect shows at normalized device coordinates (u, v) ∈ [−1, 1]² (x right, y up): where captions
/// and plots over a view go.
Vec3<double> overlay_point(const Camera& camera, double aspect, double u, double v);

/// A caption on that plane, its baseline starting at (u, v), `height` in the same units (2 is the
/// view's height), made smaller where it would run past u = 0.95 (in a narrow view, text sized by
/// the view's height alone would run into the next one); from u ≥ 0.95 on, nothing is drawn.
void add_overlay_text(Lines& lines, const Camera& camera, double aspect, std::string_view text, double u, double v, double height);

}  // namespace dq::render
