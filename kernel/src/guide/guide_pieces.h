#pragma once
// Pieces of the guide builder (private to it, st/guide/guide.h): the template faces each tube's
// placement reads, and what the guide's Booleans leave that is not the guide (sleeve parts the union
// did not join to the template, slivers of template the bores cut off).

#include "st/core/errors.h"
#include "st/core/mesh.h"
#include "st/guide/guide.h"

#include <cstdint>
#include <string>
#include <vector>

namespace st::guide_detail {

/// The stretch of a tube's axis whose template faces its placement looks at: from `above` over the
/// rays' start down to their reach, heights along the axis (tube_point).
struct AxisStretch {
  double start = 0.0; // where the rays start (over the sleeve's top, by the bore margin)
  double reach = 0.0; // how far down they look
  double above = 0.0; // how far up a ray starting in the template looks
};
AxisStretch axis_stretch(const TubeSpec& tube, const GuideOptions& options);

/// Per tube, the faces of `mesh` that may meet the cylinder its placement's rays sweep (guide.cpp,
/// place(): its outer radius about its axis stretch): the faces near the stretch's own prism (the
/// square about the axis, of the outer radius, along the stretch), found by per-vertex codes in its
/// frame, whose box meets the stretch's box and the ball around whose box meets the stretch grown by
/// the radius (a long tilted axis has a large box; the ball test keeps the faces near the axis only).
/// Every face a ray can meet is among them.
std::vector<std::vector<Index>> faces_around(const TriangleMesh& mesh, const std::vector<TubeSpec>& tubes,
                                             const GuideOptions& options);

/// A tube's plan that cannot be built as it is: the error names the tube, what and where.
GeometryError conflict(const TubeSpec& tube, const Vec3& where, const std::string& how);

/// After the union, parts made of sleeve faces only (a column piece the bone cut off from the rest,
/// or a whole column whose foot rose over bone beside the template, clear of it) are dropped; a tube
/// left with no sleeve face joined to the template is a conflict named by the tube. Returns whether a
/// part was dropped.
bool drop_unjoined(TriangleMesh& mesh, std::vector<std::uint8_t>& from_tube, const std::vector<TubeSpec>& tubes,
                   const std::vector<TubePlacement>& placements);

/// A bore near the rim can cut a sliver of template off the guide: the pieces other than the largest
/// (by volume) would fall off the print; they are dropped and counted.
std::size_t drop_fragments(TriangleMesh& mesh, std::vector<std::uint8_t>& from_tube);

} // namespace st::guide_detail
