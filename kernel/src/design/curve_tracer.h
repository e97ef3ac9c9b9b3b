#pragma once
// Walking a curve over a triangle surface (private to surface_curve.cpp): from a point in one face to
// a point in another, in the plane through both that holds the surface normal, with the mesh edges
// it crosses; points on vertices and edges are ordinary cases.

#include "detail/format.h"
#include "st/core/aabb_tree.h"
#include "st/core/errors.h"
#include "st/core/tolerances.h"
#include "st/core/topology.h"
#include "st/design/surface_curve.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace st::curve_detail {

using detail::where;

inline Vec3 unit_normal(const TriangleMesh& mesh, Index f) {
  const Vec3 n = triangle_normal(mesh, f);
  const double len = n.norm();
  return len > 0.0 ? Vec3(n / len) : Vec3::Zero();
}

// The faces a local search has met: a table of a few hundred slots with linear probing (one small
// allocation, no node per face), doubled when half full.
class FaceSet {
public:
  FaceSet() : slots_(256, kInvalidIndex) {}
  /// Adds f; false when it was there already.
  bool insert(Index f) {
    if (2 * (count_ + 1) > slots_.size()) grow();
    if (!place(slots_, f)) return false;
    ++count_;
    return true;
  }

private:
  static bool place(std::vector<Index>& slots, Index f) {
    const std::size_t mask = slots.size() - 1;
    for (std::size_t s = (std::size_t{f} * 0x9E3779B97F4A7C15ull) >> 40 & mask;; s = (s + 1) & mask) {
      if (slots[s] == f) return false;
      if (slots[s] == kInvalidIndex) {
        slots[s] = f;
        return true;
      }
    }
  }
  void grow() {
    std::vector<Index> bigger(2 * slots_.size(), kInvalidIndex);
    for (const Index f : slots_)
      if (f != kInvalidIndex) place(bigger, f);
    slots_ = std::move(bigger);
  }
  std::vector<Index> slots_;
  std::size_t count_ = 0;
};

// Closest point to p among the faces connected to `start` that come within `radius` of p.
inline ClosestPoint local_closest_point(const MeshTopology& topo, const Vec3& p, Index start, double radius) {
  const TriangleMesh& mesh = topo.mesh();
  ClosestPoint best;
  best.distance = std::numeric_limits<double>::infinity();
  std::vector<Index> stack{start};
  FaceSet seen;
  seen.insert(start);
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
      if (seen.insert(g)) stack.push_back(g);
    }
  }
  return best;
}

class CurveTracer {
public:
  CurveTracer(const MeshTopology& topo, std::string name) : topo_(topo), mesh_(topo.mesh()), name_(std::move(name)) {}

  // Walks from (a in fa) to (b in fb) in the plane through a and b that holds the surface normal;
  // appends crossings and their points. Returns false when the walk could not reach fb (the caller
  // subdivides).
  //
  // Exact positions are ordinary cases. The side of the plane is decided by the sign of one number per
  // vertex, the same in every face of the walk, zero counted as positive: a vertex on the plane (the
  // walk along a row of grid vertices or through a vertex) is passed consistently on one side. A point
  // exactly at a vertex (a control point snapped to it, a sample on it) is a point of every face
  // around the vertex: the walk leaves it from the face of the fan it can go on from, reaches it in
  // whatever face of the fan it arrives in, and turns around the vertex to the face it was given (its
  // crossings lie next to the vertex and pass through it, EdgeCrossing::through). A step of zero
  // length is such a turn, or nothing. Points that share a face are joined in it; the caller goes
  // through a shared vertex (via_vertex) when the plane walk runs along an edge into a vertex.
  bool walk(const Vec3& a, Index fa, const Vec3& b, Index fb, std::vector<EdgeCrossing>& out,
            std::vector<Vec3>& points) const {
    if (fa == fb) return true;
    // The faces b lies on (fb, and those sharing the edge or corner of fb it lies on): reaching any of
    // them is reaching b.
    const std::vector<Index> at_b = faces_around(b, fb);
    if (arrive(b, at_b, fa, fb, out, points)) return true;
    // a and b on one face (a at a vertex or on an edge of a face b lies on): step across to it.
    const std::vector<Index> at_a = faces_around(a, fa);
    for (const Index g : at_a) {
      if (std::find(at_b.begin(), at_b.end(), g) == at_b.end()) continue;
      const std::size_t n_out = out.size(), n_points = points.size();
      if (step_to(a, fa, g, out, points) && arrive(b, at_b, g, fb, out, points)) return true;
      out.resize(n_out);
      points.resize(n_points);
    }
    // Direction of travel: towards b, or, when b (almost) coincides with a on a shared edge, from the
    // centre of fa towards the centre of fb.
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
    const Plane plane{a, dir, m};
    // Leave a from the face around it (fa, or one sharing the edge or corner a lies on) from which the
    // walk can go on.
    Index f = kInvalidIndex;
    for (const Index g : at_a)
      if (g == fa ? exit_of(g, kInvalidIndex, plane).exit != kInvalidIndex
                  : exit_of(g, kInvalidIndex, plane, true).exit != kInvalidIndex) {
        f = g;
        break;
      }
    if (f == kInvalidIndex || !step_to(a, fa, f, out, points)) return false;
    Index entry = kInvalidIndex;
    for (int step = 0; step < 4096; ++step) {
      if (arrive(b, at_b, f, fb, out, points)) return true;
      const Exit e = exit_of(f, entry, plane);
      if (e.exit == kInvalidIndex) return false;
      // The walk must stay between a and b, give or take a triangle.
      const double progress = (e.x - a).dot(dir);
      if (progress > target + 2.0 * e.longest || progress < -2.0 * e.longest) return false;
      const Index o = topo_.opposite(e.exit);
      if (o == kInvalidIndex) throw_border(e.x);
      out.push_back({e.exit, e.t, e.through});
      points.push_back(e.x);
      f = o / 3;
      entry = o;
    }
    return false;
  }

  void trace(const Vec3& a, Index fa, const Vec3& b, Index fb, int depth, std::vector<EdgeCrossing>& out,
             std::vector<Vec3>& points) const {
    std::vector<EdgeCrossing> c;
    std::vector<Vec3> p;
    bool joined = walk(a, fa, b, fb, c, p);
    if (!joined) {
      c.clear();
      p.clear();
      joined = via_vertex(a, fa, b, fb, c, p);
    }
    if (joined) {
      out.insert(out.end(), c.begin(), c.end());
      points.insert(points.end(), p.begin(), p.end());
      return;
    }
    if (depth >= 10 || (b - a).norm() < 1e-9)
      throw GeometryError(name_ + ": cannot follow the surface between " + where(a) + " and " + where(b) +
                          ": the surface has a gap or a sharp fold there; move the control points");
    const Vec3 half = 0.5 * (a + b);
    const ClosestPoint mid = local_closest_point(topo_, half, fa, (b - a).norm() + 1e-9);
    trace(a, fa, mid.point, mid.face, depth + 1, out, points);
    points.push_back(mid.point);
    trace(mid.point, mid.face, b, fb, depth + 1, out, points);
  }

private:
  // From a to b through a vertex that a face a lies on and a face b lies on share (the nearer way
  // round, when there are several): the path when the straight walk runs along an edge into a
  // vertex, where the plane's sides are decided by rounding.
  bool via_vertex(const Vec3& a, Index fa, const Vec3& b, Index fb, std::vector<EdgeCrossing>& out,
                  std::vector<Vec3>& points) const {
    const std::vector<Index> at_a = faces_around(a, fa), at_b = faces_around(b, fb);
    Index best = kInvalidIndex, g_best = kInvalidIndex, h_best = kInvalidIndex;
    double best_length = std::numeric_limits<double>::infinity();
    for (const Index g : at_a)
      for (const Index v : mesh_.triangles[g])
        for (const Index h : at_b) {
          const Triangle& t = mesh_.triangles[h];
          if (std::find(t.begin(), t.end(), v) == t.end()) continue;
          const double length = (mesh_.positions[v] - a).norm() + (b - mesh_.positions[v]).norm();
          if (length < best_length) {
            best_length = length;
            best = v;
            g_best = g;
            h_best = h;
          }
        }
    if (best == kInvalidIndex) return false;
    return step_to(a, fa, g_best, out, points) && turn(best, g_best, h_best, out, points) &&
           arrive(b, at_b, h_best, fb, out, points);
  }

  const MeshTopology& topo_;
  const TriangleMesh& mesh_;
  std::string name_;

  /// The walk's plane: through `origin`, normal `normal`; `dir` is the direction of travel in it.
  struct Plane {
    Vec3 origin, dir, normal;
  };

  /// Where the walk leaves a face: the half-edge, its parameter and point, and the face's longest edge.
  struct Exit {
    Index exit = kInvalidIndex;
    double t = 0.0;
    Index through = kInvalidIndex;
    Vec3 x = Vec3::Zero();
    double longest = 0.0;
  };

  /// The edge through which the walk leaves face f (entered through `entry`, or kInvalidIndex at the
  /// start: then the crossing farthest ahead, which with `ahead` must lie ahead of the origin). The
  /// side of each vertex: the sign of (p - origin).normal, zero counted as positive, the same in every
  /// face.
  Exit exit_of(Index f, Index entry, const Plane& plane, bool ahead = false) const {
    const Triangle& tri = mesh_.triangles[f];
    double s[3];
    Exit e;
    for (int k = 0; k < 3; ++k) {
      s[k] = (mesh_.positions[tri[k]] - plane.origin).dot(plane.normal);
      e.longest = std::max(e.longest, (mesh_.positions[tri[(k + 1) % 3]] - mesh_.positions[tri[k]]).norm());
    }
    double best_progress = -std::numeric_limits<double>::infinity();
    for (Index k = 0; k < 3; ++k) {
      const Index h = 3 * f + k;
      if (h == entry) continue;
      const double su = s[k], sv = s[(k + 1) % 3];
      if ((su >= 0.0) == (sv >= 0.0)) continue;
      const EdgeCrossing c = crossing(h, su / (su - sv));
      const Vec3 x = (1.0 - c.t) * mesh_.positions[tri[k]] + c.t * mesh_.positions[tri[(k + 1) % 3]];
      const double progress = (x - plane.origin).dot(plane.dir);
      if (entry != kInvalidIndex || progress > best_progress) {
        best_progress = progress;
        e.exit = h;
        e.t = c.t;
        e.through = c.through;
        e.x = x;
      }
    }
    if (ahead && !(best_progress > 0.0)) e.exit = kInvalidIndex;
    return e;
  }

  /// A cut never lands closer to an edge's ends than this fraction of it (tolerances.h).
  double margin(Index h) const {
    return tol::edge_cut_margin((mesh_.positions[topo_.to_vertex(h)] - mesh_.positions[topo_.from_vertex(h)]).norm());
  }

  /// The crossing of half-edge h at parameter t: within the margin of an end, through that end.
  EdgeCrossing crossing(Index h, double t) const {
    const double m = margin(h);
    EdgeCrossing c{h, std::clamp(t, m, 1.0 - m)};
    if (t <= m || t >= 1.0 - m) c.through = t < 0.5 ? topo_.from_vertex(h) : topo_.to_vertex(h);
    return c;
  }

  /// Where on face f the point p lies, to rounding (within 1e-9 of the face's longest edge): at a
  /// corner (0..2), on an edge (the half-edge 3f + k), or neither. Points built on an edge or at a
  /// vertex (snapped control points, closest points, ray hits on a grid) are there only to rounding.
  struct OnFace {
    int corner = -1;
    Index edge = kInvalidIndex;
  };
  OnFace on_face(Index f, const Vec3& p) const {
    const Triangle& t = mesh_.triangles[f];
    double longest = 0.0;
    for (int k = 0; k < 3; ++k)
      longest = std::max(longest, (mesh_.positions[t[(k + 1) % 3]] - mesh_.positions[t[k]]).norm());
    const double tol2 = 1e-18 * longest * longest;
    OnFace where;
    for (int k = 0; k < 3; ++k)
      if ((mesh_.positions[t[k]] - p).squaredNorm() <= tol2) {
        where.corner = k;
        return where;
      }
    for (int k = 0; k < 3; ++k) {
      const Vec3& u = mesh_.positions[t[k]];
      const Vec3 e = mesh_.positions[t[(k + 1) % 3]] - u;
      const double len2 = e.squaredNorm();
      if (!(len2 > 0.0)) continue;
      const double s = std::clamp((p - u).dot(e) / len2, 0.0, 1.0);
      if ((u + s * e - p).squaredNorm() <= tol2) {
        where.edge = 3 * f + k;
        return where;
      }
    }
    return where;
  }

  /// The faces p lies on besides f: f first, then those across the edge, or around the corner, of f
  /// that p lies on (nearest turns first).
  std::vector<Index> faces_around(const Vec3& p, Index f) const {
    const OnFace where = on_face(f, p);
    if (where.corner >= 0) return fan_by_turns(mesh_.triangles[f][where.corner], f);
    if (where.edge != kInvalidIndex && topo_.opposite(where.edge) != kInvalidIndex)
      return {f, topo_.opposite(where.edge) / 3};
    return {f};
  }

  /// From face f to face g, both around p (the same face, across the edge p lies on, or around the
  /// corner p lies at): the crossings that join them.
  bool step_to(const Vec3& p, Index f, Index g, std::vector<EdgeCrossing>& out, std::vector<Vec3>& points) const {
    if (f == g) return true;
    const OnFace where = on_face(f, p);
    if (where.corner >= 0) return turn(mesh_.triangles[f][where.corner], f, g, out, points);
    if (where.edge == kInvalidIndex || topo_.opposite(where.edge) == kInvalidIndex ||
        topo_.opposite(where.edge) / 3 != g)
      return false;
    const Index h = where.edge;
    const Vec3& u = mesh_.positions[topo_.from_vertex(h)];
    const Vec3 e = mesh_.positions[topo_.to_vertex(h)] - u;
    const EdgeCrossing c = crossing(h, (p - u).dot(e) / e.squaredNorm());
    out.push_back(c);
    points.push_back((1.0 - c.t) * u + c.t * mesh_.positions[topo_.to_vertex(h)]);
    return true;
  }

  /// Whether the walk, in face f, has reached b (given in face fb; `at_b` = faces_around(b, fb)): f is
  /// one of at_b; then the crossings from f to fb are appended.
  bool arrive(const Vec3& b, const std::vector<Index>& at_b, Index f, Index fb, std::vector<EdgeCrossing>& out,
              std::vector<Vec3>& points) const {
    if (f == fb) return true;
    if (std::find(at_b.begin(), at_b.end(), f) == at_b.end()) return false;
    // Join f to fb the way b joins them: around b's corner of fb, or across b's edge of fb.
    std::vector<EdgeCrossing> c;
    std::vector<Vec3> unused;
    if (!step_to(b, fb, f, c, unused)) return false;
    // step_to went from fb to f: the same crossings backwards, each over the opposite half-edge.
    for (std::size_t i = c.size(); i-- > 0;) {
      const Index o = topo_.opposite(c[i].halfedge);
      const double t = 1.0 - c[i].t;
      out.push_back({o, t, c[i].through});
      points.push_back((1.0 - t) * mesh_.positions[topo_.from_vertex(o)] + t * mesh_.positions[topo_.to_vertex(o)]);
    }
    return true;
  }

  /// The half-edge of face f leaving vertex v (forward == true) or arriving at it.
  Index halfedge_at(Index f, Index v, bool forward) const {
    for (int k = 0; k < 3; ++k)
      if (mesh_.triangles[f][k] == v) return 3 * f + (forward ? k : (k + 2) % 3);
    return kInvalidIndex;
  }

  /// The faces around v reached from f by crossing its edges at v one way (forward: the edge leaving
  /// v in each face), stopping at a border or back at f.
  std::vector<std::pair<Index, Index>> rotation(Index v, Index f, bool forward) const {
    std::vector<std::pair<Index, Index>> out; // (crossed half-edge, face entered)
    Index g = f;
    for (std::size_t i = 0; i <= topo_.faces_of(v).size(); ++i) {
      const Index h = halfedge_at(g, v, forward);
      const Index o = h == kInvalidIndex ? kInvalidIndex : topo_.opposite(h);
      if (o == kInvalidIndex || o / 3 == f) break;
      out.emplace_back(h, o / 3);
      g = o / 3;
    }
    return out;
  }

  /// The faces of v's fan by how many edges lie between them and f (f first), alternating sides.
  std::vector<Index> fan_by_turns(Index v, Index f) const {
    const auto fwd = rotation(v, f, true), back = rotation(v, f, false);
    std::vector<Index> out{f};
    for (std::size_t i = 0; i < std::max(fwd.size(), back.size()); ++i) {
      if (i < fwd.size()) out.push_back(fwd[i].second);
      if (i < back.size() && std::find(out.begin(), out.end(), back[i].second) == out.end())
        out.push_back(back[i].second);
    }
    return out;
  }

  /// Turns around vertex v from face f to face g (both around v) the shorter way, crossing each edge
  /// at v next to v. False when g is not reached (v is not manifold there).
  bool turn(Index v, Index f, Index g, std::vector<EdgeCrossing>& out, std::vector<Vec3>& points) const {
    if (f == g) return true;
    std::vector<std::pair<Index, Index>> best;
    for (const bool forward : {true, false}) {
      auto r = rotation(v, f, forward);
      const auto at = std::find_if(r.begin(), r.end(), [&](const auto& c) { return c.second == g; });
      if (at == r.end()) continue;
      r.erase(at + 1, r.end());
      if (best.empty() || r.size() < best.size()) best = r;
    }
    if (best.empty()) return false;
    for (const auto& [h, face] : best) {
      const bool from_v = topo_.from_vertex(h) == v;
      const double t = from_v ? margin(h) : 1.0 - margin(h);
      out.push_back({h, t, v});
      points.push_back((1.0 - t) * mesh_.positions[topo_.from_vertex(h)] + t * mesh_.positions[topo_.to_vertex(h)]);
    }
    return true;
  }

  [[noreturn]] void throw_border(const Vec3& x) const {
    throw GeometryError(name_ + ": the curve runs into an open border or a non-manifold edge of the mesh near " +
                        where(x) + ": move the control points away from holes and the mesh's edge");
  }
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

} // namespace st::curve_detail
