#include "st/design/cut.h"

#include "st/core/aabb_tree.h"
#include "detail/format.h"
#include "st/core/errors.h"

#include <algorithm>
#include <deque>
#include <numeric>
#include <unordered_map>

namespace st {

namespace {

using detail::where;

std::uint64_t edge_key(Index a, Index b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | b;
}

struct EdgeCut {
  std::vector<double> t;      // crossing parameters from the lower to the higher vertex index
  std::vector<Index> through; // per crossing: the end it passes through (EdgeCrossing::through)
  int left_vote = 0;          // > 0: the higher vertex lies left of the curve
  Index new_vertex = kInvalidIndex;
  [[nodiscard]] bool odd() const { return t.size() % 2 == 1; }
};

constexpr signed char kLeft = 1, kRight = -1;

// Rim vertices closer than tol::kMinCutDistance_mm to the next one along the rim (a crossing next
// to a vertex the curve passes through, on a sliver triangle of the surface) are merged, the input
// vertex kept when one is: rounded to float they could fold the faces between them. A merge that
// would break the link condition or turn a face over is not made.
void merge_close_rim_vertices(CutResult& r, const MeshTopology& topology) {
  TriangleMesh& m = r.region;
  const double limit2 = tol::kMinCutDistance_mm * tol::kMinCutDistance_mm;
  // Most rims have no such pair: nothing to merge, and nothing to index.
  bool any_close = false;
  for (std::size_t i = 0; i < r.rim.size() && !any_close; ++i)
    any_close = (m.positions[r.rim[(i + 1) % r.rim.size()]] - m.positions[r.rim[i]]).squaredNorm() < limit2;
  if (!any_close) return;
  // The faces around each vertex: as the region had them (`topology`, the region's before any merge),
  // and those a merge moved onto it.
  std::vector<std::vector<Index>> moved_onto(m.vertex_count());
  auto faces_of = [&](Index v) {
    const std::span<const Index> listed = topology.faces_of(v);
    std::vector<Index> out(listed.begin(), listed.end());
    out.insert(out.end(), moved_onto[v].begin(), moved_onto[v].end());
    return out;
  };
  std::vector<char> removed(m.face_count(), 0), gone(m.vertex_count(), 0);
  auto neighbours = [&](Index v) {
    std::vector<Index> out;
    for (Index f : faces_of(v))
      if (!removed[f])
        for (Index w : m.triangles[f])
          if (w != v) out.push_back(w);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  };
  auto normal = [&](const Triangle& t) {
    return Vec3((m.positions[t[1]] - m.positions[t[0]]).cross(m.positions[t[2]] - m.positions[t[0]]));
  };
  auto merge = [&](Index keep, Index drop) {
    std::vector<Index> between, moved;
    for (Index f : faces_of(drop)) {
      if (removed[f]) continue;
      const Triangle& t = m.triangles[f];
      (std::find(t.begin(), t.end(), keep) != t.end() ? between : moved).push_back(f);
    }
    if (between.size() != 1) return false; // (keep, drop) is a border edge: one face
    std::vector<Index> common;
    const std::vector<Index> nk = neighbours(keep), nd = neighbours(drop);
    std::set_intersection(nk.begin(), nk.end(), nd.begin(), nd.end(), std::back_inserter(common));
    if (common.size() != 1) return false;
    for (Index f : moved) {
      Triangle t = m.triangles[f];
      const Vec3 before = normal(t);
      std::replace(t.begin(), t.end(), drop, keep);
      const Vec3 after = normal(t);
      if (!(after.dot(before) > 0.0)) return false;
    }
    removed[between[0]] = 1;
    for (Index f : moved) {
      std::replace(m.triangles[f].begin(), m.triangles[f].end(), drop, keep);
      moved_onto[keep].push_back(f);
    }
    gone[drop] = 1;
    return true;
  };
  // Along the rim, each vertex against the last one kept (and the last against the first); the rim
  // keeps at least 3 vertices.
  std::vector<Index> rim;
  auto try_merge = [&](Index a, Index b) { // a before b on the rim; returns the one kept, or nothing
    if ((m.positions[b] - m.positions[a]).squaredNorm() >= limit2) return kInvalidIndex;
    const bool keep_b = r.source_vertex[b] != kInvalidIndex && r.source_vertex[a] == kInvalidIndex;
    if (keep_b ? merge(b, a) : merge(a, b)) return keep_b ? b : a;
    return kInvalidIndex;
  };
  for (std::size_t i = 0; i < r.rim.size(); ++i) {
    const Index b = r.rim[i];
    if (!rim.empty() && rim.size() + (r.rim.size() - i) > 3)
      if (const Index kept = try_merge(rim.back(), b); kept != kInvalidIndex) {
        rim.back() = kept;
        continue;
      }
    rim.push_back(b);
  }
  if (rim.size() > 3)
    if (const Index kept = try_merge(rim.back(), rim.front()); kept != kInvalidIndex) {
      rim.front() = kept;
      rim.pop_back();
    }
  if (rim.size() == r.rim.size()) return;
  // Compact.
  std::vector<Index> new_index(m.vertex_count(), kInvalidIndex);
  CutResult out;
  for (Index v = 0; v < m.vertex_count(); ++v) {
    if (gone[v]) continue;
    new_index[v] = static_cast<Index>(out.region.positions.size());
    out.region.positions.push_back(m.positions[v]);
    out.source_vertex.push_back(r.source_vertex[v]);
    out.source.push_back(r.source[v]);
  }
  for (Index f = 0; f < m.face_count(); ++f)
    if (!removed[f])
      out.region.triangles.push_back(
          {new_index[m.triangles[f][0]], new_index[m.triangles[f][1]], new_index[m.triangles[f][2]]});
  for (Index v : rim) out.rim.push_back(new_index[v]);
  out.area = surface_area(out.region);
  r = std::move(out);
}

} // namespace

CutResult cut_region(const MeshTopology& topology, const SurfaceCurve& curve, const CutOptions& options) {
  const TriangleMesh& mesh = topology.mesh();
  if (curve.crossings.empty())
    throw GeometryError("the boundary curve encloses no mesh vertex: it lies within a single triangle");

  // 1. Crossings per edge; odd ones are cut.
  std::unordered_map<std::uint64_t, EdgeCut> cuts;
  cuts.reserve(curve.crossings.size() * 2);
  for (const EdgeCrossing& c : curve.crossings) {
    const Index u = topology.from_vertex(c.halfedge), v = topology.to_vertex(c.halfedge);
    EdgeCut& e = cuts[edge_key(u, v)];
    e.t.push_back(u < v ? c.t : 1.0 - c.t);
    e.through.push_back(c.through);
    // Leaving the face through u -> v: v is on the left of the curve.
    e.left_vote += (v > u) ? 1 : -1;
  }

  std::vector<signed char> side(mesh.vertex_count(), 0);
  std::vector<signed char> face_state(mesh.face_count(), 0); // 0 unseen, +-1 flooded side, 2 cut
  constexpr signed char kCutFace = 2;
  std::vector<Index> cut_faces;
  auto label = [&](Index v, signed char s, const Vec3& at) {
    if (side[v] == -s)
      throw GeometryError("the boundary curve does not separate the surface cleanly near " + where(at) +
                          ": it touches or crosses itself there");
    side[v] = s;
  };
  for (const EdgeCrossing& c : curve.crossings) {
    const Index u = topology.from_vertex(c.halfedge), v = topology.to_vertex(c.halfedge);
    const EdgeCut& e = cuts[edge_key(u, v)];
    if (!e.odd()) continue;
    const Index lo = std::min(u, v), hi = std::max(u, v);
    const Vec3 at = mesh.positions[lo];
    label(e.left_vote > 0 ? hi : lo, kLeft, at);
    label(e.left_vote > 0 ? lo : hi, kRight, at);
    for (Index h : {c.halfedge, topology.opposite(c.halfedge)}) {
      if (h == kInvalidIndex) continue;
      if (face_state[h / 3] != kCutFace) {
        face_state[h / 3] = kCutFace;
        cut_faces.push_back(h / 3);
      }
    }
  }
  if (cut_faces.empty())
    throw GeometryError("the boundary curve crosses every mesh edge an even number of times: it encloses "
                        "no region (near " +
                        where(curve.polyline.front()) + ")");

  auto is_cut_edge = [&](Index h) {
    const auto it = cuts.find(edge_key(topology.from_vertex(h), topology.to_vertex(h)));
    return it != cuts.end() && it->second.odd();
  };

  // 2. Flood both sides from the cut faces, the side with less area first; the first to close wins.
  std::deque<Index> queue[2];    // [0]: left, [1]: right
  std::vector<Index> flooded[2]; // whole faces taken by each side
  double area[2] = {0.0, 0.0};
  std::size_t border_edges[2] = {0, 0};
  Vec3 border_at[2] = {Vec3::Zero(), Vec3::Zero()};
  signed char walked = 0; // the side a walk from the inside point reached: flooded alone, unweighed
  auto q = [](signed char s) { return s == kLeft ? 0 : 1; };
  auto reach = [&](Index h, signed char s) {
    const Index o = topology.opposite(h);
    if (o == kInvalidIndex) {
      if (border_edges[q(s)]++ == 0)
        border_at[q(s)] = 0.5 * (mesh.positions[topology.from_vertex(h)] + mesh.positions[topology.to_vertex(h)]);
      return;
    }
    const Index g = o / 3;
    if (face_state[g] == 0) {
      face_state[g] = s;
      queue[q(s)].push_back(g);
    } else if (face_state[g] == -s) {
      throw GeometryError("the boundary curve does not separate the surface: both sides connect near " +
                          where(mesh.positions[mesh.triangles[g][0]]) +
                          " (the loop runs around a handle or through a hole of the mesh)");
    }
  };
  for (Index f : cut_faces) {
    int odd = 0;
    for (Index k = 0; k < 3; ++k) odd += is_cut_edge(3 * f + k);
    if (odd != 2)
      throw GeometryError("the boundary curve does not separate the surface cleanly near " +
                          where(mesh.positions[mesh.triangles[f][0]]));
    for (Index k = 0; k < 3; ++k)
      if (!is_cut_edge(3 * f + k)) reach(3 * f + k, side[mesh.triangles[f][k]]);
  }
  auto pop = [&](int qi) {
    const signed char s = qi == 0 ? kLeft : kRight;
    const Index f = queue[qi].front();
    queue[qi].pop_front();
    flooded[qi].push_back(f);
    if (walked == 0) area[qi] += 0.5 * triangle_normal(mesh, f).norm(); // for taking turns
    for (Index v : mesh.triangles[f]) {
      if (side[v] == -s)
        throw GeometryError("the boundary curve does not separate the surface: both sides meet at " +
                            where(mesh.positions[v]));
      side[v] = s;
    }
    for (Index k = 0; k < 3; ++k) reach(3 * f + k, s);
  };

  // Where is the inside point?
  Index inside_face = options.inside_face;
  if (options.inside && inside_face == kInvalidIndex) {
    double best = std::numeric_limits<double>::infinity();
    for (Index f : curve.local_faces) {
      const Triangle& t = mesh.triangles[f];
      const Vec3 c =
          closest_point_on_triangle(*options.inside, mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
      const double d = (c - *options.inside).squaredNorm();
      if (d < best) {
        best = d;
        inside_face = f;
      }
    }
  }
  auto inside_side = [&]() -> signed char {
    if (inside_face == kInvalidIndex) return 0;
    if (face_state[inside_face] != kCutFace) return face_state[inside_face];
    // On a cut face: the side of its nearest vertex.
    const Triangle& t = mesh.triangles[inside_face];
    Index best = t[0];
    for (Index v : t)
      if ((mesh.positions[v] - *options.inside).squaredNorm() < (mesh.positions[best] - *options.inside).squaredNorm())
        best = v;
    return side[best];
  };

  // With an inside point, a walk over the surface from its face towards the nearest cut face (each
  // step to a neighbour across an edge, nearer to it) reaches a face the seeding gave a side: the
  // inside point's, as the walk crossed no cut edge. Only that side is flooded then, and its faces come
  // in the same order as when both sides take turns (each side's queue grows from its own faces
  // alone): the same region, without flooding the other side as far. Where the walk stalls (a fold
  // of the surface), the sides take turns.
  if (options.inside && inside_face != kInvalidIndex && face_state[inside_face] != kCutFace) {
    auto centroid = [&](Index f) {
      const Triangle& t = mesh.triangles[f];
      return Vec3((mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) / 3.0);
    };
    Vec3 target = centroid(cut_faces.front());
    for (Index f : cut_faces)
      if (const Vec3 c = centroid(f); (c - *options.inside).squaredNorm() < (target - *options.inside).squaredNorm())
        target = c;
    Index g = inside_face;
    double gap = (centroid(g) - target).squaredNorm();
    while (face_state[g] == 0) {
      Index next = kInvalidIndex;
      for (Index k = 0; k < 3; ++k) {
        const Index o = topology.opposite(3 * g + k);
        if (o == kInvalidIndex) continue;
        if (const double d = (centroid(o / 3) - target).squaredNorm(); d < gap) {
          gap = d;
          next = o / 3;
        }
      }
      if (next == kInvalidIndex) break; // stalled
      g = next;
    }
    if (face_state[g] == kLeft || face_state[g] == kRight) walked = face_state[g];
  }
  int closed = -1;
  if (walked != 0) {
    while (!queue[q(walked)].empty()) pop(q(walked));
    closed = q(walked);
  }
  while (closed < 0) {
    const bool l = !queue[0].empty(), r = !queue[1].empty();
    if (!l) closed = 0;
    else if (!r) closed = 1;
    else pop(area[0] <= area[1] ? 0 : 1);
  }
  signed char keep = closed == 0 ? kLeft : kRight;
  if (options.inside) {
    signed char s = inside_side();
    if (s != keep) {
      keep = -keep;
      while (!queue[q(keep)].empty()) pop(q(keep));
      s = inside_side();
      if (s != keep)
        throw GeometryError("the inside point " + where(*options.inside) +
                            " is not on the surface the boundary curve lies on");
    }
  }
  if (options.require_closed_region && border_edges[q(keep)] > 0)
    throw GeometryError("the region inside the boundary contains a hole or an open edge of the mesh (" +
                        std::to_string(border_edges[q(keep)]) + " border edges, e.g. near " +
                        where(border_at[q(keep)]) + "): move the boundary around it or repair the mesh");

  // 3. Assemble the region: whole faces of the kept side plus the kept parts of the cut faces.
  CutResult result;
  std::vector<Index> new_index(mesh.vertex_count(), kInvalidIndex);
  auto vertex = [&](Index v) {
    if (new_index[v] == kInvalidIndex) {
      new_index[v] = static_cast<Index>(result.region.positions.size());
      result.region.positions.push_back(mesh.positions[v]);
      result.source_vertex.push_back(v);
      result.source.push_back({{v, v}, 0.0});
    }
    return new_index[v];
  };
  // Region vertices on the curve: cut vertices, and input vertices the curve passes through.
  std::vector<char> on_curve;
  auto cut_vertex = [&](Index a, Index b) {
    EdgeCut& e = cuts[edge_key(a, b)];
    if (e.new_vertex == kInvalidIndex) {
      // The median crossing (by t) of an edge crossed an odd number of times.
      std::vector<std::size_t> order(e.t.size());
      std::iota(order.begin(), order.end(), std::size_t{0});
      const auto mid = order.begin() + static_cast<std::ptrdiff_t>(order.size() / 2);
      std::nth_element(order.begin(), mid, order.end(), [&](std::size_t i, std::size_t j) { return e.t[i] < e.t[j]; });
      const double t = e.t[*mid];
      const Index lo = std::min(a, b), hi = std::max(a, b);
      if (e.through[*mid] != kInvalidIndex) {
        e.new_vertex = vertex(e.through[*mid]);
      } else {
        e.new_vertex = static_cast<Index>(result.region.positions.size());
        result.region.positions.push_back((1.0 - t) * mesh.positions[lo] + t * mesh.positions[hi]);
        result.source_vertex.push_back(kInvalidIndex);
        result.source.push_back({{lo, hi}, t});
      }
      on_curve.resize(result.region.positions.size(), 0);
      on_curve[e.new_vertex] = 1;
    }
    return e.new_vertex;
  };
  auto& tris = result.region.triangles;
  auto& pos = result.region.positions;
  // A triangle with a repeated corner is one a crossing through a vertex collapsed: there is none.
  auto emit = [&](Index a, Index b, Index c) {
    if (a != b && b != c && c != a) tris.push_back({a, b, c});
  };

  // The kept parts of the cut faces.
  for (Index f : cut_faces) {
    const Triangle& t = mesh.triangles[f];
    int kept = 0;
    for (Index v : t) kept += side[v] == keep;
    if (kept == 1) {
      int r = 0;
      while (side[t[r]] != keep) ++r;
      const Index a = t[r], b = t[(r + 1) % 3], c = t[(r + 2) % 3];
      const Index va = vertex(a), x1 = cut_vertex(a, b), x2 = cut_vertex(c, a);
      emit(va, x1, x2);
    } else {
      int r = 0;
      while (side[t[r]] == keep) ++r; // the dropped vertex
      const Index a = t[r], b = t[(r + 1) % 3], c = t[(r + 2) % 3];
      const Index x1 = cut_vertex(a, b), vb = vertex(b), vc = vertex(c), x2 = cut_vertex(c, a);
      // Through the dropped vertex a, the diagonal from the other crossing would run along an edge
      // (a flat triangle): take the diagonal from a then.
      const Index at_a = new_index[a];
      const bool through_a1 = at_a != kInvalidIndex && x1 == at_a;
      const bool through_a2 = at_a != kInvalidIndex && x2 == at_a;
      if (through_a2 || (!through_a1 && (pos[x1] - pos[vc]).squaredNorm() <= (pos[vb] - pos[x2]).squaredNorm())) {
        emit(x1, vb, vc);
        emit(x1, vc, x2);
      } else {
        emit(x1, vb, x2);
        emit(vb, vc, x2);
      }
    }
  }
  // Whole faces of the kept side, as the flood took them.
  for (Index f : flooded[q(keep)]) {
    const Triangle& t = mesh.triangles[f];
    emit(vertex(t[0]), vertex(t[1]), vertex(t[2]));
  }
  result.area = surface_area(result.region);

  // 4. The rim: the border loop made of the vertices on the curve. A curve that passes through a
  //    vertex twice pinches the region there.
  on_curve.resize(result.region.positions.size(), 0);
  const MeshTopology region_topology(result.region);
  const std::vector<Index> opposites = region_topology.all_opposites();
  std::vector<char> border_out(result.region.positions.size(), 0);
  for (Index h = 0; h < opposites.size(); ++h) {
    if (opposites[h] != kInvalidIndex) continue;
    const Index v = result.region.triangles[h / 3][h % 3];
    if (border_out[v]++)
      throw CurveCrossesItself("the boundary curve touches itself (it passes twice through the mesh vertex at " +
                               where(pos[v]) + "): move the control points apart there");
  }
  const auto loops = border_loops(result.region, opposites);
  int rim = -1;
  for (std::size_t i = 0; i < loops.size(); ++i) {
    bool all_cut = true;
    for (Index v : loops[i]) all_cut = all_cut && on_curve[v];
    if (!all_cut) continue;
    // A second border loop on the curve: the curve crosses itself (around a vertex or a few faces).
    if (rim >= 0)
      throw CurveCrossesItself("the boundary curve crosses itself: it cuts the surface into more than one "
                               "border loop near " +
                               where(pos[loops[i][0]]));
    rim = static_cast<int>(i);
  }
  if (rim < 0) throw GeometryError("the cut region has no border along the boundary curve");
  if (options.require_closed_region && loops.size() > 1) {
    for (std::size_t i = 0; i < loops.size(); ++i)
      if (static_cast<int>(i) != rim)
        throw GeometryError("the region inside the boundary has an extra border (a hole or a non-manifold "
                            "edge of the mesh) near " +
                            where(pos[loops[i][0]]) + ": move the boundary around it or repair the mesh");
  }
  result.rim = loops[static_cast<std::size_t>(rim)];
  merge_close_rim_vertices(result, region_topology);
  return result;
}

} // namespace st
