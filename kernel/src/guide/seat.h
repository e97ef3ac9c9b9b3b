#pragma once
// Standing guide features on the bone (private to the guide builder, st/guide/guide.h): a feature's
// foot, a grid at one height along its axis, is raised over the highest bone under each of its
// triangles, that height taken exactly from the bone clipped to the prism over the triangle. Used by
// the sleeves' columns and the saw slots' housings. Heights are along `axis` from `origin`.

#include "st/core/aabb_tree.h"
#include "st/core/mesh.h"

#include <array>
#include <optional>
#include <vector>

namespace st::guide_detail {

/// The mesh with its coordinates rounded to float (as the guide is written).
TriangleMesh rounded(TriangleMesh mesh);

/// The highest bone over the foot triangle `foot` (in the prism over it along the axis) between
/// `floor` and `ceiling`; nothing when no bone lies there. Each bone triangle near is clipped by the
/// prism's three side planes and by the ceiling: the highest point of what is left is one of its
/// corners, so the height is that of the bone itself, not of samples.
std::optional<double> highest_bone(const AabbTree& bone, const Vec3& origin, const Vec3& axis,
                                   const std::array<Vec3, 3>& foot, double floor, double ceiling);

/// Per foot vertex of `mesh` (its first `foot_vertices` vertices, lying at height `floor`): the height
/// it must stand at, `above` over the highest bone (up to `ceiling`) over the foot triangles around
/// it, or -infinity where there is none. `shift` moves the foot triangles along the axis to `floor`
/// first (a foot made at another height).
std::vector<double> foot_needs(const TriangleMesh& mesh, Index foot_vertices, const Vec3& origin, const Vec3& axis,
                               double floor, double ceiling, double above, const AabbTree& bone, double shift = 0.0);

/// A place where a face of `solid` meets the bone (exact triangle tests), or nothing.
std::optional<Vec3> meets_bone(const TriangleMesh& solid, const AabbTree& bone);

} // namespace st::guide_detail
