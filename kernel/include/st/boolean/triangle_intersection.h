#pragma once
// Exact intersection tests between closed triangles and segments in 3D, the building blocks of the
// self-intersection check. Every decision is taken with the exact predicates of predicates.h, so the
// answers are exact for all finite double input, in particular for touching and coplanar
// configurations. Degenerate triangles (collinear or repeated corners) are handled as the segment or
// point they are; nothing is divided, so no input is refused.

#include "st/core/mesh.h"

#include <array>

namespace st {

/// True when the closed triangles (a0, a1, a2) and (b0, b1, b2) share at least one point: crossing,
/// piercing, touching at a vertex or along an edge, a vertex on the other's edge or face, coplanar
/// overlap or containment all count. A triangle whose corners are collinear is its segment (or point).
bool triangles_intersect(const Vec3& a0, const Vec3& a1, const Vec3& a2, const Vec3& b0, const Vec3& b1,
                         const Vec3& b2);

/// The self-intersection test for two faces of the same mesh, given by their vertex indices `ta`, `tb`
/// and the positions of those vertices `pa`, `pb` (pa[i] is the position of ta[i]; a shared index must
/// come with the same position on both sides). Faces that share vertex indices always touch there;
/// they count as intersecting only when they meet beyond the convex hull of the shared vertices:
///   - no shared index: triangles_intersect;
///   - one shared vertex v: the faces have a common point other than v. For non-degenerate faces this
///     holds exactly when the edge opposite v in one face meets the other face (which covers both a
///     piercing opposite edge and an overlap of the two angular wedges near v, coplanar or not);
///   - a shared edge (u, w): the faces have a common point off the segment [u, w]. For non-degenerate
///     faces: they are coplanar and the two opposite vertices lie on the same side of the line uw (a
///     fold onto each other); two faces on opposite sides, or not coplanar, only share the edge;
///   - the same index triple (in any order): always intersecting (a duplicate face).
/// Faces with a repeated index are handled by the same rule, with the distinct shared indices.
bool mesh_triangles_intersect(const std::array<Index, 3>& ta, const std::array<Vec3, 3>& pa,
                              const std::array<Index, 3>& tb, const std::array<Vec3, 3>& pb);

/// True when the closed segment [p, q] and the closed triangle (a, b, c) share a point. The segment may
/// be a point (p == q) and the triangle may be degenerate.
bool segment_intersects_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c);

} // namespace st
