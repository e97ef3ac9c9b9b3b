#include "guide/seat.h"

#include "st/boolean/triangle_intersection.h"
#include "st/core/float32.h"

#include <algorithm>
#include <limits>

namespace st::guide_detail {

namespace {

// Keeps the side of `polygon` where n . x >= offset (Sutherland-Hodgman, one plane).
std::vector<Vec3> clipped(const std::vector<Vec3>& polygon, const Vec3& n, double offset) {
  std::vector<Vec3> out;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Vec3 &p = polygon[i], &q = polygon[(i + 1) % polygon.size()];
    const double sp = n.dot(p) - offset, sq = n.dot(q) - offset;
    if (sp >= 0.0) out.push_back(p);
    if ((sp >= 0.0) != (sq >= 0.0)) out.push_back(p + (sp / (sp - sq)) * (q - p));
  }
  return out;
}

} // namespace

TriangleMesh rounded(TriangleMesh mesh) {
  round_to_float32(mesh);
  return mesh;
}

std::optional<double> highest_bone(const AabbTree& bone, const Vec3& origin, const Vec3& axis,
                                   const std::array<Vec3, 3>& foot, double floor, double ceiling) {
  auto height = [&](const Vec3& x) { return axis.dot(x - origin); };
  BoundingBox box;
  for (const Vec3& f : foot) {
    box.extend(f);
    box.extend(f + (ceiling - floor) * axis);
  }
  std::array<Vec3, 3> normals;
  std::array<double, 3> offsets{};
  for (int k = 0; k < 3; ++k) {
    Vec3 n = axis.cross(foot[(k + 1) % 3] - foot[k]);
    if (n.dot(foot[(k + 2) % 3] - foot[k]) < 0.0) n = -n;
    normals[k] = n;
    offsets[k] = n.dot(foot[k]);
  }
  std::optional<double> highest;
  const TriangleMesh& mesh = bone.mesh();
  bone.for_each_in_box(box.inflated(1e-6), [&](Index g) {
    const Triangle& t = mesh.triangles[g];
    std::vector<Vec3> polygon{mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]};
    for (int k = 0; k < 3 && !polygon.empty(); ++k) polygon = clipped(polygon, normals[k], offsets[k]);
    if (!polygon.empty()) polygon = clipped(polygon, -axis, -(ceiling + axis.dot(origin)));
    for (const Vec3& x : polygon) highest = std::max(highest.value_or(height(x)), height(x));
  });
  return highest;
}

std::vector<double> foot_needs(const TriangleMesh& mesh, Index foot_vertices, const Vec3& origin, const Vec3& axis,
                               double floor, double ceiling, double above, const AabbTree& bone, double shift) {
  std::vector<double> need(foot_vertices, -std::numeric_limits<double>::infinity());
  for (const Triangle& t : mesh.triangles) {
    if (t[0] >= foot_vertices || t[1] >= foot_vertices || t[2] >= foot_vertices) continue;
    const auto h = highest_bone(
        bone, origin, axis,
        {mesh.positions[t[0]] + shift * axis, mesh.positions[t[1]] + shift * axis, mesh.positions[t[2]] + shift * axis},
        floor, ceiling);
    if (!h) continue;
    for (Index v : t) need[v] = std::max(need[v], *h + above);
  }
  return need;
}

std::optional<Vec3> meets_bone(const TriangleMesh& solid, const AabbTree& bone) {
  if (bone.empty()) return std::nullopt;
  std::optional<Vec3> meets;
  const AabbTree tree(solid);
  tree.for_each_overlapping_pair(bone, [&](Index fc, Index fb) {
    if (meets) return;
    const Triangle& c = solid.triangles[fc];
    const Triangle& b = bone.mesh().triangles[fb];
    const auto& q = bone.mesh().positions;
    if (triangles_intersect(solid.positions[c[0]], solid.positions[c[1]], solid.positions[c[2]], q[b[0]], q[b[1]],
                            q[b[2]]))
      meets = solid.positions[c[0]];
  });
  return meets;
}

} // namespace st::guide_detail
