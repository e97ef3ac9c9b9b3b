#pragma once
// The insertion analysis's samples and the areas they hide (private to insertion.cpp and its tests):
// the bone as the samples' segments see it, the samples of a region's faces, and the hidden area of
// the samples along several directions at once, as the direction search asks for it.

#include "st/core/aabb_tree.h"
#include "st/core/mesh.h"
#include "validate/sweep_columns.h"

#include <cstddef>
#include <vector>

namespace st::insertion_detail {

/// The bone as the segments see it: how far they reach (past the bone's bounding box) and how far off
/// the surface they start; measured once per bone, not per direction. For one direction asked of many
/// samples, the bone's faces the segments can meet may be listed in columns along it: a segment starts
/// on the bone, where the tree's boxes rise across it, and reads one cell instead.
struct Sight {
  const AabbTree& bone;
  double reach;
  double lift;
  const validate_detail::SweepColumns* columns = nullptr; // along -d, over the faces the segments reach
};

/// The sight of the whole bone's tree for segments `reach` long (at most twice the bone's size).
Sight sight_of(const AabbTree& bone, double reach);

/// A sample of a region's face: a point of it, the face, its weight (area).
struct Sample {
  Vec3 point;
  Index face;
  double area;
};

/// Samples of every stride-th face of `region` (each weighing `stride` faces' area), a face split into
/// k x k equal triangles with one sample at each centre (k from `spacing`, insertion.h; 1 when it is 0).
std::vector<Sample> samples_of(const TriangleMesh& region, double spacing, std::size_t stride);

/// Whether the guide moving along unit d cannot reach the sample `p` on region face (a, b, c): the
/// face looks away from d, or a bone face meets the segment from p (a lift off it) back along -d.
bool is_hidden(const Sight& sight, const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// The hidden area of `samples` along each unit direction of `ds`, or infinity for a direction once
/// the area it hides is over `bound` by more than the sums' rounding (1e-9 of it): its whole area is
/// then over the bound too, so a caller comparing it with the bound decides as it would on the whole
/// area. The directions share the threads; the areas are the same for any number of threads, and
/// whether the segments read the tree or columns along d.
std::vector<double> hidden_areas(const Sight& sight, const TriangleMesh& region, const std::vector<Sample>& samples,
                                 const std::vector<Vec3>& ds, double bound);

} // namespace st::insertion_detail
