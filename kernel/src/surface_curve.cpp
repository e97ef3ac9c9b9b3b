#include "st/surface_curve.h"

#include "st/aabb_tree.h"
#include "st/errors.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <unordered_set>

namespace st {

namespace {

std::string where(const Vec3& p) {
  std::ostringstream s;
  s.precision(2);
  s << std::fixed << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return s.str();
}

Vec3 unit_normal(const TriangleMesh& mesh, Index f) {
  const Vec3 n = triangle_normal(mesh, f);
  const double len = n.norm();
  return len > 0.0 ? Vec3(n / len) : Vec3::Zero();
}

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

// Faces connected (across manifold edges) to `seeds` inside the candidate set.
std::vector<Index> connected_faces(const MeshTopology& topo, const std::vector<char>& candidate,
                                   const std::vector<Index>& seeds) {
  std::vector<char> seen(candidate.size(), 0);
  std::vector<Index> out, stack;
  for (Index s : seeds)
    if (!seen[s]) {
      seen[s] = 1;
      stack.push_back(s);
    }
  while (!stack.empty()) {
    const Index f = stack.back();
    stack.pop_back();
    out.push_back(f);
    for (Index k = 0; k < 3; ++k) {
      const Index o = topo.opposite(3 * f + k);
      if (o == kInvalidIndex) continue;
      const Index g = o / 3;
      if (candidate[g] && !seen[g]) {
        seen[g] = 1;
        stack.push_back(g);
      }
    }
  }
  return out;
}

// Closest point to p among the faces connected to `start` that come within `radius` of p.
ClosestPoint local_closest_point(const MeshTopology& topo, const Vec3& p, Index start, double radius) {
  const TriangleMesh& mesh = topo.mesh();
  ClosestPoint best;
  best.distance = std::numeric_limits<double>::infinity();
  std::vector<Index> stack{start};
  std::unordered_set<Index> seen{start};
  while (!stack.empty()) {
    const Index f = stack.back();
    stack.pop_back();
    const Triangle& t = mesh.triangles[f];
    const Vec3 q = closest_point_on_triangle(p, mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
    const double d = (q - p).norm();
    if (d < best.distance) best = {f, q, d};
    if (d > radius && f != start) continue;
    for (Index k = 0; k < 3; ++k) {
      const Index o = topo.opposite(3 * f + k);
      if (o == kInvalidIndex) continue;
      const Index g = o / 3;
      if (seen.insert(g).second) stack.push_back(g);
    }
  }
  return best;
}

class CurveTracer {
public:
  CurveTracer(const MeshTopology& topo, const AabbTree* tree, std::string name)
      : topo_(topo), mesh_(topo.mesh()), tree_(tree), name_(std::move(name)) {}

  // Walks from (a in fa) to (b in fb); appends crossings and their points. Returns false when the
  // walk could not reach fb (the caller subdivides).
  bool walk(const Vec3& a, Index fa, const Vec3& b, Index fb, std::vector<EdgeCrossing>& out,
            std::vector<Vec3>& points) const {
    if (fa == fb) return true;
    // Direction of travel: towards b, or, when b (almost) coincides with a on a shared edge or
    // vertex, from the centre of fa towards the centre of fb.
    Vec3 dir = b - a;
    const double scale = std::sqrt(triangle_normal(mesh_, fa).norm()) + 1e-300;
    if (dir.norm() < 1e-6 * scale) dir = centroid(fb) - centroid(fa);
    const double dir_len = dir.norm();
    if (!(dir_len > 0.0)) return false;
    dir /= dir_len;
    const Vec3 n = ring_normal(fa) + ring_normal(fb);
    Vec3 m = dir.cross(n);
    if (!(m.norm() > 1e-9)) return false;
    m.normalize();
    const double target = std::max((b - a).dot(dir), 0.0);
    Index f = fa;
    Index entry = kInvalidIndex;
    for (int step = 0; step < 4096; ++step) {
      if (f == fb) return true;
      const Triangle& tri = mesh_.triangles[f];
      double s[3];
      double longest = 0.0;
      for (int k = 0; k < 3; ++k) {
        s[k] = (mesh_.positions[tri[k]] - a).dot(m);
        longest = std::max(longest, (mesh_.positions[tri[(k + 1) % 3]] - mesh_.positions[tri[k]]).norm());
      }
      Index exit = kInvalidIndex;
      double exit_t = 0.0;
      Vec3 exit_x = Vec3::Zero();
      double best_progress = -std::numeric_limits<double>::infinity();
      for (Index k = 0; k < 3; ++k) {
        const Index h = 3 * f + k;
        if (h == entry) continue;
        const double su = s[k], sv = s[(k + 1) % 3];
        if ((su >= 0.0) == (sv >= 0.0)) continue;
        const double t = std::clamp(su / (su - sv), tol::kEdgeCutMargin, 1.0 - tol::kEdgeCutMargin);
        const Vec3 x = (1.0 - t) * mesh_.positions[tri[k]] + t * mesh_.positions[tri[(k + 1) % 3]];
        const double progress = (x - a).dot(dir);
        if (entry != kInvalidIndex || progress > best_progress) {
          best_progress = progress;
          exit = h;
          exit_t = t;
          exit_x = x;
        }
      }
      if (exit == kInvalidIndex) return false;
      // The walk must stay between a and b, give or take a triangle.
      const double progress = (exit_x - a).dot(dir);
      if (progress > target + 2.0 * longest || progress < -2.0 * longest) return false;
      const Index o = topo_.opposite(exit);
      if (o == kInvalidIndex)
        throw GeometryError(name_ + ": the curve runs into an open border or a non-manifold edge of the "
                            "mesh near " + where(exit_x) +
                            ": move the control points away from holes and the mesh's edge");
      out.push_back({exit, exit_t});
      points.push_back(exit_x);
      f = o / 3;
      entry = o;
    }
    return false;
  }

  void trace(const Vec3& a, Index fa, const Vec3& b, Index fb, int depth,
             std::vector<EdgeCrossing>& out, std::vector<Vec3>& points) const {
    std::vector<EdgeCrossing> c;
    std::vector<Vec3> p;
    if (walk(a, fa, b, fb, c, p)) {
      out.insert(out.end(), c.begin(), c.end());
      points.insert(points.end(), p.begin(), p.end());
      return;
    }
    if (depth >= 10 || (b - a).norm() < 1e-9)
      throw GeometryError(name_ + ": cannot follow the surface between " + where(a) + " and " + where(b) +
                          ": the surface has a gap or a sharp fold there; move the control points");
    const Vec3 half = 0.5 * (a + b);
    const ClosestPoint mid = tree_ ? *tree_->closest_point(half)
                                   : local_closest_point(topo_, half, fa, (b - a).norm() + 1e-9);
    trace(a, fa, mid.point, mid.face, depth + 1, out, points);
    points.push_back(mid.point);
    trace(mid.point, mid.face, b, fb, depth + 1, out, points);
  }

private:
  const MeshTopology& topo_;
  const TriangleMesh& mesh_;
  const AabbTree* tree_; // may be null: then midpoints are found by a local search
  std::string name_;

  // Area-weighted normal of the faces around f's corners: robust on sliver triangles.
  Vec3 ring_normal(Index f) const {
    Vec3 n = Vec3::Zero();
    for (Index v : mesh_.triangles[f])
      for (Index g : topo_.faces_of(v)) n += triangle_normal(mesh_, g);
    const double len = n.norm();
    return len > 0.0 ? Vec3(n / len) : unit_normal(mesh_, f);
  }

  Vec3 centroid(Index f) const {
    const Triangle& t = mesh_.triangles[f];
    return (mesh_.positions[t[0]] + mesh_.positions[t[1]] + mesh_.positions[t[2]]) / 3.0;
  }
};

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
void check_self_crossing(const TriangleMesh& mesh, const SurfaceCurve& curve,
                         const std::vector<Index>& point_faces, const CurveOptions& options) {
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
            throw GeometryError(options.name + ": the curve crosses itself near " + where(curve.polyline[si]) +
                                (options.smooth ? ": reorder or move the control points" : ""));
        }
    }
    lo = hi;
  }
}

// Joins the curve's samples by walks over the surface: fills crossings, polyline and length, and
// checks that the curve does not cross itself.
void join_samples(const MeshTopology& topology, const AabbTree* tree, const CurveOptions& options,
                  SurfaceCurve& curve) {
  const TriangleMesh& mesh = topology.mesh();
  // 4. Walk the surface between consecutive samples. The walk gives a sequence of events: points
  //    inside faces (samples, subdivision points) and edge crossings.
  struct Event {
    Vec3 point;
    Index face;                       // the face the curve is in after this event
    Index halfedge = kInvalidIndex;   // crossings only
    double t = 0.0;
  };
  const CurveTracer tracer(topology, tree, options.name);
  std::vector<Event> events;
  const std::size_t m = curve.samples.size();
  for (std::size_t i = 0; i < m; ++i) {
    const std::size_t j = (i + 1) % m;
    events.push_back({curve.samples[i], curve.sample_faces[i]});
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
        events.push_back({p[k], topology.opposite(c[ci].halfedge) / 3, c[ci].halfedge, c[ci].t});
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
    if (e.halfedge != kInvalidIndex) curve.crossings.push_back({e.halfedge, e.t});
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
  if (n < 3)
    throw InvalidInput(options.name + ": needs at least 3 control points, got " + std::to_string(n));
  for (std::size_t i = 0; i < n; ++i) {
    if (!control_points[i].allFinite())
      throw InvalidInput(options.name + ": control point " + std::to_string(i) + " has a non-finite coordinate");
    if ((control_points[i] - control_points[(i + 1) % n]).norm() < 1e-9)
      throw InvalidInput(options.name + ": control points " + std::to_string(i) + " and " +
                         std::to_string((i + 1) % n) + " coincide at " + where(control_points[i]));
  }
  if (!(options.max_snap_distance > 0.0))
    throw InvalidInput(options.name + ": max_snap_distance must be > 0");
  if (mesh.empty()) throw InvalidInput(options.name + ": the mesh has no triangles");

  // 1. Index only the triangles in a tube around the control polygon (the spline stays within a
  //    fraction of a segment's length of its chord), plus those near the extra point.
  BoundingBox box;
  double longest = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    box.extend(control_points[i]);
    longest = std::max(longest, (control_points[(i + 1) % n] - control_points[i]).norm());
  }
  const double snap_margin = options.max_snap_distance;
  BoundingBox near = box.inflated(snap_margin + 0.3 * longest);
  if (options.also_index) near.extend(BoundingBox{*options.also_index, *options.also_index}.inflated(snap_margin));
  std::vector<char> candidate(mesh.face_count(), 0);
  std::vector<Index> candidates;
  for (Index f = 0; f < mesh.face_count(); ++f) {
    const Triangle& t = mesh.triangles[f];
    BoundingBox b;
    for (Index v : t) b.extend(mesh.positions[v]);
    if (!b.overlaps(near)) continue;
    const Vec3 c = b.center();
    const double r = 0.5 * b.diagonal();
    bool in_tube = options.also_index && ((*options.also_index - c).norm() - r <= snap_margin);
    for (std::size_t i = 0; i < n && !in_tube; ++i) {
      const Vec3& a = control_points[i];
      const Vec3 ab = control_points[(i + 1) % n] - a;
      const double len2 = ab.squaredNorm();
      const double u = len2 > 0.0 ? std::clamp((c - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
      in_tube = (c - (a + u * ab)).norm() - r <= snap_margin + 0.3 * std::sqrt(len2);
    }
    if (in_tube) {
      candidate[f] = 1;
      candidates.push_back(f);
    }
  }
  if (candidates.empty())
    throw InvalidInput(options.name + ": no part of the mesh lies near the control points (first point " +
                       where(control_points[0]) + ")");

  SurfaceCurve curve;
  // 2. Snap, then keep to the connected part of the surface most control points lie on (CT noise
  //    islands and facing surfaces across thin gaps must not capture the curve).
  std::optional<AabbTree> tree;
  {
    AabbTree near_tree(mesh, candidates);
    std::vector<Index> snapped(n);
    for (std::size_t i = 0; i < n; ++i) {
      const auto c = near_tree.closest_point(control_points[i]);
      if (!c || c->distance > options.max_snap_distance)
        throw InvalidInput(options.name + ": control point " + std::to_string(i) + " " + where(control_points[i]) +
                           " is " + (c ? std::to_string(c->distance) : std::string("too far")) +
                           " mm from the surface (limit " + std::to_string(options.max_snap_distance) + " mm)");
      snapped[i] = c->face;
    }
    std::vector<Index> best;
    std::size_t best_hits = 0;
    std::vector<char> tried(n, 0);
    for (std::size_t i = 0; i < n && best_hits * 2 <= n; ++i) {
      if (tried[i]) continue;
      std::vector<Index> part = connected_faces(topology, candidate, {snapped[i]});
      std::sort(part.begin(), part.end());
      std::size_t hits = 0;
      for (std::size_t j = 0; j < n; ++j)
        if (std::binary_search(part.begin(), part.end(), snapped[j])) {
          ++hits;
          tried[j] = 1;
        }
      if (hits > best_hits) {
        best_hits = hits;
        best = std::move(part);
      }
    }
    curve.local_faces = std::move(best);
    if (curve.local_faces.size() == candidates.size()) tree.emplace(std::move(near_tree));
  }
  if (!tree) tree.emplace(mesh, curve.local_faces);
  double edge_sum = 0.0;
  for (Index f : curve.local_faces)
    for (int k = 0; k < 3; ++k)
      edge_sum += (mesh.positions[mesh.triangles[f][(k + 1) % 3]] - mesh.positions[mesh.triangles[f][k]]).norm();
  const double mean_edge = edge_sum / (3.0 * static_cast<double>(curve.local_faces.size()));

  for (std::size_t i = 0; i < n; ++i) {
    const auto c = tree->closest_point(control_points[i]);
    if (!c || c->distance > options.max_snap_distance)
      throw InvalidInput(options.name + ": control point " + std::to_string(i) + " " + where(control_points[i]) +
                         " is " + (c ? std::to_string(c->distance) : std::string("too far")) +
                         " mm from the connected part of the surface the other points lie on (limit " +
                         std::to_string(options.max_snap_distance) + " mm)");
    curve.control_points.push_back(c->point);
    curve.control_faces.push_back(c->face);
  }

  // 3. Dense spline samples, brought onto the surface.
  double polygon_length = 0.0;
  for (std::size_t i = 0; i < n; ++i)
    polygon_length += (curve.control_points[(i + 1) % n] - curve.control_points[i]).norm();
  double spacing = options.sample_spacing > 0.0 ? options.sample_spacing : tol::kCurveSampleSpacing * mean_edge;
  spacing = std::max(spacing, polygon_length / tol::kMaxCurveSamples);
  if (!options.smooth) {
    curve.samples = curve.control_points;
    curve.sample_faces = curve.control_faces;
  }
  const std::vector<Vec3> spline =
      options.smooth ? closed_catmull_rom(curve.control_points, spacing) : std::vector<Vec3>{};
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

  join_samples(topology, &*tree, options, curve);
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
  join_samples(topology, nullptr, options, curve);
  return curve;
}

} // namespace st
