// Short edges at the intersection curve, collapsed after the result's coordinates are rounded, and
// the check of the faces made or moved there (check_fresh).
//
// A curve point within a few hundred float ulp of a neighbour makes sliver faces whose planes turn by
// whole degrees when their corners are rounded to float32, enough for two nearly tangent faces to
// cross. Such an edge is collapsed: one end moves onto the other, by less than the edge's length. Which
// end moves decides what keeps its shape; the second operand is the part added or cut as planned (a
// sleeve, a slot's housing or cut), the first the template, whose surface may move by that much:
// - a vertex of the first operand moves onto the curve point (the curve stays on the second
//   operand's surface); when that is not allowed, the curve point moves onto the vertex;
// - a curve point moves onto a vertex of the second operand, which lies on that surface already;
// - between two curve points, the one on a face of the second operand moves onto the one on an edge
//   of it (which lies on both faces of that edge: a slot's corner stays a corner); otherwise either.
// The link condition keeps the mesh 2-manifold, no moved face may turn over or cross a face around the
// edge, and every face that moved is handed to the final exact check (fresh), including faces of the
// first operand that took no part in the corefinement.

#include "boolean/corefinement.h"

#include "detail/format.h"
#include "st/boolean/triangle_intersection.h"
#include "st/core/aabb_tree.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <iterator>
#include <unordered_map>
#include <utility>
#include <vector>

namespace st::boolean_detail {

namespace {

enum class FaceState : std::uint8_t { other, fresh, unchanged };

class EdgeCollapser {
public:
  EdgeCollapser(TriangleMesh& m, const std::vector<VertexOrigin>& origin, const std::vector<Index>& fresh,
                const std::vector<Index>& unchanged)
      : m_(m), origin_(origin), removed_(m.face_count(), 0), gone_(m.vertex_count(), 0),
        state_(m.face_count(), FaceState::other) {
    for (Index f : fresh) state_[f] = FaceState::fresh;
    for (Index f : unchanged) state_[f] = FaceState::unchanged;
  }

  /// The short edges of fresh faces at a curve point, shortest first.
  std::vector<std::pair<Index, Index>> short_edges(const std::vector<Index>& fresh, double min_length) {
    std::vector<std::pair<double, std::pair<Index, Index>>> edges;
    for (Index f : fresh)
      for (int k = 0; k < 3; ++k) {
        const Index u = m_.triangles[f][k], v = m_.triangles[f][(k + 1) % 3];
        if (u > v || (!curve(u) && !curve(v))) continue;
        const double d2 = (m_.positions[u] - m_.positions[v]).squaredNorm();
        if (d2 < min_length * min_length) edges.push_back({d2, {u, v}});
      }
    std::sort(edges.begin(), edges.end());
    std::vector<std::pair<Index, Index>> out;
    out.reserve(edges.size());
    for (const auto& e : edges) out.push_back(e.second);
    return out;
  }

  /// Lists the faces around each end of the edges, the only vertices that may move.
  void index_faces(const std::vector<std::pair<Index, Index>>& edges) {
    std::vector<std::uint8_t> end(m_.vertex_count(), 0);
    for (const auto& [u, v] : edges) {
      faces_of_[u];
      faces_of_[v];
      end[u] = end[v] = 1;
    }
    for (Index f = 0; f < m_.face_count(); ++f)
      for (Index v : m_.triangles[f])
        if (end[v]) faces_of_[v].push_back(f);
  }

  /// Collapses the edge (u, v) one way or the other when allowed.
  void collapse_edge(Index u, Index v) {
    if (gone_[u] || gone_[v]) return;
    if (curve(u) && curve(v)) {
      // Onto the point on the second operand's edge first.
      const bool u_on_edge = origin_[u] == VertexOrigin::curve_on_second_edge;
      const Index drop = u_on_edge ? v : u, keep = u_on_edge ? u : v;
      if (!move(drop, keep)) move(keep, drop);
      return;
    }
    const Index point = curve(u) ? u : v, vertex = curve(u) ? v : u;
    if (origin_[vertex] == VertexOrigin::first) {
      if (!move(vertex, point)) move(point, vertex);
    } else {
      move(point, vertex);
    }
  }

  std::size_t collapses() const { return collapses_; }

  /// Drops the removed faces and the vertices moved away, in place: the others keep their relative
  /// order (a corner's id less the vertices dropped below it; no longer the order of first use that
  /// assemble() gave, which nothing relies on); the face lists follow. Only those vertices fall out of
  /// use: the link condition keeps the two opposite corners of each collapsed edge in other faces.
  void compact(BooleanResult& r, std::vector<Index>& fresh, std::vector<Index>& unchanged) {
    // Most of a result lies before its first dropped vertex and its first removed face (far faces come
    // first, pieces after them): those are neither renumbered nor moved.
    const Index first_gone = static_cast<Index>(std::find(gone_.begin(), gone_.end(), 1) - gone_.begin());
    std::vector<Index> below(m_.vertex_count() - first_gone);
    Index dropped = 0, kept_vertices = first_gone;
    for (Index v = first_gone; v < m_.vertex_count(); ++v) {
      below[v - first_gone] = dropped;
      if (gone_[v]) ++dropped;
      else m_.positions[kept_vertices++] = m_.positions[v];
    }
    m_.positions.resize(kept_vertices);
    fresh.clear();
    unchanged.clear();
    Index kept = 0;
    for (Index f = 0; f < m_.face_count(); ++f) {
      if (removed_[f]) continue;
      if (state_[f] == FaceState::fresh) fresh.push_back(kept);
      if (state_[f] == FaceState::unchanged) unchanged.push_back(kept);
      Triangle t = m_.triangles[f];
      for (Index& v : t) {
        if (v < first_gone) continue;
        if (gone_[v]) throw Degenerate{"a face left at a collapsed vertex"};
        v -= below[v - first_gone];
      }
      if (kept != f || t != m_.triangles[f]) {
        m_.triangles[kept] = t;
        r.from_b[kept] = r.from_b[f];
        r.source_face[kept] = r.source_face[f];
      }
      ++kept;
    }
    m_.triangles.resize(kept);
    r.from_b.resize(kept);
    r.source_face.resize(kept);
  }

private:
  bool curve(Index v) const {
    return origin_[v] == VertexOrigin::curve_on_first_edge || origin_[v] == VertexOrigin::curve_on_second_edge;
  }

  Vec3 normal(const Triangle& t) const {
    return (m_.positions[t[1]] - m_.positions[t[0]]).cross(m_.positions[t[2]] - m_.positions[t[0]]);
  }

  static std::vector<Index> sorted_unique(std::vector<Index> v) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
    return v;
  }

  /// Moves `drop` onto `keep` when that is allowed; returns whether it did.
  bool move(Index drop, Index keep) {
    std::vector<Index> shared, others, around_drop, around_keep;
    for (Index f : faces_of_[drop]) {
      if (removed_[f]) continue;
      const Triangle& t = m_.triangles[f];
      (std::find(t.begin(), t.end(), keep) != t.end() ? shared : others).push_back(f);
      for (Index w : t)
        if (w != drop) around_drop.push_back(w);
    }
    if (shared.size() != 2) return false;
    for (Index f : faces_of_[keep])
      if (!removed_[f])
        for (Index w : m_.triangles[f])
          if (w != keep) around_keep.push_back(w);
    around_drop = sorted_unique(std::move(around_drop));
    around_keep = sorted_unique(std::move(around_keep));
    std::vector<Index> common;
    std::set_intersection(around_drop.begin(), around_drop.end(), around_keep.begin(), around_keep.end(),
                          std::back_inserter(common));
    if (common.size() != 2) return false; // link condition: only the two opposite corners are shared
    // No moved face may turn over or cross a face around the edge (a fold the normals do not show).
    std::vector<Index> near = faces_of_[keep];
    near.insert(near.end(), others.begin(), others.end());
    auto moved = [&](Index f) {
      Triangle t = m_.triangles[f];
      std::replace(t.begin(), t.end(), drop, keep);
      return t;
    };
    for (Index f : others) {
      const Triangle t = moved(f);
      const Vec3 after = normal(t);
      if (!(after.dot(normal(m_.triangles[f])) > 0.0) || after.squaredNorm() == 0.0) return false;
      const std::array<Vec3, 3> pt = {m_.positions[t[0]], m_.positions[t[1]], m_.positions[t[2]]};
      for (Index g : near) {
        if (g == f || removed_[g] || std::find(shared.begin(), shared.end(), g) != shared.end()) continue;
        const Triangle u = moved(g);
        if (mesh_triangles_intersect(t, pt, u, {m_.positions[u[0]], m_.positions[u[1]], m_.positions[u[2]]}))
          return false;
      }
    }
    for (Index f : shared) removed_[f] = 1;
    for (Index f : others) {
      m_.triangles[f] = moved(f);
      state_[f] = FaceState::fresh; // moved: the final check looks at it
      faces_of_[keep].push_back(f);
    }
    gone_[drop] = 1;
    ++collapses_;
    return true;
  }

  TriangleMesh& m_;
  const std::vector<VertexOrigin>& origin_;
  std::vector<std::uint8_t> removed_, gone_;
  std::vector<FaceState> state_;
  std::unordered_map<Index, std::vector<Index>> faces_of_;
  std::size_t collapses_ = 0;
};

} // namespace

std::size_t collapse_short_edges(BooleanResult& r, const std::vector<VertexOrigin>& origin, double min_length,
                                 std::vector<Index>& fresh, std::vector<Index>& unchanged) {
  EdgeCollapser collapser(r.mesh, origin, fresh, unchanged);
  const std::vector<std::pair<Index, Index>> edges = collapser.short_edges(fresh, min_length);
  if (edges.empty()) return 0;
  collapser.index_faces(edges);
  for (const auto& [u, v] : edges) collapser.collapse_edge(u, v);
  if (collapser.collapses() == 0) return 0;
  collapser.compact(r, fresh, unchanged);
  return collapser.collapses();
}

void check_fresh(const TriangleMesh& out, const std::vector<Index>& fresh, const std::vector<Index>& unchanged,
                 bool debug) {
  for (Index f : fresh) {
    const Triangle& t = out.triangles[f];
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) throw Degenerate{"two corners rounded together"};
    const Vec3 n = (out.positions[t[1]] - out.positions[t[0]]).cross(out.positions[t[2]] - out.positions[t[0]]);
    if (n.squaredNorm() == 0.0) throw Degenerate{"a triangle rounded flat"};
  }
  if (fresh.empty()) return;
  auto test = [&](Index f, Index g) {
    const Triangle &ta = out.triangles[f], &tb = out.triangles[g];
    const std::array<Vec3, 3> pa = {out.positions[ta[0]], out.positions[ta[1]], out.positions[ta[2]]};
    const std::array<Vec3, 3> pb = {out.positions[tb[0]], out.positions[tb[1]], out.positions[tb[2]]};
    if (mesh_triangles_intersect(ta, pa, tb, pb)) {
      if (debug) {
        std::fprintf(stderr, "  crossing faces %u and %u:\n", f, g);
        for (const auto* p : {&pa, &pb})
          std::fprintf(stderr, "    (%.9g %.9g %.9g) (%.9g %.9g %.9g) (%.9g %.9g %.9g)\n", (*p)[0].x(), (*p)[0].y(),
                       (*p)[0].z(), (*p)[1].x(), (*p)[1].y(), (*p)[1].z(), (*p)[2].x(), (*p)[2].y(), (*p)[2].z());
        std::fprintf(stderr, "    ids %u %u %u / %u %u %u\n", ta[0], ta[1], ta[2], tb[0], tb[1], tb[2]);
      }
      throw Degenerate{"faces near the intersection curve cross after rounding, near " + detail::where(pa[0])};
    }
  };
  const AabbTree tree(out, fresh);
  tree.for_each_overlapping_pair(test);
  // Every unchanged face near them, not only those sharing a corner: a collapse can swing a fresh
  // face through a face a little way off.
  BoundingBox near;
  for (Index f : fresh) near.extend(triangle_box(out, f));
  for (Index g : unchanged) {
    const BoundingBox box = triangle_box(out, g);
    if (!box.overlaps(near)) continue;
    tree.for_each_in_box(box, [&](Index f) { test(f, g); });
  }
}

} // namespace st::boolean_detail
