#include "st/validate/validate.h"

#include "detail/parallel.h"
#include "st/core/aabb_tree.h"
#include "st/core/topology.h"
#include "st/boolean/triangle_intersection.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <sstream>
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

SolidReport check_solid(const TriangleMesh& mesh, const SolidOptions& options) {
  SolidReport r;
  r.vertices = mesh.vertex_count();
  r.triangles = mesh.face_count();
  r.area = surface_area(mesh);
  r.volume = signed_volume(mesh);
  auto note = [&](const Vec3& p) {
    if (r.problem_points.size() < 10) r.problem_points.push_back(p);
  };

  // Edges: count uses per direction.
  std::unordered_map<std::uint64_t, std::pair<int, int>> edges; // (lo->hi uses, hi->lo uses)
  edges.reserve(mesh.triangles.size() * 2);
  for (const Triangle& t : mesh.triangles) {
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) {
      ++r.degenerate_triangles;
      note(mesh.positions[t[0]]);
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      const Index a = t[k], b = t[(k + 1) % 3];
      const std::uint64_t key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
      auto& e = edges[key];
      (a < b ? e.first : e.second)++;
    }
  }
  for (Index f = 0; f < mesh.face_count(); ++f)
    if (triangle_normal(mesh, f).squaredNorm() == 0.0) {
      ++r.degenerate_triangles;
      note(mesh.positions[mesh.triangles[f][0]]);
    }
  for (const auto& [key, uses] : edges) {
    const int total = uses.first + uses.second;
    const Vec3& p = mesh.positions[static_cast<Index>(key >> 32)];
    if (total == 1) {
      ++r.border_edges;
      note(p);
    } else if (total > 2) {
      ++r.nonmanifold_edges;
      note(p);
    } else if (uses.first != 1) {
      ++r.misoriented_edges;
      note(p);
    }
  }

  // Vertex fans and components.
  const MeshTopology topology(mesh);
  const std::vector<Index> opp = topology.all_opposites();
  r.components = component_count(mesh, opp);
  for (Index v = 0; v < mesh.vertex_count(); ++v) {
    const auto faces = topology.faces_of(v);
    if (faces.empty()) continue;
    // Walk one fan around v through manifold edges; it must reach every face of v.
    std::size_t reached = 0;
    const Index f0 = faces[0];
    Index h = 0;
    for (Index k = 0; k < 3; ++k)
      if (mesh.triangles[f0][k] == v) h = 3 * f0 + k; // outgoing half-edge of v in f0
    // Rotate one way.
    Index cur = h;
    bool closed_fan = false;
    do {
      ++reached;
      const Index in = prev_halfedge(cur); // incoming to v
      const Index o = opp[in];
      if (o == kInvalidIndex) break;
      cur = o; // outgoing from v in the next face
      if (cur == h) closed_fan = true;
    } while (!closed_fan && reached <= faces.size());
    if (!closed_fan) {
      // Rotate the other way from h.
      cur = h;
      while (true) {
        const Index o = opp[cur];
        if (o == kInvalidIndex) break;
        cur = next_halfedge(o);
        ++reached;
        if (reached > faces.size()) break;
      }
    }
    if (reached != faces.size()) {
      ++r.nonmanifold_vertices;
      note(mesh.positions[v]);
    }
  }

  if (options.check_self_intersections && r.degenerate_triangles == 0) {
    // The candidate pairs (overlapping boxes) from the tree, then the exact tests on all threads; what
    // is found is gathered per chunk, in pair order, so the report does not depend on the threads.
    std::optional<AabbTree> own_tree;
    const AabbTree& tree = options.tree ? *options.tree : own_tree.emplace(mesh);
    const std::vector<std::pair<Index, Index>> pairs = tree.overlapping_pairs();
    constexpr std::size_t kGrain = 4096;
    std::vector<std::vector<Index>> found((pairs.size() + kGrain - 1) / kGrain);
    detail::parallel_for(pairs.size(), kGrain, [&](std::size_t, std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) {
        const auto [a, b] = pairs[i];
        const Triangle& ta = mesh.triangles[a];
        const Triangle& tb = mesh.triangles[b];
        const std::array<Vec3, 3> pa{mesh.positions[ta[0]], mesh.positions[ta[1]], mesh.positions[ta[2]]};
        const std::array<Vec3, 3> pb{mesh.positions[tb[0]], mesh.positions[tb[1]], mesh.positions[tb[2]]};
        if (mesh_triangles_intersect(ta, pa, tb, pb)) found[begin / kGrain].push_back(a);
      }
    });
    for (const std::vector<Index>& chunk : found)
      for (Index a : chunk) {
        if (r.self_intersections >= options.max_reported) break;
        ++r.self_intersections;
        note(mesh.positions[mesh.triangles[a][0]]);
      }
  }
  return r;
}

namespace {

// Each face's plane and the disc about its centroid that holds it: a point at height h over the plane
// and at l from the centroid along it lies at least sqrt(h^2 + max(0, l - r)^2) from the face. Two
// dozen flops against a closest-point test's hundred: a point T over a finely tessellated surface has
// a few hundred faces whose boxes (fat where the faces are tilted) come within T, and the disc rules
// out all but those right under it.
struct FaceDisc {
  Vec3 centre;
  Vec3 normal; // unit, or zero for a degenerate face (the bound is then the ball's)
  double radius;
};

std::vector<FaceDisc> face_discs(const TriangleMesh& surface) {
  std::vector<FaceDisc> discs(surface.face_count());
  for (Index f = 0; f < surface.face_count(); ++f) {
    const Triangle& t = surface.triangles[f];
    const Vec3 &a = surface.positions[t[0]], &b = surface.positions[t[1]], &c = surface.positions[t[2]];
    FaceDisc& d = discs[f];
    d.centre = (a + b + c) / 3.0;
    const Vec3 n = (b - a).cross(c - a);
    const double length = n.norm();
    d.normal = length > 0.0 ? Vec3(n / length) : Vec3::Zero();
    // Grown a little so that rounding never puts a corner outside it.
    d.radius = std::sqrt(std::max(
                   {(a - d.centre).squaredNorm(), (b - d.centre).squaredNorm(), (c - d.centre).squaredNorm()})) *
                   (1.0 + 1e-9) +
               1e-12;
  }
  return discs;
}

} // namespace

DistanceStats distances_to_surface(const std::vector<Vec3>& points, const TriangleMesh& surface) {
  DistanceStats s;
  if (points.empty() || surface.empty()) return s;
  const AabbTree tree(surface);
  const std::vector<FaceDisc> discs = face_discs(surface);
  // Per chunk of points on all threads, summed in chunk order (the same result on any machine).
  constexpr std::size_t kGrain = 1024;
  std::vector<DistanceStats> chunks((points.size() + kGrain - 1) / kGrain);
  detail::parallel_for(points.size(), kGrain, [&](std::size_t, std::size_t begin, std::size_t end) {
    DistanceStats& c = chunks[begin / kGrain];
    c.min = std::numeric_limits<double>::infinity();
    // The previous point's closest point lies on the surface: its distance bounds this one's, so the
    // search (of neighbouring points, as meshes number them) looks only within it; the distance found
    // is the same.
    std::optional<Vec3> last;
    for (std::size_t i = begin; i < end; ++i) {
      const Vec3& p = points[i];
      // Passed over: the faces whose disc bound (less a margin for its rounding) exceeds the best.
      const std::function<bool(Index, double)> beyond = [&](Index f, double best) {
        const FaceDisc& d = discs[f];
        const Vec3 v = p - d.centre;
        const double h = d.normal.dot(v);
        const double lateral = std::max(0.0, std::sqrt(std::max(0.0, v.squaredNorm() - h * h)) - d.radius);
        return (h * h + lateral * lateral) * (1.0 - 1e-9) > best;
      };
      std::optional<ClosestPoint> near;
      if (last) near = tree.closest_point(p, (p - *last).norm() * (1.0 + 1e-9), beyond);
      if (!near) near = tree.closest_point(p, std::numeric_limits<double>::infinity(), beyond);
      last = near->point;
      const double d = near->distance;
      c.min = std::min(c.min, d);
      c.max = std::max(c.max, d);
      c.mean += d; // the sum, for now
    }
  });
  s.min = std::numeric_limits<double>::infinity();
  double sum = 0.0;
  for (const DistanceStats& c : chunks) {
    s.min = std::min(s.min, c.min);
    s.max = std::max(s.max, c.max);
    sum += c.mean;
  }
  s.count = points.size();
  s.mean = sum / static_cast<double>(points.size());
  return s;
}

} // namespace st
