// Marching tetrahedra on the distance band's contoured cubes.

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
        for (int d = 1; d < 8; ++d) out.crossed_edges[d - 1][s] = comp[0] & comp[d] & (low[0] ^ low[d]);
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
          for (int c = 0; c < 8; ++c)
            below_mask |= (node_value(blk, lx + (c & 1), ly + ((c >> 1) & 1), lz + (c >> 2)) < iso ? 1 : 0) << c;
          std::array<Index, 64> cache; // [lower corner * 8 + direction]
          cache.fill(kInvalidIndex);
          auto vertex = [&](int ca, int cb) {
            const int lower = ca & cb; // Kuhn edges join nested corners
            Index& v = cache[8 * lower + (ca ^ cb)];
            if (v == kInvalidIndex)
              v = vertex_of(blk, lx + (lower & 1), ly + ((lower >> 1) & 1), lz + (lower >> 2), ca ^ cb);
            return v;
          };
          for (const std::array<int, 4>& tet : kCubeTets) {
            int mask = 0;
            for (int k = 0; k < 4; ++k) mask |= ((below_mask >> tet[k]) & 1) << k;
            if (mask == 0 || mask == 15) continue;
            const TetCase& tc = kTetCases[mask];
            std::array<Index, 4> v{};
            for (int k = 0; k < tc.count; ++k) v[k] = vertex(tet[tc.edges[k][0]], tet[tc.edges[k][1]]);
            if (tc.count == 3) {
              tris.push_back({v[0], v[1], v[2]});
            } else if ((mesh.positions[v[0]] - mesh.positions[v[2]]).squaredNorm() <=
                       (mesh.positions[v[1]] - mesh.positions[v[3]]).squaredNorm()) {
              // A planar convex quadrilateral: split along the shorter diagonal.
              tris.push_back({v[0], v[1], v[2]});
              tris.push_back({v[0], v[2], v[3]});
            } else {
              tris.push_back({v[0], v[1], v[3]});
              tris.push_back({v[1], v[2], v[3]});
            }
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
