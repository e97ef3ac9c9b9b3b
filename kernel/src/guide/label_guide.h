#pragma once
// Labels on the guide (private to the guide builder, st/guide/guide.h): the label's frame on the
// template's outer surface, its text laid on that surface and the solid engraved or embossed.

#include "st/core/aabb_tree.h"
#include "st/guide/guide.h"

#include <limits>

namespace st::guide_detail {

/// The filled text of a label in its plane: its outlines triangulated (polygon_fill.h), then split
/// until no edge is longer than `spacing`; `boundary` lists the outline's edges (a, b) with the text
/// on their left.
struct TextCap {
  std::vector<Point2> points;
  std::vector<std::array<Index, 3>> triangles;
  std::vector<std::array<Index, 2>> boundary;
};

/// Throws GeometryError naming the label when an outline is not a polygon with holes.
TextCap text_cap(const LabelSpec& label, const std::vector<LabelPolygon>& polygons, double spacing);

/// What the guide builder already decided that a label must keep clear of.
struct LabelObstacles {
  const std::vector<TubeSpec>& tubes;
  const std::vector<TubePlacement>& tube_places;
  const std::vector<SlotSpec>& slots;
  const std::vector<SlotPlacement>& slot_places;
};

/// A label laid on the outer surface of `shell` (its first `inner_faces` faces the inner surface):
/// where it went, and its solids (one per group of glyphs whose outlines' boxes do not overlap; the
/// caller unites them) to cut from the guide (engraved) or unite with it (embossed), rounded to float.
struct LaidLabel {
  LabelPlacement placement;
  std::vector<TriangleMesh> solids;
};

/// `label` checked (check_label, as build_guide does). Throws InvalidInput for a label without outlines
/// and GeometryError naming the label and the place for a label
/// that cannot be laid (see build_guide).
LaidLabel lay_label(const LabelSpec& label, const TriangleMesh& shell, std::size_t inner_faces,
                    const LabelObstacles& obstacles, const GuideOptions& options);

} // namespace st::guide_detail
