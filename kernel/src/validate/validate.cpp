#include "st/validate/validate.h"

#include "detail/morton.h"
#include "detail/parallel.h"
#include "st/core/aabb_tree.h"
#include "st/core/errors.h"
#include "st/core/predicates.h"
#include "st/core/topology.h"
#include "st/boolean/triangle_intersection.h"
#include "validate/embedded_patch.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <sstream>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace st {

std::string SolidReport::summary() const {
  std::ostringstream s;
  s << triangles << " triangles, " << vertices << " vertices, " << components << " component(s); ";
  if (valid()) {
    s << "closed, 2-manifold, outward oriented, no self-intersection; volume " << volume << " mm^3";
    return s.str();
  }
  s << "NOT a valid solid:";
  if (border_edges) s << " " << border_edges << " border edges;";
  if (nonmanifold_edges) s << " " << nonmanifold_edges << " non-manifold edges;";
  if (nonmanifold_vertices) s << " " << nonmanifold_vertices << " non-manifold vertices;";
  if (misoriented_edges) s << " " << misoriented_edges << " inconsistently oriented edges;";
  if (!(volume > 0.0)) s << " volume " << volume << " mm^3 (not outward oriented);";
  if (degenerate_triangles) s << " " << degenerate_triangles << " degenerate triangles;";
  if (self_intersections) s << " " << self_intersections << " self-intersecting triangle pairs;";
  if (!problem_points.empty()) {
    const Vec3& p = problem_points.front();
    s << " first at (" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  }
  return s.str();
}

namespace {

// Whether the closed fan of faces `around` v (one walk reaches them all) projects one to one onto the
// axis plane most across it: every face, projected, turns the same way about v, and the edges
// opposite v (a closed cycle) wind once around it, so that the projected faces tile the turn about v
// once. The fan is then the graph of a function over that plane, and two of its faces meet only
// where they share a corner or an edge. Exact (orient2d on coordinates dropped, not rounded); the
// faces' turns are `turns` (validate_detail::projection_turns).
bool star_fan(const TriangleMesh& mesh, Index v, std::span<const Index> around,
              const std::vector<std::uint8_t>& turns) {
  Vec3 sum = Vec3::Zero();
  for (const Index f : around) sum += triangle_normal(mesh, f);
  int axis = 0;
  sum.cwiseAbs().maxCoeff(&axis);
  if (sum[axis] == 0.0) return false;
  const int turn = sum[axis] > 0.0 ? 1 : -1;
  auto projected = [&](Index w) {
    const Vec3& p = mesh.positions[w];
    return std::array<double, 2>{p[(axis + 1) % 3], p[(axis + 2) % 3]};
  };
  const std::array<double, 2> c = projected(v);
  int winding = 0;
  for (const Index f : around) {
    const Triangle& t = mesh.triangles[f];
    const int k = t[0] == v ? 0 : t[1] == v ? 1 : 2;
    if (!(turns[f] & (1u << (2 * axis + (turn > 0 ? 0 : 1))))) return false; // (v, a, b) turns as the face
    const std::array<double, 2> a = projected(t[(k + 1) % 3]), b = projected(t[(k + 2) % 3]);
    // The edge a -> b across the half-line from c along +x (Sunday's crossing rule; exact).
    if (a[1] <= c[1]) {
      if (b[1] > c[1] && orient2d(a.data(), b.data(), c.data()) > 0) ++winding;
    } else if (b[1] <= c[1] && orient2d(a.data(), b.data(), c.data()) < 0) {
      --winding;
    }
  }
  return winding == turn;
}

} // namespace

SolidReport check_solid(const TriangleMesh& mesh, const SolidOptions& options) {
  SolidReport r;
  r.vertices = mesh.vertex_count();
  r.triangles = mesh.face_count();
  r.area = surface_area(mesh);
  r.volume = signed_volume(mesh);
  // What is found is gathered per chunk of faces (vertices), in order, so that the report does not
  // depend on the number of threads.
  constexpr std::size_t kGrain = 4096;
  struct Found {
    std::size_t degenerate = 0, border = 0, nonmanifold = 0, misoriented = 0, fans = 0;
    std::vector<Vec3> at; // the first few problem points
    void note(const Vec3& p) {
      if (at.size() < 10) at.push_back(p);
    }
  };
  auto gather = [&](const std::vector<Found>& chunks) {
    for (const Found& c : chunks) {
      r.degenerate_triangles += c.degenerate;
      r.border_edges += c.border;
      r.nonmanifold_edges += c.nonmanifold;
      r.misoriented_edges += c.misoriented;
      r.nonmanifold_vertices += c.fans;
      for (const Vec3& p : c.at)
        if (r.problem_points.size() < 10) r.problem_points.push_back(p);
    }
  };
  const std::size_t faces = mesh.face_count();
  auto repeats = [&](Index f) {
    const Triangle& t = mesh.triangles[f];
    return t[0] == t[1] || t[1] == t[2] || t[2] == t[0];
  };

  // Edges, from the faces around their ends: each edge is counted once, at the first of its half-edges
  // (faces with a repeated corner left out); the opposite of every half-edge comes with it. Where no
  // face repeats a corner, the opposites come first (MeshTopology::all_opposites, by the same rule):
  // a half-edge with an opposite is on a proper edge, which counts nothing, so the uses of the edges
  // (a CornerTable) are read only when some half-edge has none.
  const MeshTopology topology(mesh);
  bool repeating = false;
  for (Index f = 0; f < faces && !repeating; ++f) repeating = repeats(f);
  std::vector<Index> opp = repeating ? std::vector<Index>(3 * faces, kInvalidIndex) : topology.all_opposites();
  const bool proper = !repeating && std::find(opp.begin(), opp.end(), kInvalidIndex) == opp.end();
  std::optional<CornerTable> corners;
  if (!proper) corners.emplace(topology, repeats);
  {
    std::vector<Found> chunks((faces + kGrain - 1) / kGrain);
    detail::parallel_for(faces, kGrain, [&](std::size_t, std::size_t begin, std::size_t end) {
      Found& c = chunks[begin / kGrain];
      for (Index f = static_cast<Index>(begin); f < end; ++f) {
        const Triangle& t = mesh.triangles[f];
        if (repeats(f) || triangle_normal(mesh, f).squaredNorm() == 0.0) {
          ++c.degenerate;
          c.note(mesh.positions[t[0]]);
        }
        if (proper || repeats(f)) continue;
        for (Index k = 0; k < 3; ++k) {
          const Index h = 3 * f + k;
          const MeshTopology::EdgeUses uses = corners->edge_uses(h);
          if (uses.reverse == 1 && uses.same == 0) opp[h] = uses.opposite;
          if (uses.lowest < h) continue;
          const int total = 1 + uses.reverse + uses.same;
          if (total == 1) ++c.border;
          else if (total > 2) ++c.nonmanifold;
          else if (uses.reverse != 1) ++c.misoriented;
          else continue;
          c.note(mesh.positions[t[k]]);
        }
      }
    });
    gather(chunks);
  }

  // Vertex fans: one walk around each vertex through manifold edges must reach all of its faces.
  // A closed fan that is a height field over an axis plane (star_fan) cannot cross itself.
  r.components = component_count(mesh, opp);
  const std::vector<std::uint8_t> turns = validate_detail::projection_turns(mesh);
  // Per vertex: 1 when its fan is closed, then (asked by the pairs that share it) 2 a star, 3 not.
  std::unique_ptr<std::atomic<std::uint8_t>[]> star(new std::atomic<std::uint8_t>[mesh.vertex_count()]);
  {
    const std::size_t vertices = mesh.vertex_count();
    std::vector<Found> chunks((vertices + kGrain - 1) / kGrain);
    detail::parallel_for(vertices, kGrain, [&](std::size_t, std::size_t begin, std::size_t end) {
      Found& c = chunks[begin / kGrain];
      for (Index v = static_cast<Index>(begin); v < end; ++v) {
        const auto around = topology.faces_of(v);
        star[v].store(0, std::memory_order_relaxed);
        if (around.empty()) continue;
        std::size_t reached = 0;
        const Index f0 = around[0];
        Index h = 0;
        for (Index k = 0; k < 3; ++k)
          if (mesh.triangles[f0][k] == v) h = 3 * f0 + k; // outgoing half-edge of v in f0
        // Rotate one way.
        Index cur = h;
        bool closed_fan = false;
        do {
          ++reached;
          const Index o = opp[prev_halfedge(cur)]; // across the edge coming in to v
          if (o == kInvalidIndex) break;
          cur = o; // outgoing from v in the next face
          if (cur == h) closed_fan = true;
        } while (!closed_fan && reached <= around.size());
        if (!closed_fan) { // the other way from h
          for (cur = h; reached <= around.size(); ++reached) {
            const Index o = opp[cur];
            if (o == kInvalidIndex) break;
            cur = next_halfedge(o);
          }
        }
        if (reached != around.size()) {
          ++c.fans;
          c.note(mesh.positions[v]);
        } else if (closed_fan) {
          star[v].store(1, std::memory_order_relaxed);
        }
      }
    });
    gather(chunks);
  }

  if (options.check_self_intersections && r.degenerate_triangles == 0) {
    // Whole patches (embedded_patch.h) before the tree, which may still be in the making beside.
    const std::vector<Index> whole = validate_detail::whole_patches(mesh, opp, turns);
    // The exact tests run on the threads that find the pairs (overlapping boxes) in the tree.
    std::optional<AabbTree> own_tree;
    const AabbTree& tree = options.tree          ? *options.tree
                           : options.tree_source ? options.tree_source()
                                                 : own_tree.emplace(mesh);
    // Pairs of the tree's nodes within one whole patch, and nodes whose faces form a patch of their
    // own, are passed over (embedded_patch.h): their faces meet only where they share corners or edges.
    const validate_detail::Patches patches(mesh, opp, turns, whole, tree.ordered_faces());
    const auto apart = [&](Index a_begin, Index a_end, Index b_begin, Index b_end) {
      return patches.apart(a_begin, a_end, b_begin, b_end);
    };
    // Whether u's fan is a star, found when a pair first asks (most pairs are passed over whole).
    auto is_star = [&](Index u) {
      std::uint8_t known = star[u].load(std::memory_order_relaxed);
      if (known == 1) {
        known = star_fan(mesh, u, topology.faces_of(u), turns) ? 2 : 3;
        star[u].store(known, std::memory_order_relaxed);
      }
      return known == 2;
    };
    const std::vector<std::pair<Index, Index>> crossing = tree.overlapping_pairs(
        [&](Index a, Index b) {
          const Triangle& ta = mesh.triangles[a];
          const Triangle& tb = mesh.triangles[b];
          // Two faces of a star fan meet only where they share a corner or an edge (shared by both faces
          // of the fan around each of its ends): nothing to test. Most pairs of a smooth surface are such.
          int shared = 0;
          bool at_star = false;
          for (const Index u : ta)
            if (u == tb[0] || u == tb[1] || u == tb[2]) {
              ++shared;
              at_star = at_star || is_star(u);
            }
          if (at_star && shared < 3) return false;
          const std::array<Vec3, 3> pa{mesh.positions[ta[0]], mesh.positions[ta[1]], mesh.positions[ta[2]]};
          const std::array<Vec3, 3> pb{mesh.positions[tb[0]], mesh.positions[tb[1]], mesh.positions[tb[2]]};
          return mesh_triangles_intersect(ta, pa, tb, pb);
        },
        apart);
    for (const auto& [a, b] : crossing) {
      if (r.self_intersections >= options.max_reported) break;
      ++r.self_intersections;
      if (r.problem_points.size() < 10) r.problem_points.push_back(mesh.positions[mesh.triangles[a][0]]);
    }
  }
  return r;
}

DistanceStats distances_to_surface(const std::vector<Vec3>& points, const TriangleMesh& surface,
                                   const std::vector<Index>& near_vertex, const AabbTree* given_tree) {
  DistanceStats s;
  if (points.empty() || surface.empty()) return s;
  if (!near_vertex.empty() && near_vertex.size() != points.size())
    throw InvalidInput("distances to a surface: one near vertex per point, or none");
  for (std::size_t i = 0; i < points.size(); ++i)
    if (!points[i].allFinite())
      throw InvalidInput("distances to a surface: point " + std::to_string(i) +
                         " has a coordinate that is not a number");
  if (given_tree && !given_tree->holds_all_of(surface))
    throw InvalidInput("distances to a surface: the tree given is not over all of the surface's faces");
  bool all_on_vertices = !near_vertex.empty();
  for (std::size_t i = 0; i < near_vertex.size(); ++i) {
    const Index v = near_vertex[i];
    if (v != kInvalidIndex && v >= surface.vertex_count())
      throw InvalidInput("distances to a surface: a near vertex the surface does not have");
    all_on_vertices = all_on_vertices && v != kInvalidIndex && points[i] == surface.positions[v];
  }
  if (all_on_vertices) { // each point is its own closest point (the inner surface at zero clearance)
    s.count = points.size();
    return s;
  }
  std::optional<AabbTree> own_tree;
  const AabbTree& tree = given_tree ? *given_tree : own_tree.emplace(surface);
  const AabbTree::Slabs slabs = tree.slabs();
  // The points are searched in Morton order, so that each one's search is bounded by a near
  // neighbour's closest point (below); each point's distance is its own search's, whatever bounds it,
  // and the distances are summed in the points' own order, per chunk, chunks in order: the same
  // result in any search order on any machine.
  const std::size_t n = points.size();
  std::vector<detail::MortonKeyed> order(n);
  {
    BoundingBox box;
    for (const Vec3& p : points) box.extend(p);
    const double extent = box.size().maxCoeff();
    const double scale = extent > 0.0 ? detail::kMortonCells / extent : 0.0;
    for (std::size_t i = 0; i < n; ++i) order[i] = {detail::morton_code(points[i], box.min, scale), i};
    detail::sort_by_code(order);
  }
  std::vector<double> distance(n);
  std::atomic<bool> unreachable{false};
  constexpr std::size_t kGrain = 1024;
  detail::parallel_for(n, kGrain, [&](std::size_t, std::size_t begin, std::size_t end) {
    // The previous point's closest point lies on the surface: its distance bounds this one's, so the
    // search looks only within it, from its face up; the distance found is the same.
    std::optional<ClosestPoint> last;
    for (std::size_t k = begin; k < end; ++k) {
      const std::size_t i = order[k].item;
      const Vec3& p = points[i];
      const Index v = near_vertex.empty() ? kInvalidIndex : near_vertex[i];
      if (v != kInvalidIndex && p == surface.positions[v]) { // on its vertex: on the surface
        distance[i] = 0.0;
        last = ClosestPoint{kInvalidIndex, p, 0.0}; // a bound for the next one, but no face to start at
        continue;
      }
      // Bounds from above: the previous point's closest point and the near vertex, both on the surface.
      double bound = last ? (p - last->point).norm() : std::numeric_limits<double>::infinity();
      if (v != kInvalidIndex) bound = std::min(bound, (p - surface.positions[v]).norm());
      const Index start = last ? last->face : kInvalidIndex;
      std::optional<ClosestPoint> near;
      if (std::isfinite(bound)) near = tree.closest_point(p, bound * (1.0 + 1e-9), slabs, start);
      if (!near) near = tree.closest_point(p, std::numeric_limits<double>::infinity(), slabs, start);
      if (!near) { // every face has a corner that is not a number (thrown below, not on a worker thread)
        unreachable = true;
        return;
      }
      last = near;
      distance[i] = near->distance;
    }
  });
  if (unreachable) throw InvalidInput("distances to a surface: no face of the surface has finite corners");
  s.min = std::numeric_limits<double>::infinity();
  double sum = 0.0;
  for (std::size_t begin = 0; begin < n; begin += kGrain) {
    double chunk = 0.0;
    for (std::size_t i = begin; i < std::min(n, begin + kGrain); ++i) {
      s.min = std::min(s.min, distance[i]);
      s.max = std::max(s.max, distance[i]);
      chunk += distance[i];
    }
    sum += chunk;
  }
  s.count = points.size();
  s.mean = sum / static_cast<double>(points.size());
  return s;
}

namespace {

double point_segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

} // namespace

DistanceStats distances_to_polyline(const std::vector<Vec3>& points, const std::vector<Vec3>& poly) {
  const std::size_t n = poly.size();
  std::vector<double> distance(points.size(), std::numeric_limits<double>::infinity());
  auto segment = [&](std::size_t s, const Vec3& p) { return point_segment_distance(p, poly[s], poly[(s + 1) % n]); };
  if (n > 0) {
    BoundingBox box;
    double cell = 0.0;
    for (std::size_t s = 0; s < n; ++s) {
      box.extend(poly[s]);
      cell = std::max(cell, (poly[(s + 1) % n] - poly[s]).norm());
    }
    cell = std::max(cell, 1e-9 * (1.0 + box.size().maxCoeff()));
    auto index = [&](double x, int axis) {
      return static_cast<std::int64_t>(std::floor(std::clamp((x - box.min[axis]) / cell, -1e9, 1e9)));
    };
    auto key = [](std::int64_t i, std::int64_t j, std::int64_t k) {
      return static_cast<std::uint64_t>(i & 0x1fffff) << 42 | static_cast<std::uint64_t>(j & 0x1fffff) << 21 |
             static_cast<std::uint64_t>(k & 0x1fffff);
    };
    std::vector<std::pair<std::uint64_t, std::size_t>> cells; // (cell, segment) for the cells its box meets
    for (std::size_t s = 0; s < n; ++s) {
      const Vec3 lo = poly[s].cwiseMin(poly[(s + 1) % n]), hi = poly[s].cwiseMax(poly[(s + 1) % n]);
      for (std::int64_t i = index(lo.x(), 0); i <= index(hi.x(), 0); ++i)
        for (std::int64_t j = index(lo.y(), 1); j <= index(hi.y(), 1); ++j)
          for (std::int64_t k = index(lo.z(), 2); k <= index(hi.z(), 2); ++k) cells.emplace_back(key(i, j, k), s);
    }
    std::sort(cells.begin(), cells.end());
    detail::parallel_for(points.size(), 256, [&](std::size_t, std::size_t begin, std::size_t end) {
      for (std::size_t q = begin; q < end; ++q) {
        const Vec3& p = points[q];
        const std::int64_t ci = index(p.x(), 0), cj = index(p.y(), 1), ck = index(p.z(), 2);
        double best = std::numeric_limits<double>::infinity();
        // Rings 0 to r - 1 read: a segment in none of their cells lies more than r - 1 cells from p.
        for (std::int64_t r = 0; r == 0 || !(best <= static_cast<double>(r - 1) * cell); ++r) {
          if (r > 4) { // far from the polyline: all of it
            for (std::size_t s = 0; s < n; ++s) best = std::min(best, segment(s, p));
            break;
          }
          for (std::int64_t i = ci - r; i <= ci + r; ++i)
            for (std::int64_t j = cj - r; j <= cj + r; ++j)
              for (std::int64_t k = ck - r; k <= ck + r; ++k) {
                if (std::max({std::abs(i - ci), std::abs(j - cj), std::abs(k - ck)}) != r) continue; // the ring
                const std::uint64_t c = key(i, j, k);
                for (auto it = std::lower_bound(cells.begin(), cells.end(), std::make_pair(c, std::size_t{0}));
                     it != cells.end() && it->first == c; ++it)
                  best = std::min(best, segment(it->second, p));
              }
        }
        distance[q] = best;
      }
    });
  }
  DistanceStats s;
  s.min = std::numeric_limits<double>::infinity();
  double sum = 0.0;
  for (const double d : distance) {
    s.min = std::min(s.min, d);
    s.max = std::max(s.max, d);
    sum += d;
  }
  s.count = points.size();
  s.mean = s.count ? sum / static_cast<double>(s.count) : 0.0;
  return s;
}

} // namespace st
