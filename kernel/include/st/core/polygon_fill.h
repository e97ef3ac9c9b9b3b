#pragma once
// Triangles filling a polygon with holes in the plane (the block-out fills its holes with it): ear
// clipping after joining each hole to the outer loop by a bridge (Eberly, "Triangulation by ear
// clipping", 2002). Every decision (convex corner, point in an ear, bridge visibility) is an exact
// orient2d on the given coordinates; points may repeat (the bridges repeat two) and runs of collinear
// points are clipped last, as ears of no area.

#include "st/core/mesh.h"

#include <array>
#include <optional>
#include <vector>

namespace st {

using Point2 = std::array<double, 2>;

/// Triangles (indices into `points`, counter-clockwise) covering the polygon whose outer loop is
/// loops[0] (counter-clockwise) and whose holes are the other loops (clockwise, inside the outer
/// one); every loop lists indices into `points`. Nothing when the loops do not make such a polygon
/// (the clipping finds no ear: loops that cross or touch each other, a loop that turns the wrong way).
std::optional<std::vector<std::array<Index, 3>>> fill_polygon(const std::vector<Point2>& points,
                                                              std::vector<std::vector<Index>> loops);

/// Twice the signed area of a loop (positive counter-clockwise).
double loop_area2(const std::vector<Point2>& points, const std::vector<Index>& loop);

} // namespace st
