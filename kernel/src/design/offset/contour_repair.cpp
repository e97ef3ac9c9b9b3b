// After contouring: back islands removed, pinched vertices split.

#include "design/offset/distance_band.h"
#include "st/core/union_find.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

namespace st::offset_detail {

// ---- after contouring ------------------------------------------------------------------------------

/// front_only: removes the connected components without a vertex in front of the patch. The edge of
/// the contoured region behind the rim is ragged at the scale of h and can cut small pieces off the
/// rim; the front sheet and everything joined to it stay. "In front" is judged with the closest
/// triangle of the node the vertex's grid edge starts from; once a component has one such vertex,
/// no other of its vertices is tested.
void remove_back_islands(Contour& contour, const Patch& patch) {
  TriangleMesh& mesh = contour.mesh;
  const std::size_t nv = mesh.positions.size();
  UnionFind sets(nv);
  const auto root = [&](Index v) { return sets.find(v); };
  for (const Triangle& t : mesh.triangles) {
    sets.join(t[1], t[0]);
    sets.join(t[2], t[0]);
  }
  std::vector<std::uint8_t> keep(nv, 0);
  for (Index v = 0; v < nv; ++v) {
    const Index r = root(v);
    if (keep[r]) continue;
    const std::int32_t t = contour.source[v] >> 3;
    const Nearest near = nearest_on_triangle(patch.triangles[t], mesh.positions[v]);
    if (near.offset.dot(patch.pseudo_normal(t, near.feature)) > 0.0) keep[r] = 1;
  }
  bool all_kept = true;
  for (Index v = 0; v < nv && all_kept; ++v) all_kept = keep[root(v)] != 0;
  if (all_kept) return;

  std::size_t out = 0;
  for (const Triangle& t : mesh.triangles)
    if (keep[root(t[0])]) mesh.triangles[out++] = t;
  mesh.triangles.resize(out);
  std::vector<Index> remap(nv, kInvalidIndex);
  Index kept = 0;
  for (Index v = 0; v < nv; ++v) {
    if (!keep[root(v)]) continue;
    remap[v] = kept;
    mesh.positions[kept++] = mesh.positions[v];
  }
  mesh.positions.resize(kept);
  for (Triangle& t : mesh.triangles)
    for (Index& v : t) v = remap[v];
  std::size_t candidates = 0;
  for (const Index v : contour.border_candidates)
    if (remap[v] != kInvalidIndex) contour.border_candidates[candidates++] = remap[v];
  contour.border_candidates.resize(candidates);
}

/// Where the triangles around a candidate vertex form more than one fan (two border fans touching in
/// a point, which can happen where the band of an open offset stops), gives each extra fan its own
/// copy of the vertex, so the mesh becomes a 2-manifold with border.
void split_pinched_vertices(TriangleMesh& mesh, const std::vector<Index>& candidates) {
  std::vector<std::int32_t> row_of(mesh.positions.size(), -1);
  for (std::size_t i = 0; i < candidates.size(); ++i) row_of[candidates[i]] = static_cast<std::int32_t>(i);
  std::vector<Index> offsets(candidates.size() + 1, 0);
  for (const Triangle& t : mesh.triangles)
    for (Index v : t)
      if (row_of[v] >= 0) ++offsets[row_of[v] + 1];
  for (std::size_t i = 0; i < candidates.size(); ++i) offsets[i + 1] += offsets[i];
  std::vector<Index> corners(offsets.back());
  {
    std::vector<Index> fill(offsets.begin(), offsets.end() - 1);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
      for (Index k = 0; k < 3; ++k) {
        const std::int32_t r = row_of[mesh.triangles[t][k]];
        if (r >= 0) corners[fill[r]++] = static_cast<Index>(3 * t + k);
      }
  }
  UnionFind fans;
  std::vector<std::pair<Index, Index>> copies; // (fan root, new vertex)
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    const Index v = candidates[i];
    const Index begin = offsets[i];
    const Index degree = offsets[i + 1] - begin;
    if (degree < 2) continue;
    fans.reset(degree);
    auto others = [&](Index corner) {
      const Triangle& t = mesh.triangles[corner / 3];
      return std::array<Index, 2>{t[(corner + 1) % 3], t[(corner + 2) % 3]};
    };
    // Two triangles at v are in one fan when they share an edge at v, i.e. another vertex.
    std::size_t groups = degree;
    for (Index a = 0; a < degree; ++a) {
      const auto oa = others(corners[begin + a]);
      for (Index b = 0; b < a; ++b) {
        const auto ob = others(corners[begin + b]);
        if (oa[0] != ob[0] && oa[0] != ob[1] && oa[1] != ob[0] && oa[1] != ob[1]) continue;
        if (fans.join(a, b)) --groups;
      }
    }
    if (groups == 1) continue;
    const Index keep = fans.find(0);
    copies.clear();
    for (Index a = 0; a < degree; ++a) {
      const Index r = fans.find(a);
      if (r == keep) continue;
      Index copy = kInvalidIndex;
      for (const auto& [cr, cv] : copies)
        if (cr == r) copy = cv;
      if (copy == kInvalidIndex) {
        copy = static_cast<Index>(mesh.positions.size());
        mesh.positions.push_back(mesh.positions[v]);
        copies.emplace_back(r, copy);
      }
      const Index corner = corners[begin + a];
      mesh.triangles[corner / 3][corner % 3] = copy;
    }
  }
}

} // namespace st::offset_detail
