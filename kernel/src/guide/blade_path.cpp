#include "st/guide/blade_path.h"

#include "st/boolean/triangle_intersection.h"
#include "st/core/aabb_tree.h"

#include <cmath>

namespace st {

BladePathReport check_blade_path(const TriangleMesh& guide, const SlotSpec& slot, const SlotPlacement& p,
                                 double tolerance) {
  BladePathReport r;
  r.name = slot.name;
  const SlotFrame f = slot_frame(slot);
  const double half = 0.5 * p.width - tolerance, along = 0.5 * slot.length - tolerance;
  const double z0 = p.cut_bottom + tolerance, z1 = p.housing_top;
  const TriangleMesh path = frame_box(f, half, -along, along, z0, z1);
  auto inside = [&](const Vec3& x) {
    const Vec3 q = x - f.origin;
    const double z = q.dot(f.up());
    return std::abs(q.dot(f.n)) < half && std::abs(q.dot(f.e)) < along && z > z0 && z < z1;
  };
  for (const Vec3& x : guide.positions)
    if (inside(x)) {
      r.blocked = x;
      return r;
    }
  const AabbTree tree(guide), box(path);
  tree.for_each_overlapping_pair(box, [&](Index fg, Index fb) {
    if (r.blocked) return;
    const Triangle& g = guide.triangles[fg];
    const Triangle& b = path.triangles[fb];
    if (triangles_intersect(guide.positions[g[0]], guide.positions[g[1]], guide.positions[g[2]], path.positions[b[0]],
                            path.positions[b[1]], path.positions[b[2]]))
      r.blocked = guide.positions[g[0]];
  });
  r.free = !r.blocked;
  return r;
}

} // namespace st
