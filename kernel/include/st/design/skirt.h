#pragma once
// The skirt: where block-out cut a hidden zone off at the rim (blockout.h), the guide would end at the
// silhouette, where the bone turns under, and cover less than the region drawn. The skirt gives it back:
// from each rim vertex the cut left (on the silhouette), a wall runs along the insertion direction down to
// the depth the drawn border had there, the way a technician's wax runs straight down from a height of
// contour. A wall parallel to d slides off along d with the rest of the guide, and it hangs beside the bone
// that turns under, never on it.
//
// Method. For a rim vertex s not on the input's rim, the depth is that of the nearest dropped rim vertex r
// seen along d, (r - s) . d (nothing when r lies higher), and no deeper than the first bone met from s along
// d less the clearance. Depths change along the rim by no more than the distance between vertices (45
// degrees), so the skirt runs out to nothing where the cut meets the input's rim. Every skirt face is then
// tested exactly (triangle_intersection.h) against the bone and against the region's faces; where one
// meets either, the depths of its lower corners are halved and the test repeated. Depths under
// kMinSkirtDepth_mm hang no wall (the rim stays at the silhouette there).

#include "st/core/aabb_tree.h"
#include "st/design/cut.h"

#include <cstdint>
#include <vector>

namespace st {

inline constexpr double kMinSkirtDepth_mm = 0.05;

struct SkirtResult {
  std::size_t faces = 0;     ///< skirt faces added to the region
  double area_mm2 = 0.0;     ///< their area
  double max_depth_mm = 0.0; ///< the deepest wall along d
  std::size_t shortened = 0; ///< rim vertices whose wall stops short of the drawn depth (bone or region below)
};

/// Hangs the skirt on `region` (displaced off the bone by the clearance; its rim in half-edge order):
/// `on_input_rim` marks per region vertex the rim vertices of the region as cut (before block-out);
/// `dropped_rim` holds the positions of the rim vertices block-out removed. Appends vertices (their source
/// is their top's) and faces, marking the faces 1 in `filled`; the rim becomes the skirt's lower edge.
SkirtResult add_skirt(CutResult& region, const std::vector<std::uint8_t>& on_input_rim,
                      const std::vector<Vec3>& dropped_rim, const Vec3& direction, const AabbTree& bone,
                      double clearance, std::vector<std::uint8_t>& filled);

} // namespace st
