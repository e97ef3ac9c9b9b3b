// Marching cubes (polygons by faces) or marching tetrahedra on the distance band's contoured cubes.

#include "design/offset/distance_band.h"

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
namespace {

// ---- marching tetrahedra tables ------------------------------------------------------------------
// Cube corners are numbered by bits (x = 1, y = 2, z = 4). The Kuhn split: for each order of the
// axes, the tetrahedron 0 -> +first axis -> +second axis -> 7. Odd orders have their last two
// vertices swapped so that all six are positively oriented.

constexpr std::array<std::array<int, 4>, 6> kCubeTets = {{
    {0, 1, 3, 7}, // x y z
    {0, 1, 7, 5}, // x z y
    {0, 2, 7, 3}, // y x z
    {0, 2, 6, 7}, // y z x
    {0, 4, 5, 7}, // z x y
    {0, 4, 7, 6}, // z y x
}};

// Contour of a positively oriented tetrahedron (vertices 0..3) by the mask of vertices below the iso
// value: 3 edges (a triangle) or 4 (a quadrilateral, in cyclic order), each edge a vertex pair.
// Oriented with normals toward the vertices above.
//
// Rule: for an even permutation (L, x, y, z) of a positive tetrahedron, the triangle on edges
// (Lx, Ly, Lz) has its normal pointing away from L. For an even permutation (P, Q, R, S) with P, Q
// below, the cycle (PR, PS, QS, QR) has its normal pointing toward R and S.
struct TetCase {
  int count = 0;
  std::array<std::array<int, 2>, 4> edges{};
};

constexpr std::array<TetCase, 16> make_tet_cases() {
  constexpr int lead[4][4] = {{0, 1, 2, 3}, {1, 0, 3, 2}, {2, 3, 0, 1}, {3, 2, 1, 0}};
  constexpr int pair_order[16][4] = {{}, {}, {},           {0, 1, 2, 3}, {}, {0, 2, 3, 1}, {1, 2, 0, 3},
                                     {}, {}, {0, 3, 1, 2}, {1, 3, 2, 0}, {}, {2, 3, 0, 1}, {},
                                     {}, {}};
  std::array<TetCase, 16> cases{};
  for (int mask = 1; mask < 15; ++mask) {
    TetCase& c = cases[mask];
    const int below = bit_count(static_cast<unsigned>(mask));
    if (below == 1 || below == 3) {
      int lone = 0;
      while (((mask >> lone) & 1) != (below == 1 ? 1 : 0)) ++lone;
      const int* p = lead[lone];
      c.count = 3;
      c.edges[0] = {lone, p[1]};
      c.edges[1] = {lone, below == 1 ? p[2] : p[3]};
      c.edges[2] = {lone, below == 1 ? p[3] : p[2]};
    } else {
      const int* p = pair_order[mask];
      c.count = 4;
      c.edges[0] = {p[0], p[2]};
      c.edges[1] = {p[0], p[3]};
      c.edges[2] = {p[1], p[3]};
      c.edges[3] = {p[1], p[2]};
    }
  }
  return cases;
}

constexpr std::array<TetCase, 16> kTetCases = make_tet_cases();

// ---- marching cubes by faces -------------------------------------------------------------------------
// The faces of a cube, corners counter-clockwise seen from outside. Faces 2a and 2a+1 are x_a = 0 and
// x_a = 1. Each is the canonical order (0,0), (1,0), (1,1), (0,1) over the next two axes (a+1, a+2),
// reversed on the x_a = 0 side; either way corners 0 and 2 are diagonal, as are 1 and 3.
constexpr std::array<std::array<int, 4>, 6> kCubeFaces = {{
    {0, 4, 6, 2},
    {1, 3, 7, 5},
    {0, 1, 5, 4},
    {2, 6, 7, 3},
    {0, 2, 3, 1},
    {4, 5, 7, 6},
}};

/// A polygon of one cube's contour: the crossed cube edges in cyclic order, each as (corner a, corner b).
struct CubePolygon {
  int count = 0;
  std::array<std::array<int, 2>, 12> edges{};
};

/// The contour of one cube whose corner c has the value below the iso value when bit c of `below` is
/// set (`f` the corner values less the iso value): polygons whose sides are the contour's segments on
/// the cube's faces, oriented like the tetrahedra's (normals toward the corners above).
///
/// On a face, walking its corners counter-clockwise seen from outside, a crossed edge is an entry (from
/// above to below) or an exit; each segment runs from an entry to an exit. A face with four crossings
/// (diagonal corners below) joins either its corners below or those above; the bilinear interpolant
/// of the four values decides (the asymptotic decider: below joined when its saddle value is below
/// the iso value). The decision reads the face's values as f0 f2 - f1 f3, which both cubes sharing the
/// face compute bit-identically (products commute), so neighbours always agree and the contour is
/// welded and 2-manifold across faces. Each crossing is an entry on one of its two faces and an exit
/// on the other, so the segments close into cycles.
int cube_polygons(int below, const std::array<double, 8>& f, std::array<CubePolygon, 4>& out) {
  std::array<std::int8_t, 64> next; // [8 * lower corner + direction]: the next crossing of the cycle
  next.fill(-1);
  auto key = [](int a, int b) { return 8 * (a & b) + (a ^ b); };
  for (const std::array<int, 4>& q : kCubeFaces) {
    int entries[2];
    int exits[2];
    int n_entries = 0;
    int n_exits = 0;
    for (int k = 0; k < 4; ++k) {
      const bool here = ((below >> q[k]) & 1) != 0;
      const bool there = ((below >> q[(k + 1) & 3]) & 1) != 0;
      if (here && !there) exits[n_exits++] = k;
      if (!here && there) entries[n_entries++] = k;
    }
    if (n_entries == 1) {
      next[key(q[entries[0]], q[(entries[0] + 1) & 3])] =
          static_cast<std::int8_t>(key(q[exits[0]], q[(exits[0] + 1) & 3]));
    } else if (n_entries == 2) {
      const double saddle = f[q[0]] * f[q[2]] - f[q[1]] * f[q[3]];
      const bool corner0_below = ((below >> q[0]) & 1) != 0;
      const bool joined_below = corner0_below ? saddle > 0.0 : saddle < 0.0;
      for (const int e : entries) {
        const int x = joined_below ? (e + 3) & 3 : (e + 1) & 3;
        next[key(q[e], q[(e + 1) & 3])] = static_cast<std::int8_t>(key(q[x], q[(x + 1) & 3]));
      }
    }
  }
  int polygons = 0;
  for (int start = 0; start < 64; ++start) {
    if (next[start] < 0) continue;
    CubePolygon& p = out[polygons++];
    p.count = 0;
    for (int k = start; next[k] >= 0;) {
      const int lower = k >> 3;
      p.edges[p.count++] = {lower, lower | (k & 7)};
      const int n = next[k];
      next[k] = -1;
      k = n;
    }
  }
  return polygons;
}

/// Triangle quality 4 sqrt(3) area / (sum of squared edge lengths), negative when the triangle faces
/// against `normal`.
double facing_quality(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& normal) {
  const Vec3 n = (b - a).cross(c - a);
  const double edges = (b - a).squaredNorm() + (c - b).squaredNorm() + (a - c).squaredNorm();
  if (!(n.dot(normal) > 0.0) || !(edges > 0.0)) return -1.0;
  return 2.0 * std::numbers::sqrt3 * n.norm() / edges;
}

/// Triangulates the cycle `v` (positions from `positions`, n >= 3) without new vertices, keeping its
/// orientation: the triangulation whose worst triangle is best (quality, against the polygon's Newell
/// normal), by dynamic programming over its diagonals.
void triangulate_cycle(const std::array<Index, 12>& v, int n, const std::vector<Vec3>& positions,
                       std::vector<Triangle>& out) {
  if (n == 3) {
    out.push_back({v[0], v[1], v[2]});
    return;
  }
  if (n == 4) {
    // A quadrilateral: split along the shorter diagonal.
    if ((positions[v[0]] - positions[v[2]]).squaredNorm() <= (positions[v[1]] - positions[v[3]]).squaredNorm()) {
      out.push_back({v[0], v[1], v[2]});
      out.push_back({v[0], v[2], v[3]});
    } else {
      out.push_back({v[0], v[1], v[3]});
      out.push_back({v[1], v[2], v[3]});
    }
    return;
  }
  Vec3 normal = Vec3::Zero();
  for (int i = 0; i < n; ++i) normal += positions[v[i]].cross(positions[v[(i + 1) % n]]);
  std::array<std::array<double, 12>, 12> best{};
  std::array<std::array<std::int8_t, 12>, 12> split{};
  for (int len = 2; len < n; ++len)
    for (int i = 0; i + len < n; ++i) {
      const int j = i + len;
      best[i][j] = -std::numeric_limits<double>::infinity();
      for (int k = i + 1; k < j; ++k) {
        double q = facing_quality(positions[v[i]], positions[v[k]], positions[v[j]], normal);
        if (k - i > 1) q = std::min(q, best[i][k]);
        if (j - k > 1) q = std::min(q, best[k][j]);
        if (q > best[i][j]) {
          best[i][j] = q;
          split[i][j] = static_cast<std::int8_t>(k);
        }
      }
    }
  std::array<std::array<int, 2>, 12> stack{};
  int top = 0;
  stack[top++] = {0, n - 1};
  while (top > 0) {
    const auto [i, j] = stack[--top];
    const int k = split[i][j];
    out.push_back({v[i], v[k], v[j]});
    if (k - i > 1) stack[top++] = {i, k};
    if (j - k > 1) stack[top++] = {k, j};
  }
}

} // namespace

// ---- contouring ---------------------------------------------------------------------------------------
// Every grid edge of the Kuhn triangulation joins a node p to p + d, d one of the 7 non-zero 0/1
// vectors (bit 0 = x, 1 = y, 2 = z). An edge crossed by the contour is owned by p; its vertex index
// is its rank among the crossed edges of p's block (by direction, slice and bit) plus the block's
// first index: a collision-free table keyed by the grid edge, so every crossed edge gives exactly
// one vertex, found with a popcount, and blocks are processed in parallel.

Contour DistanceBand::contour() const {
  const std::size_t nb = blocks_.size();
  const double iso = p_.iso;
  const double h = p_.h;

  std::vector<SliceMasks> below(nb);
  detail::parallel_for(nb, 32, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t b = begin; b < end; ++b)
      for (int s = 0; s < 8; ++s) {
        std::uint64_t m = 0;
        for (std::uint64_t c = blocks_[b].computed[s]; c; c &= c - 1) {
          const int bit = std::countr_zero(c);
          if (field_value(blocks_[b].dist[64 * s + bit]) < iso) m |= std::uint64_t{1} << bit;
        }
        below[b][s] = m;
      }
  });

  // Per block: contoured cubes (8 computed nodes, one of which anchors), crossed cubes, crossed
  // edges and their ranks. Without front_only every node up to T + 2h anchors, so every cube the
  // contour crosses is contoured (it has a corner below T); with front_only the anchors select the
  // front sheet and the rim.
  struct BlockContour {
    SliceMasks contoured;
    SliceMasks crossed_cubes;
    std::array<SliceMasks, 7> crossed_edges;  // [direction - 1]
    std::array<std::array<Index, 8>, 7> rank; // crossed edges before (direction, slice) in the block
    Index first = 0;                          // index of the block's first vertex
    Index count = 0;
  };
  std::vector<BlockContour> bc(nb);
  detail::parallel_for(nb, 32, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t b = begin; b < end; ++b) {
      const Block& blk = blocks_[b];
      BlockContour& out = bc[b];
      // The blocks at offsets {0, 1}^3, indexed like cube corners.
      std::array<std::int32_t, 8> corner_block{};
      for (int c = 0; c < 8; ++c) corner_block[c] = blk.neighbours[neighbour_slot(c & 1, (c >> 1) & 1, c >> 2)];
      for (int s = 0; s < 8; ++s) {
        // Masks of the corner (cx, cy, cz) of every cube of the slice: the node masks of slice
        // s + cz shifted by (cx, cy), taking the bits past x = 7 or y = 7 from the next blocks.
        std::array<std::uint64_t, 8> comp{};
        std::array<std::uint64_t, 8> low{};
        std::uint64_t any_anchoring = 0;
        for (int cz = 0; cz < 2; ++cz) {
          const int oz = (s + cz) >> 3;
          const int slice = (s + cz) & 7;
          std::uint64_t fc[4], fb[4], fs[4]; // blocks (0,0), (1,0), (0,1), (1,1) in x, y
          for (int k = 0; k < 4; ++k) {
            const std::int32_t n = corner_block[k + 4 * oz];
            fc[k] = n >= 0 ? blocks_[n].computed[slice] : 0;
            fb[k] = n >= 0 ? below[n][slice] : 0;
            fs[k] = n >= 0 ? blocks_[n].anchoring[slice] : 0;
          }
          auto shifts = [](const std::uint64_t* f, std::uint64_t* out4) {
            out4[0] = f[0];
            out4[1] = shift_x(f[0], f[1]);
            out4[2] = shift_y(f[0], f[2]);
            out4[3] = shift_y(out4[1], shift_x(f[2], f[3]));
          };
          shifts(fc, &comp[4 * cz]);
          shifts(fb, &low[4 * cz]);
          std::uint64_t sp[4];
          shifts(fs, sp);
          any_anchoring |= sp[0] | sp[1] | sp[2] | sp[3];
        }
        std::uint64_t all_computed = ~std::uint64_t{0};
        std::uint64_t any_below = 0;
        std::uint64_t all_below = ~std::uint64_t{0};
        for (int c = 0; c < 8; ++c) {
          all_computed &= comp[c];
          any_below |= low[c];
          all_below &= low[c];
        }
        out.contoured[s] = all_computed & any_anchoring;
        out.crossed_cubes[s] = out.contoured[s] & any_below & ~all_below;
        for (int d = 1; d < 8; ++d)
          out.crossed_edges[d - 1][s] = p_.tetrahedra || std::has_single_bit(static_cast<unsigned>(d))
                                            ? comp[0] & comp[d] & (low[0] ^ low[d])
                                            : 0;
      }
      Index count = 0;
      for (int d = 0; d < 7; ++d)
        for (int s = 0; s < 8; ++s) {
          out.rank[d][s] = count;
          count += static_cast<Index>(bit_count(out.crossed_edges[d][s]));
        }
      out.count = count;
    }
  });
  Index total = 0;
  for (BlockContour& c : bc) {
    c.first = total;
    total += c.count;
  }

  // Vertices: one per crossed edge, on the linear interpolation of the (shifted) node values.
  Contour result;
  TriangleMesh& mesh = result.mesh;
  mesh.positions.resize(total);
  std::vector<std::uint8_t> on_border(p_.front_only ? total : 0, 0);
  std::vector<std::int32_t> source(p_.front_only ? total : 0, -1);
  auto cube_contoured = [&](const Block& blk, int x, int y, int z) { // x, y, z in -1..8, local to blk
    const std::int32_t n = blk.neighbours[neighbour_slot(x >> 3, y >> 3, z >> 3)];
    if (n < 0) return false;
    const int l = (x & 7) | ((y & 7) << 3) | ((z & 7) << 6);
    return ((bc[n].contoured[l >> 6] >> (l & 63)) & 1) != 0;
  };
  auto node_value = [&](const Block& blk, int x, int y, int z) { // x, y, z in 0..8, local to blk
    const Block& n = blocks_[blk.neighbours[neighbour_slot(x >> 3, y >> 3, z >> 3)]];
    return field_value(n.dist[(x & 7) | ((y & 7) << 3) | ((z & 7) << 6)]);
  };
  detail::parallel_for(nb, 32, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t b = begin; b < end; ++b) {
      const Block& blk = blocks_[b];
      for (int d = 1; d < 8; ++d)
        for (int s = 0; s < 8; ++s)
          for (std::uint64_t m = bc[b].crossed_edges[d - 1][s]; m; m &= m - 1) {
            const int bit = std::countr_zero(m);
            const int x = bit & 7;
            const int y = bit >> 3;
            const int z = s;
            const int dx = d & 1;
            const int dy = (d >> 1) & 1;
            const int dz = d >> 2;
            const double v0 = node_value(blk, x, y, z);
            const double v1 = node_value(blk, x + dx, y + dy, z + dz);
            const double t = (iso - v0) / (v1 - v0);
            const std::uint64_t all = bc[b].crossed_edges[d - 1][s];
            const Index index = bc[b].first + bc[b].rank[d - 1][s] +
                                static_cast<Index>(bit_count(all & ((std::uint64_t{1} << bit) - 1)));
            mesh.positions[index] = node_position(8 * blk.coord[0] + x, 8 * blk.coord[1] + y, 8 * blk.coord[2] + z) +
                                    (t * h) * Vec3(dx, dy, dz);
            if (p_.front_only) {
              // The cubes around the edge have lowest node p - e, e over the subsets of the axes the
              // edge does not move along; a vertex with one of them left out may be on the border.
              bool interior = true;
              for (int e = 0; e < 8 && interior; ++e)
                if ((e & d) == 0) interior = cube_contoured(blk, x - (e & 1), y - ((e >> 1) & 1), z - (e >> 2));
              on_border[index] = interior ? 0 : 1;
              source[index] = blocks_[b].closest[bit + 64 * s];
            }
          }
    }
  });

  // Triangles, by chunks of blocks in parallel, concatenated in block order.
  constexpr std::size_t kChunk = 32;
  std::vector<std::vector<Triangle>> chunks((nb + kChunk - 1) / kChunk);
  auto vertex_of = [&](const Block& blk, int x, int y, int z, int d) { // edge from local node (x, y, z)
    const std::int32_t n = blk.neighbours[neighbour_slot(x >> 3, y >> 3, z >> 3)];
    const int l = (x & 7) | ((y & 7) << 3) | ((z & 7) << 6);
    const std::uint64_t m = bc[n].crossed_edges[d - 1][l >> 6];
    return bc[n].first + bc[n].rank[d - 1][l >> 6] +
           static_cast<Index>(bit_count(m & ((std::uint64_t{1} << (l & 63)) - 1)));
  };
  detail::parallel_for(nb, kChunk, [&](std::size_t, std::size_t begin, std::size_t end) {
    std::vector<Triangle>& tris = chunks[begin / kChunk];
    for (std::size_t b = begin; b < end; ++b) {
      const Block& blk = blocks_[b];
      for (int s = 0; s < 8; ++s)
        for (std::uint64_t m = bc[b].crossed_cubes[s]; m; m &= m - 1) {
          const int bit = std::countr_zero(m);
          const int lx = bit & 7;
          const int ly = bit >> 3;
          const int lz = s;
          int below_mask = 0;
          std::array<double, 8> f{};
          for (int c = 0; c < 8; ++c) {
            f[c] = node_value(blk, lx + (c & 1), ly + ((c >> 1) & 1), lz + (c >> 2)) - iso;
            below_mask |= (f[c] < 0.0 ? 1 : 0) << c;
          }
          std::array<Index, 64> cache; // [lower corner * 8 + direction]
          cache.fill(kInvalidIndex);
          auto vertex = [&](int ca, int cb) {
            const int lower = ca & cb; // Kuhn edges and cube edges join nested corners
            Index& v = cache[8 * lower + (ca ^ cb)];
            if (v == kInvalidIndex)
              v = vertex_of(blk, lx + (lower & 1), ly + ((lower >> 1) & 1), lz + (lower >> 2), ca ^ cb);
            return v;
          };
          if (!p_.tetrahedra) {
            std::array<CubePolygon, 4> polygons;
            const int count = cube_polygons(below_mask, f, polygons);
            for (int k = 0; k < count; ++k) {
              std::array<Index, 12> v{};
              for (int i = 0; i < polygons[k].count; ++i)
                v[i] = vertex(polygons[k].edges[i][0], polygons[k].edges[i][1]);
              triangulate_cycle(v, polygons[k].count, mesh.positions, tris);
            }
            continue;
          }
          for (const std::array<int, 4>& tet : kCubeTets) {
            int mask = 0;
            for (int k = 0; k < 4; ++k) mask |= ((below_mask >> tet[k]) & 1) << k;
            if (mask == 0 || mask == 15) continue;
            const TetCase& tc = kTetCases[mask];
            std::array<Index, 12> v{};
            for (int k = 0; k < tc.count; ++k) v[k] = vertex(tet[tc.edges[k][0]], tet[tc.edges[k][1]]);
            triangulate_cycle(v, tc.count, mesh.positions, tris); // a quadrilateral here is planar and convex
          }
        }
    }
  });
  std::size_t triangle_count = 0;
  for (const auto& c : chunks) triangle_count += c.size();
  mesh.triangles.reserve(triangle_count);
  for (auto& c : chunks) {
    mesh.triangles.insert(mesh.triangles.end(), c.begin(), c.end());
    c = {};
  }

  // Drop the vertices of crossed edges that no contoured cube uses (only where the band stops).
  std::vector<Index> remap(total, kInvalidIndex);
  for (const Triangle& t : mesh.triangles)
    for (Index v : t) remap[v] = 0;
  Index kept = 0;
  for (Index v = 0; v < total; ++v) {
    if (remap[v] == kInvalidIndex) continue;
    remap[v] = kept;
    mesh.positions[kept] = mesh.positions[v];
    if (p_.front_only) {
      if (on_border[v]) result.border_candidates.push_back(kept);
      source[kept] = source[v];
    }
    ++kept;
  }
  mesh.positions.resize(kept);
  if (p_.front_only) {
    source.resize(kept);
    result.source = std::move(source);
  }
  if (kept != total)
    for (Triangle& t : mesh.triangles)
      for (Index& v : t) v = remap[v];
  return result;
}

} // namespace st::offset_detail
