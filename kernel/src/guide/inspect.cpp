#include "st/guide/inspect.h"

#include "detail/format.h"
#include "detail/parallel.h"
#include "st/core/aabb_tree.h"
#include "st/guide/sleeve.h"
#include "st/boolean/triangle_intersection.h"

#include <algorithm>
#include <sstream>

namespace st {

namespace {

/// Whether p lies behind the bone surface (inside the bone) seen from its closest point c: by the
/// closest face's normal when c is inside that face, else (c on an edge or a vertex) by the sum of
/// the normals of every face that c lies on, the pseudo-normal that decides sharp crests and grooves
/// correctly where a single face's normal does not.
bool behind_surface(const TriangleMesh& bone, const AabbTree& tree, const Vec3& p, const ClosestPoint& c) {
  const Triangle& t = bone.triangles[c.face];
  const Vec3 &a = bone.positions[t[0]], &b = bone.positions[t[1]], &d = bone.positions[t[2]];
  const Vec3 n = (b - a).cross(d - a);
  const double area2 = n.squaredNorm();
  const double wa = (b - c.point).cross(d - c.point).dot(n) / area2;
  const double wb = (d - c.point).cross(a - c.point).dot(n) / area2;
  const double wd = 1.0 - wa - wb;
  if (std::min({wa, wb, wd}) > 1e-9) return (p - c.point).dot(n) < 0.0;
  Vec3 normal = Vec3::Zero();
  const double reach = c.distance * (1.0 + 1e-9) + 1e-12;
  BoundingBox box;
  box.extend(p);
  tree.for_each_in_box(box.inflated(reach), [&](Index f) {
    const Triangle& u = bone.triangles[f];
    const Vec3 q = closest_point_on_triangle(p, bone.positions[u[0]], bone.positions[u[1]], bone.positions[u[2]]);
    const Vec3 m = triangle_normal(bone, f);
    if ((q - p).norm() <= reach && m.norm() > 0.0) normal += m.normalized();
  });
  return (p - c.point).dot(normal) < 0.0;
}

} // namespace

double segment_segment_distance(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1) {
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r), c = d1.dot(r), b = d1.dot(d2);
  if (a <= 1e-300 || e <= 1e-300) { // a point: its distance to the other segment
    const Vec3 p = a <= 1e-300 ? p0 : q0;
    const Vec3 s0 = a <= 1e-300 ? q0 : p0, sd = a <= 1e-300 ? d2 : d1;
    const double len = sd.squaredNorm();
    const double t = len > 1e-300 ? std::clamp((p - s0).dot(sd) / len, 0.0, 1.0) : 0.0;
    return (s0 + t * sd - p).norm();
  }
  const double denom = a * e - b * b;
  double s = denom > 1e-300 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
  double t = (b * s + f) / e;
  if (t < 0.0) {
    t = 0.0;
    s = std::clamp(-c / a, 0.0, 1.0);
  } else if (t > 1.0) {
    t = 1.0;
    s = std::clamp((b - c) / a, 0.0, 1.0);
  }
  return (p0 + s * d1 - (q0 + t * d2)).norm();
}

double segment_triangle_distance(const Vec3& p0, const Vec3& p1, const Vec3& a, const Vec3& b, const Vec3& c) {
  if (segment_intersects_triangle(p0, p1, a, b, c)) return 0.0;
  double d = std::min((closest_point_on_triangle(p0, a, b, c) - p0).norm(),
                      (closest_point_on_triangle(p1, a, b, c) - p1).norm());
  d = std::min(d, segment_segment_distance(p0, p1, a, b));
  d = std::min(d, segment_segment_distance(p0, p1, b, c));
  return std::min(d, segment_segment_distance(p0, p1, c, a));
}

bool GuideInspection::passed() const {
  return solid.valid() && vertices_in_bone == 0 &&
         std::all_of(bores.begin(), bores.end(), [](const BoreCheck& b) { return b.open; });
}

std::string GuideInspection::summary() const {
  std::ostringstream s;
  s << (solid.valid() ? "valid solid" : "NOT a valid solid: " + solid.summary());
  if (vertices_in_bone == 0) s << "; seats (nothing in the bone)";
  else s << "; " << vertices_in_bone << " vertices in the bone, deepest " << detail::mm(deepest_in_bone);
  std::size_t open = 0;
  for (const BoreCheck& b : bores) open += b.open;
  if (!bores.empty()) s << "; " << open << " of " << bores.size() << " bores open";
  for (const BoreCheck& b : bores)
    if (!b.open) s << " (" << b.name << " blocked by " << detail::mm(-b.margin) << ")";
  return s.str();
}

GuideInspection inspect_guide(const TriangleMesh& guide, const TriangleMesh& bone, const std::vector<TubeSpec>& tubes,
                              double clearance, double tolerance) {
  check_mesh(guide, "guide");
  check_mesh(bone, "bone");
  for (const TubeSpec& t : tubes) check_tube(t);
  GuideInspection r;
  r.solid = check_solid(guide);
  const AabbTree bone_tree(bone);
  r.vertex_distance.resize(guide.positions.size(), 0.0);
  detail::parallel_for(guide.positions.size(), 1024, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t v = begin; v < end; ++v) {
      const Vec3& p = guide.positions[v];
      const auto c = bone_tree.closest_point(p);
      if (!c) continue;
      r.vertex_distance[v] = behind_surface(bone, bone_tree, p, *c) ? -c->distance : c->distance;
    }
  });
  for (const double d : r.vertex_distance) {
    if (-d > tolerance) {
      ++r.vertices_in_bone;
      r.deepest_in_bone = std::max(r.deepest_in_bone, -d);
    }
    if (std::abs(d - clearance) <= tolerance) ++r.seated_vertices;
  }
  const AabbTree guide_tree(guide);
  for (const TubeSpec& t : tubes) {
    const Vec3 a0 = tube_point(t, -t.outer_radius), a1 = tube_point(t, t.offset + t.length);
    BoundingBox box;
    box.extend(a0);
    box.extend(a1);
    double nearest = 1e300;
    guide_tree.for_each_in_box(box.inflated(t.inner_radius), [&](Index f) {
      const Triangle& tri = guide.triangles[f];
      nearest = std::min(nearest, segment_triangle_distance(a0, a1, guide.positions[tri[0]], guide.positions[tri[1]],
                                                            guide.positions[tri[2]]));
    });
    BoreCheck b;
    b.name = t.name;
    b.margin = std::min(nearest, 1e3) - t.inner_radius;
    b.open = b.margin >= -tolerance;
    r.bores.push_back(b);
  }
  return r;
}

} // namespace st
