#include "st/design/skirt.h"

#include "st/boolean/triangle_intersection.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace st {

namespace {

/// Depths change along the (closed) rim by at most the distance between neighbours: a min-plus sweep
/// each way, twice round so that it wraps.
void limit_slope(std::vector<double>& depth, const std::vector<Vec3>& top) {
  const std::size_t m = depth.size();
  for (std::size_t i = 0; i < 2 * m; ++i) {
    const std::size_t a = i % m, b = (i + 1) % m;
    depth[b] = std::min(depth[b], depth[a] + (top[b] - top[a]).norm());
  }
  for (std::size_t i = 2 * m; i-- > 0;) {
    const std::size_t a = (i + 1) % m, b = i % m;
    depth[b] = std::min(depth[b], depth[a] + (top[b] - top[a]).norm());
  }
}

} // namespace

SkirtResult add_skirt(CutResult& region, const std::vector<std::uint8_t>& on_input_rim,
                      const std::vector<Vec3>& dropped_rim, const Vec3& direction, const AabbTree& bone,
                      double clearance, std::vector<std::uint8_t>& filled) {
  SkirtResult out;
  const std::vector<Index>& rim = region.rim;
  const std::size_t m = rim.size();
  if (dropped_rim.empty() || m < 3) return out;
  const Vec3 d = direction.normalized();
  TriangleMesh& mesh = region.region;
  const auto nv = static_cast<Index>(mesh.vertex_count());

  // The depth each wall is drawn to, and the first bone below its top.
  std::vector<Vec3> top(m);
  std::vector<double> wanted(m, 0.0), depth(m, 0.0);
  for (std::size_t i = 0; i < m; ++i) {
    top[i] = mesh.positions[rim[i]];
    if (on_input_rim[rim[i]]) continue;
    double across = std::numeric_limits<double>::infinity(), along = 0.0;
    for (const Vec3& r : dropped_rim) {
      const Vec3 e = r - top[i];
      const double a = e.dot(d), c = e.squaredNorm() - a * a;
      if (c < across) {
        across = c;
        along = a;
      }
    }
    wanted[i] = depth[i] = std::max(0.0, along);
    if (depth[i] > 0.0)
      if (const auto hit = bone.first_hit(top[i], d, 0.5 * kMinSkirtDepth_mm, depth[i] + clearance))
        depth[i] = std::max(0.0, std::min(depth[i], hit->t - clearance));
  }
  limit_slope(depth, top);

  // Skirt faces, corners coded: i < m is rim vertex i, m + i the wall's foot under it (or i itself
  // where it hangs no wall). For the rim's half-edge a -> b the kept face holds, the wall's quad runs
  // b -> a -> foot(a) -> foot(b), so the feet's edge foot(a) -> foot(b) is the new rim's half-edge.
  using Corners = std::array<std::size_t, 3>;
  auto hangs = [&](std::size_t i) { return depth[i] >= kMinSkirtDepth_mm; };
  auto foot = [&](std::size_t i) { return hangs(i) ? m + i : i; };
  auto faces = [&] {
    std::vector<Corners> out_faces;
    for (std::size_t a = 0; a < m; ++a) {
      const std::size_t b = (a + 1) % m;
      if (hangs(a)) out_faces.push_back({b, a, foot(a)});
      if (hangs(b)) out_faces.push_back({b, foot(a), foot(b)});
    }
    return out_faces;
  };
  auto index = [&](std::size_t c) { return c < m ? rim[c] : nv + static_cast<Index>(c - m); };
  auto point = [&](std::size_t c) -> Vec3 { return c < m ? top[c] : top[c - m] + depth[c - m] * d; };
  const auto nb = static_cast<Index>(bone.mesh().vertex_count());
  auto bone_index = [&](std::size_t c) {
    if (c < m) {
      const Index b = region.source_vertex[rim[c]];
      if (b != kInvalidIndex && bone.mesh().positions[b] == top[c]) return b;
    }
    return nb + static_cast<Index>(c);
  };
  const AabbTree own(mesh);
  // Exact: a skirt face touching the bone or crossing the region's faces lifts its feet.
  for (;;) {
    limit_slope(depth, top);
    for (double& t : depth)
      if (t < kMinSkirtDepth_mm) t = 0.0;
    bool lifted = false;
    for (const Corners& c : faces()) {
      const std::array<Vec3, 3> p{point(c[0]), point(c[1]), point(c[2])};
      BoundingBox box;
      for (const Vec3& q : p) box.extend(q);
      // Against the bone, a top that is a bone vertex (clearance 0) is that vertex: the skirt may
      // touch the bone there and along the top edge, nowhere else.
      const std::array<Index, 3> cb{bone_index(c[0]), bone_index(c[1]), bone_index(c[2])};
      bool meets = false;
      bone.for_each_in_box(box, [&](Index f) {
        const Triangle& t = bone.mesh().triangles[f];
        const auto& x = bone.mesh().positions;
        meets = meets || mesh_triangles_intersect(cb, p, {t[0], t[1], t[2]}, {x[t[0]], x[t[1]], x[t[2]]});
      });
      const std::array<Index, 3> ci{index(c[0]), index(c[1]), index(c[2])};
      own.for_each_in_box(box, [&](Index f) {
        const Triangle& t = mesh.triangles[f];
        const auto& x = mesh.positions;
        meets = meets || mesh_triangles_intersect(ci, p, {t[0], t[1], t[2]}, {x[t[0]], x[t[1]], x[t[2]]});
      });
      if (!meets) continue;
      for (std::size_t k : c)
        if (k >= m) depth[k - m] *= 0.5;
      lifted = true;
    }
    if (!lifted) break;
  }

  // The walls: their feet as vertices (moved with their tops), their faces marked as fills.
  filled.resize(mesh.face_count(), 0);
  for (std::size_t i = 0; i < m; ++i) {
    if (depth[i] + 1e-9 < wanted[i]) ++out.shortened;
    if (!hangs(i)) continue;
    mesh.positions.push_back(point(m + i));
    region.source.push_back(region.source[rim[i]]);
    region.source_vertex.push_back(kInvalidIndex);
    out.max_depth_mm = std::max(out.max_depth_mm, depth[i]);
  }
  // Feet as numbered in the mesh: in rim order, after its vertices.
  std::vector<Index> foot_index(m, kInvalidIndex);
  for (std::size_t i = 0, k = 0; i < m; ++i)
    if (hangs(i)) foot_index[i] = nv + static_cast<Index>(k++);
  auto vertex = [&](std::size_t c) { return c < m ? rim[c] : foot_index[c - m]; };
  for (const Corners& c : faces()) {
    mesh.triangles.push_back({vertex(c[0]), vertex(c[1]), vertex(c[2])});
    filled.push_back(1);
    out.area_mm2 += 0.5 * (point(c[1]) - point(c[0])).cross(point(c[2]) - point(c[0])).norm();
    ++out.faces;
  }
  std::vector<Index> new_rim(m);
  for (std::size_t i = 0; i < m; ++i) new_rim[i] = vertex(foot(i));
  region.rim = std::move(new_rim);
  return out;
}

} // namespace st
