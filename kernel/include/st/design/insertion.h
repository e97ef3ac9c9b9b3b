#pragma once
// Insertion direction and undercuts: which part of the bone a guide covers it can reach when it moves
// onto the bone along a direction d, and the direction with the least undercut.
//
// A point p of the region is reachable along d when the face it lies on looks at the guide (its
// outward normal n has n . d < 0, decided with orient3d) and the segment from p back along -d, as
// long as the guide is lifted to come off (`reach`, 20 mm in the pipeline; by default as long as the
// bone's bounding box), meets no face of the bone (exact segment-triangle test). A face
// parallel to d (exactly: a wall the guide slides along) is reached unless bone overhangs it: its
// segment starts a lift off the wall on its outer side, so it passes beside the wall's own edges
// (a box's side wall is reached, the post under a tooth's bulge is not). Bone anywhere, also outside the region,
// can hide a point. The segment starts a nanometre-scale length off p, so that the bone face p lies
// on, to rounding, does not count. Faces are sampled by area (each split into
// k x k equal triangles, k = ceil(longest edge / (1.5 spacing)), one sample at each centre: a face of
// one sample's share of the area, spacing^2 / 2, gets one sample), so the hidden
// area converges as the spacing shrinks: a visibility that is exact per sample, not a test of face
// normals alone. Where faces are much smaller than a sample's share of the area (spacing^2 / 2; a
// finely triangulated scan), every stride-th face is sampled; of the faces between, those turned away
// are hidden, those within two spacings of a hidden sample are tested at their centres (a hidden zone's
// border is found face by face), and the rest, among visible samples only, count as seen.

#include "st/core/aabb_tree.h"
#include "st/core/mesh.h"

#include <limits>
#include <optional>
#include <vector>

namespace st {

struct Undercut {
  Vec3 direction = Vec3::Zero(); ///< unit; the guide moves along it onto the bone
  double area_mm2 = 0.0;         ///< the region's area
  double hidden_mm2 = 0.0;       ///< the region's area the guide cannot reach along `direction`
  std::vector<float> hidden;     ///< per region face, the fraction of its area hidden
};

/// The undercut of `region` (faces of the bone, oriented outward) seen along `direction` against the
/// whole bone `bone`, sampled every `spacing` mm. Throws InvalidInput for a zero or non-finite
/// direction or a spacing that is not > 0.
Undercut undercut(const AabbTree& bone, const TriangleMesh& region, const Vec3& direction, double spacing,
                  double reach = std::numeric_limits<double>::infinity());

/// The direction with the least hidden area within 60 degrees of `start` (by default the region's
/// inward mean normal): a coarse search (every 7.5 degrees in angle from `start` and 30 degrees
/// around it, on the centres of about 4000 faces), then refined around the best direction with
/// halving steps down to 1/8 degree. Among equal areas the direction nearest `start` wins, so the
/// search ends at `start` when nothing is hidden along it, and after the first ring with a zero.
Vec3 least_undercut_direction(const AabbTree& bone, const TriangleMesh& region,
                              const std::optional<Vec3>& start = std::nullopt,
                              double reach = std::numeric_limits<double>::infinity());

} // namespace st
