#include "guide/guide_pieces.h"

#include "detail/format.h"
#include "st/core/mesh.h"
#include "st/guide/sleeve.h"

#include <algorithm>
#include "st/core/union_find.h"

namespace st::guide_detail {

GeometryError conflict(const TubeSpec& tube, const Vec3& where, const std::string& how) {
  return GeometryError("tube '" + tube.name + "': its " + how + " near " + detail::where(where) +
                       "; shorten it, raise its offset or change its direction");
}

bool drop_unjoined(TriangleMesh& mesh, std::vector<std::uint8_t>& from_tube, const std::vector<TubeSpec>& tubes,
                   const std::vector<TubePlacement>& placements) {
  // The sleeve faces joined through each other; such a set is joined to the template when one of its
  // corners is a template face's (then so is its whole part), else it is a part of its own.
  UnionFind sets(mesh.vertex_count());
  std::vector<std::uint8_t> joined(mesh.vertex_count(), 0);
  for (Index f = 0; f < mesh.face_count(); ++f) {
    const Triangle& t = mesh.triangles[f];
    if (from_tube[f]) {
      sets.join(t[0], t[1]);
      sets.join(t[1], t[2]);
    } else {
      joined[t[0]] = joined[t[1]] = joined[t[2]] = 1;
    }
  }
  for (Index v = 0; v < mesh.vertex_count(); ++v)
    if (joined[v]) joined[sets.find(v)] = 1;
  std::vector<Index> kept;
  bool dropped = false;
  for (Index f = 0; f < mesh.face_count(); ++f) {
    if (!from_tube[f] || joined[sets.find(mesh.triangles[f][0])]) kept.push_back(f);
    else dropped = true;
  }
  if (!dropped) return false;
  std::vector<std::uint8_t> tube_faces;
  for (Index f : kept) tube_faces.push_back(from_tube[f]);
  mesh = submesh(mesh, kept);
  from_tube = std::move(tube_faces);
  for (std::size_t i = 0; i < tubes.size(); ++i) {
    if (placements[i].sleeve_inside_template) continue;
    const Vec3 axis = tube_axis(tubes[i]);
    bool has_sleeve = false;
    for (Index f = 0; f < mesh.face_count() && !has_sleeve; ++f) {
      if (!from_tube[f]) continue;
      const Vec3 q = mesh.positions[mesh.triangles[f][0]] - tubes[i].entry;
      const double h = q.dot(axis);
      has_sleeve = (q - h * axis).norm() <= tubes[i].outer_radius + 1e-3 && h > placements[i].column_bottom - 1e-3 &&
                   h < placements[i].sleeve_top + 1e-3;
    }
    if (!has_sleeve)
      throw conflict(tubes[i], tube_point(tubes[i], placements[i].sleeve_top),
                     placements[i].trimmed_by_bone
                         ? "sleeve stands on bone beside the template: the bone under it cuts it off from the template"
                         : "sleeve stands on bone beside the template, clear of it (it would not be joined)");
  }
  return true;
}

std::size_t drop_fragments(TriangleMesh& mesh, std::vector<std::uint8_t>& from_tube) {
  UnionFind sets(mesh.vertex_count());
  for (const Triangle& t : mesh.triangles) {
    sets.join(t[0], t[1]);
    sets.join(t[1], t[2]);
  }
  // One set (the usual case): nothing to weigh, nothing to drop.
  Index sets_used = 0;
  for (Index v = 0; v < mesh.vertex_count() && sets_used < 2; ++v) sets_used += sets.find(v) == v;
  if (sets_used <= 1) return 0;
  std::vector<double> volume(mesh.vertex_count(), 0.0);
  for (const Triangle& t : mesh.triangles)
    volume[sets.find(t[0])] += mesh.positions[t[0]].dot(mesh.positions[t[1]].cross(mesh.positions[t[2]])) / 6.0;
  Index largest = kInvalidIndex;
  std::size_t pieces = 0;
  for (Index v = 0; v < mesh.vertex_count(); ++v) {
    if (sets.find(v) != v || volume[v] == 0.0) continue;
    ++pieces;
    if (largest == kInvalidIndex || volume[v] > volume[largest]) largest = v;
  }
  if (pieces <= 1) return 0;
  std::vector<Index> kept;
  std::vector<std::uint8_t> tube_faces;
  for (Index f = 0; f < mesh.face_count(); ++f)
    if (sets.find(mesh.triangles[f][0]) == largest) {
      kept.push_back(f);
      tube_faces.push_back(from_tube[f]);
    }
  mesh = submesh(mesh, kept);
  from_tube = std::move(tube_faces);
  return pieces - 1;
}

AxisStretch axis_stretch(const TubeSpec& tube, const GuideOptions& options) {
  AxisStretch s;
  // Rays start above the sleeve and look for the template as far below the entry as the sleeve is
  // wide (steep bone) plus a margin.
  s.start = tube.offset + tube.length + options.bore_margin;
  s.reach = s.start + 3.0 * tube.outer_radius + 20.0;
  s.above = 3.0 * tube.outer_radius + 20.0;
  return s;
}

std::vector<std::vector<Index>> faces_around(const TriangleMesh& mesh, const std::vector<TubeSpec>& tubes,
                                             const GuideOptions& options) {
  struct Reach {
    Vec3 a, ab;
    double length2, radius;
    BoundingBox box;
  };
  std::vector<Reach> reaches;
  std::vector<FramedBox> prisms;
  for (const TubeSpec& tube : tubes) {
    const AxisStretch s = axis_stretch(tube, options);
    const Vec3 a = tube_point(tube, s.start + s.above), b = tube_point(tube, s.start - s.reach);
    BoundingBox box;
    box.extend(a);
    box.extend(b);
    reaches.push_back({a, b - a, (b - a).squaredNorm(), tube.outer_radius, box.inflated(tube.outer_radius)});
    FramedBox prism;
    Vec3 u, v;
    const Vec3 axis = tube_axis(tube);
    orthonormal_frame(axis, u, v);
    prism.axes << u.transpose(), v.transpose(), axis.transpose();
    prism.centre = 0.5 * (a + b);
    // Grown far beyond the rounding of a corner's coordinates in the frame.
    const double grown = 1e-9 * (1.0 + prism.centre.cwiseAbs().maxCoeff() + (b - a).norm() + tube.outer_radius);
    prism.half = Vec3(tube.outer_radius, tube.outer_radius, 0.5 * (b - a).norm()) + Vec3::Constant(grown);
    prisms.push_back(prism);
  }
  std::vector<std::vector<Index>> faces(tubes.size());
  for (Index f : faces_near_framed_boxes(mesh, prisms)) {
    const BoundingBox fb = triangle_box(mesh, f);
    const Vec3 c = fb.center();
    const double half = 0.5 * fb.size().norm();
    for (std::size_t i = 0; i < reaches.size(); ++i) {
      const Reach& r = reaches[i];
      if (!fb.overlaps(r.box)) continue;
      const double t = r.length2 > 0.0 ? std::clamp((c - r.a).dot(r.ab) / r.length2, 0.0, 1.0) : 0.0;
      const double reach = r.radius + half;
      if ((c - (r.a + t * r.ab)).squaredNorm() <= reach * reach) faces[i].push_back(f);
    }
  }
  return faces;
}

} // namespace st::guide_detail
