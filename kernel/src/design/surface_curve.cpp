#include "st/design/surface_curve.h"

#include "design/curve_tracer.h"

#include "st/core/aabb_tree.h"
#include "detail/format.h"
#include "st/core/errors.h"

#include <algorithm>
#include <cmath>
#include <queue>
#include <unordered_set>

namespace st {

namespace {

using namespace curve_detail;

// Barry-Goldman evaluation of a centripetal Catmull-Rom segment between p1 and p2.
Vec3 catmull_rom(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& p3, double u) {
  auto knot = [](const Vec3& a, const Vec3& b) { return std::max(std::sqrt((b - a).norm()), 1e-9); };
  const double t0 = 0.0;
  const double t1 = t0 + knot(p0, p1);
  const double t2 = t1 + knot(p1, p2);
  const double t3 = t2 + knot(p2, p3);
  const double t = t1 + u * (t2 - t1);
  const Vec3 a1 = (t1 - t) / (t1 - t0) * p0 + (t - t0) / (t1 - t0) * p1;
  const Vec3 a2 = (t2 - t) / (t2 - t1) * p1 + (t - t1) / (t2 - t1) * p2;
  const Vec3 a3 = (t3 - t) / (t3 - t2) * p2 + (t - t2) / (t3 - t2) * p3;
  const Vec3 b1 = (t2 - t) / (t2 - t0) * a1 + (t - t0) / (t2 - t0) * a2;
  const Vec3 b2 = (t3 - t) / (t3 - t1) * a2 + (t - t1) / (t3 - t1) * a3;
  return (t2 - t) / (t2 - t1) * b1 + (t - t1) / (t2 - t1) * b2;
}

double segment_param_2d(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  const Eigen::Vector2d u = b - a, v = c - a;
  return u.x() * v.y() - u.y() * v.x();
}

bool segments_cross_2d(const Eigen::Vector2d& p0, const Eigen::Vector2d& p1, const Eigen::Vector2d& q0,
                       const Eigen::Vector2d& q1) {
  const double d1 = segment_param_2d(p0, p1, q0), d2 = segment_param_2d(p0, p1, q1);
  const double d3 = segment_param_2d(q0, q1, p0), d4 = segment_param_2d(q0, q1, p1);
  return ((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0));
}

// The curve inside each face is a set of segments; two non-consecutive ones crossing means the
// curve crosses itself.
void check_self_crossing(const TriangleMesh& mesh, const SurfaceCurve& curve, const std::vector<Index>& point_faces,
                         const CurveOptions& options) {
  const std::size_t n = curve.polyline.size();
  std::vector<std::pair<Index, Index>> by_face; // (face, segment index)
  by_face.reserve(n);
  for (std::size_t i = 0; i < n; ++i) by_face.emplace_back(point_faces[i], static_cast<Index>(i));
  std::sort(by_face.begin(), by_face.end());
  for (std::size_t lo = 0; lo < by_face.size();) {
    std::size_t hi = lo;
    while (hi < by_face.size() && by_face[hi].first == by_face[lo].first) ++hi;
    if (hi - lo >= 2) {
      const Vec3 nrm = triangle_normal(mesh, by_face[lo].first);
      int drop = 0;
      nrm.cwiseAbs().maxCoeff(&drop);
      const int ax = (drop + 1) % 3, ay = (drop + 2) % 3;
      auto p2 = [&](std::size_t i) { return Eigen::Vector2d(curve.polyline[i % n][ax], curve.polyline[i % n][ay]); };
      for (std::size_t i = lo; i < hi; ++i)
        for (std::size_t j = i + 1; j < hi; ++j) {
          const std::size_t si = by_face[i].second, sj = by_face[j].second;
          if ((si + 1) % n == sj || (sj + 1) % n == si) continue;
          if (segments_cross_2d(p2(si), p2(si + 1), p2(sj), p2(sj + 1)))
            throw CurveCrossesItself(options.name + ": the curve crosses itself near " + where(curve.polyline[si]) +
                                     (options.name == "boundary" ? ": reorder or move the control points" : ""));
        }
    }
    lo = hi;
  }
}

// Joins the curve's samples by walks over the surface: fills crossings, polyline and length, and
// checks that the curve does not cross itself.
void join_samples(const MeshTopology& topology, const CurveOptions& options, SurfaceCurve& curve) {
  const TriangleMesh& mesh = topology.mesh();
  // 4. Walk the surface between consecutive samples. The walk gives a sequence of events: points
  //    inside faces (samples, subdivision points) and edge crossings.
  struct Event {
    Vec3 point;
    Index face;                     // the face the curve is in after this event
    Index halfedge = kInvalidIndex; // crossings only
    double t = 0.0;
    Index through = kInvalidIndex;
  };
  const CurveTracer tracer(topology, options.name);
  std::vector<Event> events;
  const std::size_t m = curve.samples.size();
  for (std::size_t i = 0; i < m; ++i) {
    const std::size_t j = (i + 1) % m;
    events.push_back({curve.samples[i], curve.sample_faces[i]});
    // A step of zero length is no step: the next sample is this point, in the face the curve is in.
    if (j != 0 && curve.samples[j] == curve.samples[i]) {
      curve.sample_faces[j] = curve.sample_faces[i];
      continue;
    }
    std::vector<EdgeCrossing> c;
    std::vector<Vec3> p;
    tracer.trace(curve.samples[i], curve.sample_faces[i], curve.samples[j], curve.sample_faces[j], 0, c, p);
    for (std::size_t k = 0, ci = 0; k < p.size(); ++k) {
      // Subdivision points are not crossings; they lie in the face the last crossing entered.
      const bool crossing =
          ci < c.size() && (p[k] - ((1.0 - c[ci].t) * mesh.positions[topology.from_vertex(c[ci].halfedge)] +
                                    c[ci].t * mesh.positions[topology.to_vertex(c[ci].halfedge)]))
                                   .squaredNorm() == 0.0;
      if (crossing) {
        events.push_back({p[k], topology.opposite(c[ci].halfedge) / 3, c[ci].halfedge, c[ci].t, c[ci].through});
        ++ci;
      } else {
        events.push_back({p[k], events.back().face});
      }
    }
  }
  // Samples projected near an edge may step over it and straight back: drop such excursions
  // (a crossing followed, after points in the other face only, by the crossing back over the same
  // edge). Parity and the curve's path are unchanged, and no spurious self-crossing is left.
  std::vector<Event> kept;
  kept.reserve(events.size());
  std::vector<std::size_t> crossing_at; // indices into `kept` of its crossings
  for (const Event& e : events) {
    if (e.halfedge != kInvalidIndex && !crossing_at.empty() &&
        topology.opposite(kept[crossing_at.back()].halfedge) == e.halfedge) {
      kept.resize(crossing_at.back());
      crossing_at.pop_back();
      continue;
    }
    if (e.halfedge != kInvalidIndex) crossing_at.push_back(kept.size());
    kept.push_back(e);
  }
  std::vector<Index> point_faces;
  for (const Event& e : kept) {
    curve.polyline.push_back(e.point);
    point_faces.push_back(e.face);
    if (e.halfedge != kInvalidIndex) curve.crossings.push_back({e.halfedge, e.t, e.through});
  }
  for (std::size_t i = 0; i < curve.polyline.size(); ++i)
    curve.length += (curve.polyline[(i + 1) % curve.polyline.size()] - curve.polyline[i]).norm();
  if (options.check_self_crossing) check_self_crossing(mesh, curve, point_faces, options);
}

} // namespace

std::vector<Vec3> closed_catmull_rom(const std::vector<Vec3>& points, double spacing) {
  const std::size_t n = points.size();
  std::vector<Vec3> out;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& p0 = points[(i + n - 1) % n];
    const Vec3& p1 = points[i];
    const Vec3& p2 = points[(i + 1) % n];
    const Vec3& p3 = points[(i + 2) % n];
    const int steps = std::max(1, static_cast<int>(std::ceil((p2 - p1).norm() / spacing)));
    for (int s = 0; s < steps; ++s) out.push_back(catmull_rom(p0, p1, p2, p3, static_cast<double>(s) / steps));
  }
  return out;
}

SurfaceCurve trace_surface_curve(const MeshTopology& topology, const std::vector<Vec3>& control_points,
                                 const CurveOptions& options) {
  const TriangleMesh& mesh = topology.mesh();
  const std::size_t n = control_points.size();
  if (n < 3) throw InvalidInput(options.name + ": needs at least 3 control points, got " + std::to_string(n));
  for (std::size_t i = 0; i < n; ++i) {
    if (!control_points[i].allFinite())
      throw InvalidInput(options.name + ": control point " + std::to_string(i) + " has a non-finite coordinate");
    if ((control_points[i] - control_points[(i + 1) % n]).norm() < 1e-9)
      throw InvalidInput(options.name + ": control points " + std::to_string(i) + " and " +
                         std::to_string((i + 1) % n) + " coincide at " + where(control_points[i]));
  }
  if (!(options.max_snap_distance > 0.0)) throw InvalidInput(options.name + ": max_snap_distance must be > 0");
  if (mesh.empty()) throw InvalidInput(options.name + ": the mesh has no triangles");

  // 1. The faces within the snap distance of each control point (and of the extra point): one pass
  //    over the mesh's bounding boxes, nothing indexed. The rest of the work follows the surface.
  const double reach = options.max_snap_distance;
  std::vector<Vec3> centres(control_points);
  std::vector<double> radii(n, reach);
  if (options.also_index) {
    centres.push_back(*options.also_index);
    radii.push_back(2.0 * reach);
  }
  BoundingBox all;
  for (std::size_t i = 0; i < centres.size(); ++i) all.extend(BoundingBox{centres[i], centres[i]}.inflated(radii[i]));
  // Faces come in increasing order: each point's list, and the faces near any (the local faces).
  std::vector<std::vector<std::pair<double, Index>>> near(centres.size()); // (distance, face) per point
  SurfaceCurve curve;
  for (Index f = 0; f < mesh.face_count(); ++f) {
    const Triangle& t = mesh.triangles[f];
    BoundingBox b;
    for (Index v : t) b.extend(mesh.positions[v]);
    if (!b.overlaps(all)) continue;
    bool local = false;
    for (std::size_t i = 0; i < centres.size(); ++i) {
      if (!b.inflated(radii[i]).contains(centres[i])) continue;
      const Vec3 q =
          closest_point_on_triangle(centres[i], mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
      const double d = (q - centres[i]).norm();
      if (d <= radii[i]) {
        near[i].emplace_back(d, f);
        local = true;
      }
    }
    if (local) curve.local_faces.push_back(f);
  }

  // 2. Snap each control point to the closest face that belongs to a surface reaching beyond its
  //    snap ball: CT noise islands (small components wholly inside the ball) never capture a point.
  //    The faces are tried nearest first (the nearest alone, as a rule); a face's flood within the ball
  //    goes farthest face first, so that on a surface reaching beyond the ball it leaves the ball after
  //    a walk across it rather than a flood of it (a piece wholly inside is flooded whole either way).
  for (std::size_t i = 0; i < n; ++i) {
    const auto& faces = near[i]; // in increasing face order
    auto in_ball = [&](Index f) {
      const auto it = std::lower_bound(faces.begin(), faces.end(), f,
                                       [](const std::pair<double, Index>& e, Index g) { return e.second < g; });
      return it != faces.end() && it->second == f ? it : faces.end();
    };
    std::vector<Index> island; // faces known to lie on small pieces, sorted
    auto escapes_from = [&](Index f, double d) {
      std::priority_queue<std::pair<double, Index>> front; // farthest first
      front.emplace(d, f);
      std::unordered_set<Index> piece{f};
      while (!front.empty()) {
        const Index g = front.top().second;
        front.pop();
        for (Index k = 0; k < 3; ++k) {
          const Index o = topology.opposite(3 * g + k);
          if (o == kInvalidIndex) continue;
          const auto at = in_ball(o / 3);
          if (at == faces.end()) return true;
          if (piece.insert(o / 3).second) front.emplace(at->first, o / 3);
        }
      }
      island.insert(island.end(), piece.begin(), piece.end());
      std::sort(island.begin(), island.end());
      return false;
    };
    Index chosen = kInvalidIndex;
    if (!faces.empty()) {
      const auto nearest = *std::min_element(faces.begin(), faces.end());
      if (escapes_from(nearest.second, nearest.first)) chosen = nearest.second;
    }
    if (chosen == kInvalidIndex && !island.empty()) {
      std::vector<std::pair<double, Index>> by_distance = faces;
      std::sort(by_distance.begin(), by_distance.end());
      for (const auto& [d, f] : by_distance) {
        if (std::binary_search(island.begin(), island.end(), f)) continue;
        if (escapes_from(f, d)) {
          chosen = f;
          break;
        }
      }
    }
    if (chosen == kInvalidIndex)
      throw InvalidInput(options.name + ": control point " + std::to_string(i) + " " + where(control_points[i]) +
                         " is farther than " + detail::number(options.max_snap_distance) +
                         " mm from the surface (only small loose pieces, if anything, are that close)");
    const Triangle& t = mesh.triangles[chosen];
    curve.control_points.push_back(
        closest_point_on_triangle(control_points[i], mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]));
    curve.control_faces.push_back(chosen);
  }

  // Mean edge length around the control points sets the sampling density.
  double edge_sum = 0.0;
  std::size_t edge_count = 0;
  for (std::size_t i = 0; i < n; ++i)
    for (const auto& [d, f] : near[i])
      for (int k = 0; k < 3; ++k, ++edge_count)
        edge_sum += (mesh.positions[mesh.triangles[f][(k + 1) % 3]] - mesh.positions[mesh.triangles[f][k]]).norm();
  const double mean_edge = edge_sum / static_cast<double>(std::max<std::size_t>(edge_count, 1));

  // 3. Dense spline samples, brought onto the surface.
  double polygon_length = 0.0;
  for (std::size_t i = 0; i < n; ++i)
    polygon_length += (curve.control_points[(i + 1) % n] - curve.control_points[i]).norm();
  double spacing = options.sample_spacing > 0.0 ? options.sample_spacing : tol::kCurveSampleSpacing * mean_edge;
  spacing = std::max(spacing, polygon_length / tol::kMaxCurveSamples);
  const std::vector<Vec3> spline = closed_catmull_rom(curve.control_points, spacing);
  // Each sample is brought onto the surface near the previous one (a local closest-point search
  // over the faces connected to it), so the curve cannot jump across a thin process or a narrow
  // gap to a surface that is merely close in space.
  Index previous_face = curve.control_faces[0];
  Vec3 previous = curve.control_points[0];
  for (const Vec3& s : spline) {
    const double radius = (s - previous).norm() + 2.0 * mean_edge;
    const auto c = local_closest_point(topology, s, previous_face, radius);
    previous_face = c.face;
    previous = c.point;
    if (!curve.samples.empty() && (c.point - curve.samples.back()).norm() < 1e-9) continue;
    curve.samples.push_back(c.point);
    curve.sample_faces.push_back(c.face);
  }
  if (curve.samples.size() > 1 && (curve.samples.front() - curve.samples.back()).norm() < 1e-9) {
    curve.samples.pop_back();
    curve.sample_faces.pop_back();
  }
  if (curve.samples.size() < 3) throw InvalidInput(options.name + ": the control points enclose no area");

  join_samples(topology, options, curve);
  return curve;
}

} // namespace st

namespace st {

SurfaceCurve join_surface_points(const MeshTopology& topology, const std::vector<Vec3>& points,
                                 const std::vector<Index>& faces, const CurveOptions& options) {
  if (points.size() < 3 || points.size() != faces.size())
    throw InvalidInput(options.name + ": needs at least 3 points, each with its face");
  for (Index f : faces)
    if (f >= topology.mesh().face_count()) throw InvalidInput(options.name + ": face index out of range");
  SurfaceCurve curve;
  curve.control_points = points;
  curve.control_faces = faces;
  curve.samples = points;
  curve.sample_faces = faces;
  join_samples(topology, options, curve);
  return curve;
}

} // namespace st
