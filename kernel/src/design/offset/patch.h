#pragma once
// The offset's input surface prepared for distance queries (private to offset_surface): per-triangle
// geometry, the closest point on a triangle with its feature, and the pseudo-normals that tell the
// front of the patch from its back.

#include "st/core/closest_point.h"
#include "st/core/mesh.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

namespace st::offset_detail {

// ---- the patch: per-triangle geometry and pseudo-normals ---------------------------------------------

/// A patch triangle: its closest-point geometry and its plane, whose distance |normal.p - plane| is a
/// lower bound of the distance to the triangle.
struct PatchTriangle : TriangleGeometry {
  Vec3 normal = Vec3::Zero(); // unit, zero when degenerate
  double plane = 0.0;         // normal.a
};

struct Patch {
  const TriangleMesh* mesh = nullptr;
  std::vector<PatchTriangle> triangles;
  std::vector<Vec3> face_normals;                       // unit, zero for degenerate triangles
  std::vector<std::array<Vec3, 3>> side_normals;        // unit outward normals of the planes through each
                                                        // edge perpendicular to the triangle (edge k: k, k+1)
  std::vector<std::int32_t> edge_of;                    // 3 per triangle: edge k runs from corner k to corner k+1
  std::vector<Vec3> edge_normals;                       // unit sum of the adjacent face normals
  std::vector<Vec3> vertex_normals;                     // unit angle-weighted sum of the incident face normals
  std::vector<Index> vertex_face_offsets, vertex_faces; // triangles around each vertex (rows)
  std::vector<Index> edge_face_offsets, edge_faces;     // triangles along each edge (rows)
  std::vector<std::uint8_t> border_edge;                // 1 for edges used by one triangle
  std::vector<std::uint8_t> border_vertex;              // 1 for vertices of such edges
  std::vector<std::array<float, 3>> side_slack;         // per triangle and edge k: how far outside the
                                                        // edge's plane (in units of the distance) the
                                                        // points whose closest point is on the edge or its
                                                        // end points can lie: 1 on the border, else the
                                                        // sine of the largest angle between this triangle's
                                                        // normal and those around the edge's end points
  double area = 0.0;
  double border_length = 0.0; // total length of edges used by one triangle

  /// Pseudo-normal of the closest feature (Baerentzen & Aanaes): a point lies behind the patch when
  /// its offset from the closest point has a negative dot product with it.
  [[nodiscard]] const Vec3& pseudo_normal(std::int32_t t, int feature) const {
    if (feature == kFace) return face_normals[t];
    if (feature <= kVertex2) return vertex_normals[mesh->triangles[t][feature - kVertex0]];
    return edge_normals[edge_of[3 * t + (feature - kEdge01)]];
  }

  /// Whether the closest feature lies on the patch's border.
  [[nodiscard]] bool on_border(std::int32_t t, int feature) const {
    if (feature == kFace) return false;
    if (feature <= kVertex2) return border_vertex[mesh->triangles[t][feature - kVertex0]] != 0;
    return border_edge[edge_of[3 * t + (feature - kEdge01)]] != 0;
  }
};

/// The patch of `mesh`; pseudo-normals (and the border data they need) only when asked for.
Patch build_patch(const TriangleMesh& mesh, bool with_pseudo_normals);

} // namespace st::offset_detail
