#pragma once
// Undercut block-out: the part of a covered region that a guide moving onto the bone along d cannot
// reach is replaced by a surface the guide can reach, so that the guide goes on and comes off along d.
//
// Method. The region's faces with any hidden area along d (insertion.h: faces turned away from the
// guide, and faces behind other bone; decided exactly per face by the removal check's sweep) are removed; each
// connected zone of them leaves a hole in the region, bounded by the silhouette where the visible surface turns under
// (the upper border) and by the first visible faces beyond the zone's shadow (the lower border), or by the region's rim
// where the zone reaches it. Seen along d the zone's borders make a polygon with holes: around a tooth, the ring
// between its widest outline and the gum beyond its shadow. The hole is filled by that polygon's
// triangles (polygon_fill.h: ear clipping, every decision an exact orient2d on the coordinates across
// d), over the zone's own border vertices: walls that run from the silhouette down to the lower border
// as steeply as one face of the lower border allows (the wax a technician lays under a height of
// contour). The kept faces are the bone's own, so the guide still fits it exactly where it can reach it.
//
// A zone that reaches the region's rim cannot be filled from its own border (the rim would stay under
// the overhang): it is cut off instead, and the rim follows the zone's edge on the visible side (where the
// bone turns under), provided the region keeps one simple border loop. The design then hangs a skirt from
// that edge down to the drawn border's depth (skirt.h), so the guide still covers what was drawn.
//
// A zone is left as it is (and named) when its borders do not make such a polygon seen along d (a
// border vertex used twice, borders that cross seen along d, a fill edge that is already an edge of
// the kept faces); the removal check (removal.h) then says whether the guide still comes off.

#include "st/core/mesh.h"
#include "st/validate/removal.h"

#include <cstdint>
#include <vector>

namespace st {

struct BlockOutResult {
  std::vector<Triangle> triangles;  ///< the region's faces: the kept ones, then the fills (same vertices)
  std::vector<std::uint8_t> filled; ///< per face of `triangles`: 1 for a fill
  std::size_t zones = 0;            ///< connected zones of hidden faces
  std::size_t filled_zones = 0;     ///< of them, filled
  std::size_t removed_faces = 0;    ///< hidden faces replaced by fills
  double volume_mm3 = 0.0;          ///< between the fills and the faces they replace
  std::size_t trimmed_zones = 0;    ///< zones at the rim cut off the region
  double trimmed_area_mm2 = 0.0;    ///< their area
  bool rim_changed = false;         ///< zones were trimmed: the region's border loop is not the input's
  std::vector<Vec3> unfilled;       ///< a point of each zone left as it was
};

/// Blocks out the faces of `region` (part of the surface of the bone `bone` tests against, oriented outward) that the
/// guide moving along the unit `direction` onto the bone cannot reach: those with sampled[f] > 0 (from undercut(),
/// insertion.h) and every face whose prism, raised off the bone and swept against the direction by `reach` (the removal
/// distance), meets the bone (removal.h, SweepStart::raised: exact, also for a face mostly in view).
BlockOutResult block_out(const SweepTest& bone, const TriangleMesh& region, const std::vector<float>& sampled,
                         const Vec3& direction, double reach);

} // namespace st
