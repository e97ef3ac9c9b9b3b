// Seeding and growing the distance band.

#include "design/offset/distance_band.h"

#include "st/core/errors.h"

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

std::int32_t DistanceBand::find_or_create_block(std::int64_t bx, std::int64_t by, std::int64_t bz) {
  const std::uint64_t key = block_key(bx, by, bz);
  const std::int32_t found = blocks_map_.find(key);
  if (found >= 0) return found;
  if (static_cast<double>(blocks_.size() + 1) * kBlockNodes > p_.node_cap ||
      blocks_.size() + 1 >= (std::size_t{1} << 23)) { // node references are 32-bit
    char msg[200];
    std::snprintf(msg, sizeof msg,
                  "offset: the distance band at h=%.4g mm grew past %.1f million cells; use a coarser "
                  "resolution",
                  p_.h, p_.node_cap * 1e-6);
    throw InvalidInput(msg);
  }
  const auto b = static_cast<std::int32_t>(blocks_.size());
  Block& blk = blocks_.emplace_back();
  blk.dist.fill(std::numeric_limits<float>::infinity());
  blk.closest.fill(-1);
  blk.computed.fill(0);
  blk.pending.fill(0);
  blk.front.fill(0);
  blk.spreading.fill(0);
  blk.anchoring.fill(0);
  blk.queued.fill(0);
  blk.neighbours.fill(-1);
  blk.coord = {bx, by, bz};
  blk.pending_stamp = 0;
  blk.front_stamp = 0;
  blocks_map_.insert(key, b);
  for (int oz = -1; oz <= 1; ++oz)
    for (int oy = -1; oy <= 1; ++oy)
      for (int ox = -1; ox <= 1; ++ox) {
        const int s = neighbour_slot(ox, oy, oz);
        const std::int32_t n = s == 13 ? b : blocks_map_.find(block_key(bx + ox, by + oy, bz + oz));
        if (n < 0) continue;
        blocks_[b].neighbours[s] = n;
        blocks_[n].neighbours[26 - s] = b;
      }
  return b;
}

std::int32_t DistanceBand::neighbour_or_create(std::int32_t b, int slot) {
  const std::int32_t n = blocks_[b].neighbours[slot];
  if (n >= 0) return n;
  const std::array<std::int64_t, 3> c = blocks_[b].coord;
  return find_or_create_block(c[0] + slot % 3 - 1, c[1] + (slot / 3) % 3 - 1, c[2] + slot / 9 - 1);
}

// front_only. Behind the patch (the offset from the closest point against the pseudo-normal of
// the closest feature), a node whose closest point is inside the patch neither spreads nor
// anchors a contoured cube, so no back sheet is made. Around the border, nodes spread in the whole
// band, so that where two parts of the border face each other each part's distance reaches the
// other's side; they anchor contoured cubes down to `margin` behind the border only, which is where
// the rounded rim ends.
bool DistanceBand::spreads(const Nearest& nearest, std::int32_t t, double d) const {
  if (d > p_.limit) return false;
  if (!p_.front_only || patch_.on_border(t, nearest.feature)) return true;
  return nearest.offset.dot(patch_.pseudo_normal(t, nearest.feature)) >= 0.0;
}

bool DistanceBand::anchors(const Nearest& nearest, std::int32_t t, double d) const {
  if (d > p_.limit) return false;
  if (!p_.front_only) return true;
  const double margin = patch_.on_border(t, nearest.feature) ? p_.margin : 0.0;
  return d <= margin || nearest.offset.dot(patch_.pseudo_normal(t, nearest.feature)) >= -margin;
}

// ---- seeding ------------------------------------------------------------------------------------------

/// Grid index range (stored indices) of the box of triangle t grown by the seed radius.
std::array<std::array<std::int64_t, 3>, 2> DistanceBand::seed_range(std::size_t t) const {
  const PatchTriangle& g = patch_.triangles[t];
  const Vec3 b = g.a + g.ab;
  const Vec3 c = g.a + g.ac;
  const Vec3 lo = g.a.cwiseMin(b).cwiseMin(c).array() - p_.seed_radius;
  const Vec3 hi = g.a.cwiseMax(b).cwiseMax(c).array() + p_.seed_radius;
  std::array<std::array<std::int64_t, 3>, 2> range{};
  for (int a = 0; a < 3; ++a) {
    range[0][a] = ceil_int((lo[a] - p_.origin[a]) / p_.h) + kIndexOffset;
    range[1][a] = floor_int((hi[a] - p_.origin[a]) / p_.h) + kIndexOffset;
  }
  return range;
}

/// False when no node of the block lies within the seed radius of triangle t (tested on the ball
/// around the block's nodes against the triangle's plane and its three edge planes).
bool DistanceBand::block_may_hold_seeds(std::size_t t, const std::array<std::int64_t, 3>& block) const {
  const PatchTriangle& g = patch_.triangles[t];
  if (g.degenerate) return true;
  const Vec3 centre = node_position(8 * block[0], 8 * block[1], 8 * block[2]) + Vec3::Constant(3.5 * p_.h);
  const double reach = p_.seed_radius + 3.5 * std::sqrt(3.0) * p_.h;
  const Vec3& n = patch_.face_normals[t];
  if (std::abs(n.dot(centre - g.a)) > reach) return false;
  const std::array<Vec3, 3> q = {g.a, g.a + g.ab, g.a + g.ac};
  for (int k = 0; k < 3; ++k)
    if ((centre - q[k]).dot(patch_.side_normals[t][k]) > reach) return false;
  return true;
}

/// Exact distances from triangle t to the nodes of block b within the seed radius r whose closest
/// point can be on t: over the triangle, or outside an edge by at most r times its side_slack
/// (a node at distance d whose closest point is on an edge or vertex of t lies outside t's edge
/// plane by at most d times the sine of the angle between t's normal and its own direction, which
/// lies in the cone of the normals around that vertex or edge). Columns run along the axis closest
/// to the normal, each cut to the slab |n.(x - a)| <= r. On a smooth patch this evaluates a node
/// with one or two triangles instead of all within r of it, and every node within r still gets
/// the exact distance.
void DistanceBand::rasterize(std::size_t t, std::int32_t b) {
  const PatchTriangle& g = patch_.triangles[t];
  const double r = p_.seed_radius;
  const double h = p_.h;
  const Vec3& o = p_.origin;
  Block& blk = blocks_[b];
  std::array<std::array<std::int64_t, 3>, 2> range = seed_range(t);
  for (int a = 0; a < 3; ++a) {
    range[0][a] = std::max(range[0][a], 8 * blk.coord[a]);
    range[1][a] = std::min(range[1][a], 8 * blk.coord[a] + 7);
    if (range[0][a] > range[1][a]) return;
  }
  const Vec3& n = patch_.face_normals[t];
  int w = 0;
  n.cwiseAbs().maxCoeff(&w);
  const int u = (w + 1) % 3;
  const int v = (w + 2) % 3;
  const std::array<Vec3, 3> q = {g.a, g.a + g.ab, g.a + g.ac};
  const std::array<Vec3, 3>& side = patch_.side_normals[t];
  auto coordinate = [&](int axis, std::int64_t i) { return o[axis] + h * static_cast<double>(i - kIndexOffset); };
  const double inv_h = 1.0 / h;
  const double half = g.degenerate ? 0.0 : r / std::abs(n[w]); // |n[w]| >= 1/sqrt(3)
  std::array<double, 3> slack{};                               // how far outside edge k a node may be
  std::array<double, 3> column_slack{};                        // the same for a column's point on the plane
  for (int k = 0; k < 3; ++k) {
    slack[k] = r * patch_.side_slack[t][k] + 1e-6 * h;
    column_slack[k] = slack[k] + half * std::abs(side[k][w]);
  }

  Vec3 x;
  std::array<int, 3> local{};
  for (std::int64_t iu = range[0][u]; iu <= range[1][u]; ++iu) {
    x[u] = coordinate(u, iu);
    local[u] = static_cast<int>(iu & 7);
    for (std::int64_t iv = range[0][v]; iv <= range[1][v]; ++iv) {
      x[v] = coordinate(v, iv);
      local[v] = static_cast<int>(iv & 7);
      std::int64_t k0 = range[0][w];
      std::int64_t k1 = range[1][w];
      if (!g.degenerate) {
        // The column meets the slab |n.(x - a)| <= r around its point on the plane; skip it when
        // that point lies too far outside an edge for any node of the slab to come within r.
        x[w] = g.a[w] - (n[u] * (x[u] - g.a[u]) + n[v] * (x[v] - g.a[v])) / n[w];
        if ((x - q[0]).dot(side[0]) > column_slack[0] || (x - q[1]).dot(side[1]) > column_slack[1] ||
            (x - q[2]).dot(side[2]) > column_slack[2])
          continue;
        k0 = std::max(k0, ceil_int((x[w] - half - o[w]) * inv_h) + kIndexOffset);
        k1 = std::min(k1, floor_int((x[w] + half - o[w]) * inv_h) + kIndexOffset);
      }
      for (std::int64_t kw = k0; kw <= k1; ++kw) {
        x[w] = coordinate(w, kw);
        if (!g.degenerate && ((x - q[0]).dot(side[0]) > slack[0] || (x - q[1]).dot(side[1]) > slack[1] ||
                              (x - q[2]).dot(side[2]) > slack[2]))
          continue;
        const Nearest near = nearest_on_triangle(g, x);
        if (near.squared > r * r) continue;
        local[w] = static_cast<int>(kw & 7);
        const int l = local[0] | (local[1] << 3) | (local[2] << 6);
        const auto d = static_cast<float>(std::sqrt(near.squared));
        const std::uint64_t bit = std::uint64_t{1} << (l & 63);
        if ((blk.computed[l >> 6] & bit) && !(d < blk.dist[l])) continue;
        blk.computed[l >> 6] |= bit;
        blk.dist[l] = d;
        blk.closest[l] = static_cast<std::int32_t>(8 * t) + near.feature;
        if (spreads(near, static_cast<std::int32_t>(t), d)) {
          blk.front[l >> 6] |= bit;
          blk.spreading[l >> 6] |= bit;
        } else {
          blk.front[l >> 6] &= ~bit;
          blk.spreading[l >> 6] &= ~bit;
        }
        if (anchors(near, static_cast<std::int32_t>(t), d)) blk.anchoring[l >> 6] |= bit;
        else blk.anchoring[l >> 6] &= ~bit;
      }
    }
  }
}

void DistanceBand::seed() {
  // Bin the triangles into the blocks their seed region may reach, creating the blocks, then fill
  // the blocks in parallel, each from its own triangles (no two threads write the same block).
  const std::size_t nf = patch_.triangles.size();
  std::vector<std::pair<std::int32_t, std::int32_t>> pairs; // (block, triangle)
  pairs.reserve(4 * nf);
  for (std::size_t t = 0; t < nf; ++t) {
    const auto range = seed_range(t);
    std::array<std::int64_t, 3> lo{}, hi{};
    std::int64_t count = 1;
    for (int a = 0; a < 3; ++a) {
      lo[a] = range[0][a] >> 3;
      hi[a] = range[1][a] >> 3;
      count *= std::max<std::int64_t>(0, hi[a] - lo[a] + 1);
    }
    for (std::int64_t bz = lo[2]; bz <= hi[2]; ++bz)
      for (std::int64_t by = lo[1]; by <= hi[1]; ++by)
        for (std::int64_t bx = lo[0]; bx <= hi[0]; ++bx) {
          if (count > 8 && !block_may_hold_seeds(t, {bx, by, bz})) continue;
          pairs.emplace_back(find_or_create_block(bx, by, bz), static_cast<std::int32_t>(t));
        }
  }
  std::vector<std::size_t> offsets(blocks_.size() + 1, 0);
  for (const auto& pr : pairs) ++offsets[pr.first + 1];
  for (std::size_t b = 0; b < blocks_.size(); ++b) offsets[b + 1] += offsets[b];
  std::vector<std::int32_t> binned(pairs.size());
  {
    std::vector<std::size_t> fill(offsets.begin(), offsets.end() - 1);
    for (const auto& pr : pairs) binned[fill[pr.first]++] = pr.second;
  }
  pairs = {};
  detail::parallel_for(blocks_.size(), 16, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t b = begin; b < end; ++b)
      for (std::size_t k = offsets[b]; k < offsets[b + 1]; ++k)
        rasterize(static_cast<std::size_t>(binned[k]), static_cast<std::int32_t>(b));
  });
  for (std::size_t b = 0; b < blocks_.size(); ++b) {
    bool any_front = false;
    for (int s = 0; s < 8; ++s) {
      computed_nodes_ += static_cast<std::size_t>(bit_count(blocks_[b].computed[s]));
      any_front = any_front || blocks_[b].front[s] != 0;
    }
    if (any_front) front_blocks_.push_back(static_cast<std::int32_t>(b));
  }
}

// ---- growing ------------------------------------------------------------------------------------------

void DistanceBand::deposit(std::int32_t target, const std::uint64_t* masks, int first, int count, std::uint32_t layer,
                           std::vector<std::int32_t>& touched) {
  Block& blk = blocks_[target];
  std::uint64_t any = 0;
  for (int s = first; s < first + count; ++s) {
    const std::uint64_t m = masks[s - first] & ~blk.computed[s];
    blk.pending[s] |= m;
    any |= m;
  }
  if (any && blk.pending_stamp != layer) {
    blk.pending_stamp = layer;
    touched.push_back(target);
  }
}

// Dilates the front of block b by one node in all 26 directions, with bit operations on the z-slice
// masks, and marks the not yet computed nodes it reaches (in b and in its neighbours) as pending.
void DistanceBand::spread_front(std::int32_t b, std::uint32_t layer, std::vector<std::int32_t>& touched) {
  const SliceMasks f = blocks_[b].front;
  blocks_[b].front.fill(0);
  std::uint64_t along_x[3][8]; // [ox + 1][slice]
  for (int s = 0; s < 8; ++s) {
    const std::uint64_t m = f[s];
    along_x[0][s] = (m & kColumn0) << 7;
    along_x[1][s] = m | ((m << 1) & ~kColumn0) | ((m >> 1) & ~kColumn7);
    along_x[2][s] = (m & kColumn7) >> 7;
  }
  for (int ox = 0; ox < 3; ++ox)
    for (int oy = 0; oy < 3; ++oy) {
      std::uint64_t m[8];
      std::uint64_t any = 0;
      for (int s = 0; s < 8; ++s) {
        const std::uint64_t x = along_x[ox][s];
        m[s] = oy == 0 ? x << 56 : oy == 1 ? x | (x << 8) | (x >> 8) : x >> 56;
        any |= m[s];
      }
      if (!any) continue;
      std::uint64_t same_z[8];
      for (int s = 0; s < 8; ++s) same_z[s] = m[s] | (s > 0 ? m[s - 1] : 0) | (s < 7 ? m[s + 1] : 0);
      deposit(neighbour_or_create(b, neighbour_slot(ox - 1, oy - 1, 0)), same_z, 0, 8, layer, touched);
      if (m[7]) deposit(neighbour_or_create(b, neighbour_slot(ox - 1, oy - 1, 1)), &m[7], 0, 1, layer, touched);
      if (m[0]) deposit(neighbour_or_create(b, neighbour_slot(ox - 1, oy - 1, -1)), &m[0], 7, 1, layer, touched);
    }
}

// Closest-point propagation. A node takes the nearest of the closest triangles of its computed
// neighbours, each evaluated exactly at the node (a triangle whose plane is farther than the best so
// far is skipped); when that nearest is reached at a vertex or an edge, the other triangles around
// the vertex or edge are evaluated too (neighbours that tie at a vertex name any one of its
// triangles, which would hide the others).
DistanceBand::Closest DistanceBand::closest_among(const Vec3& x, const std::int32_t* candidates, int count,
                                                  Scratch& scratch) const {
  if (++scratch.current == 0) {
    std::fill(scratch.stamp.begin(), scratch.stamp.end(), 0);
    scratch.current = 1;
  }
  const std::uint32_t current = scratch.current;
  Closest best;
  best.nearest.squared = std::numeric_limits<double>::infinity();
  auto consider = [&](std::int32_t t) {
    if (scratch.stamp[t] == current) return;
    scratch.stamp[t] = current;
    const PatchTriangle& g = patch_.triangles[t];
    const double plane_distance = g.normal.dot(x) - g.plane; // a lower bound of the distance
    if (plane_distance * plane_distance > best.nearest.squared) return;
    const Nearest n = nearest_on_triangle(g, x);
    if (n.squared < best.nearest.squared || (n.squared == best.nearest.squared && t < best.tri)) {
      best.nearest = n;
      best.tri = t;
    }
  };
  for (int k = 0; k < count; ++k) consider(candidates[k]);
  for (int round = 0; round < 8 && best.tri >= 0 && best.nearest.feature != kFace; ++round) {
    const std::int32_t t = best.tri;
    const int feature = best.nearest.feature;
    const bool vertex = feature <= kVertex2;
    const std::size_t row = vertex ? patch_.mesh->triangles[t][feature - kVertex0]
                                   : static_cast<std::size_t>(patch_.edge_of[3 * t + (feature - kEdge01)]);
    const std::vector<Index>& offsets = vertex ? patch_.vertex_face_offsets : patch_.edge_face_offsets;
    const std::vector<Index>& faces = vertex ? patch_.vertex_faces : patch_.edge_faces;
    for (Index k = offsets[row]; k < offsets[row + 1]; ++k) consider(static_cast<std::int32_t>(faces[k]));
    if (best.tri == t && best.nearest.feature == feature) break;
  }
  return best;
}

/// The 26 neighbour offsets (dx, dy, dz in -1..1, not all 0), dx fastest, and their index
/// offsets in a 10x10x10 apron.
struct NeighbourOffsets {
  std::array<std::array<int, 3>, 26> step{};
  std::array<int, 26> apron{};
  constexpr NeighbourOffsets() {
    int k = 0;
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if (dx != 0 || dy != 0 || dz != 0) {
            step[k] = {dx, dy, dz};
            apron[k] = dx + 10 * dy + 100 * dz;
            ++k;
          }
  }
  [[nodiscard]] Vec3 vector(int k, double h) const { return h * Vec3(step[k][0], step[k][1], step[k][2]); }
};

constexpr NeighbourOffsets kNeighbours;
constexpr std::array<int, 6> kFaceNeighbours = {4, 10, 12, 13, 15, 21}; // indices of the 6 face neighbours
static_assert(kNeighbours.step[4][2] == -1 && kNeighbours.step[21][2] == 1 && kNeighbours.step[12][0] == -1 &&
              kNeighbours.step[13][0] == 1 && kNeighbours.step[10][1] == -1 && kNeighbours.step[15][1] == 1);

// Besides its value, the evaluation of node x reports the neighbours whose stored distance is
// larger than their distance to x's closest point (plus a tolerance): those were given a wrong
// triangle (the band grows in layers of 26-neighbours, which reach some nodes from the wrong part
// of the patch first, near its medial axis) and are repaired after the layer (see repair()).
void DistanceBand::evaluate_block(std::int32_t b, const std::vector<std::uint32_t>& nodes, std::size_t begin,
                                  std::size_t end, Scratch& scratch, std::vector<Evaluation>& out) const {
  if (scratch.stamp.size() != patch_.triangles.size()) scratch.stamp.assign(patch_.triangles.size(), 0);
  {
    // Only the rows around the block's candidates are read.
    int y0 = 7, y1 = 0, z0 = 7, z1 = 0;
    for (std::size_t i = begin; i < end; ++i) {
      const int l = static_cast<int>(nodes[i] % kBlockNodes);
      y0 = std::min(y0, (l >> 3) & 7);
      y1 = std::max(y1, (l >> 3) & 7);
      z0 = std::min(z0, l >> 6);
      z1 = std::max(z1, l >> 6);
    }
    fill_apron(b, y0, y1 + 2, z0, z1 + 2, scratch);
  }
  const NeighbourOffsets& offsets = kNeighbours;
  const double tolerance = kRepairTolerance * p_.h;

  for (std::size_t i = begin; i < end; ++i) {
    const int l = static_cast<int>(nodes[i] % kBlockNodes);
    const int centre = ((l & 7) + 1) + 10 * (((l >> 3) & 7) + 1) + 100 * ((l >> 6) + 1);
    // The neighbours' closest triangles, without runs of repeats (neighbours along x mostly
    // agree) and without the -1 of nodes not computed yet; stamps remove the other repeats.
    std::array<std::int32_t, 26> candidates;
    int count = 0;
    std::int32_t previous = -1;
    const std::int32_t* around = scratch.apron.data() + centre;
#pragma GCC unroll 26
    for (int k = 0; k < 26; ++k) {
      const std::int32_t t = around[offsets.apron[k]] >> 3; // -1 where not computed
      candidates[count] = t;
      count += static_cast<int>((t != previous) & (t >= 0));
      previous = t;
    }
    const Vec3 x = node_position(b, l);
    const Closest best = closest_among(x, candidates.data(), count, scratch);
    Evaluation& e = out[i];
    e = {std::numeric_limits<float>::infinity(), -1, false, false, 0};
    if (best.tri < 0) continue;
    const double d = std::sqrt(best.nearest.squared);
    e.dist = static_cast<float>(d);
    e.closest = 8 * best.tri + best.nearest.feature;
    e.spreads = spreads(best.nearest, best.tri, d);
    e.anchors = anchors(best.nearest, best.tri, d);
    // Neighbour x + h u is at most |h u + offset| from x's closest point. (The 6 face neighbours
    // are enough to find the border of a wrongly reached region; repair() looks at all 26.)
    const float* around_dist = scratch.apron_dist.data() + centre;
    for (const int k : kFaceNeighbours) {
      const std::int32_t c = around[offsets.apron[k]];
      if (c < 0 || (c >> 3) == best.tri) continue;
      const double stored = around_dist[offsets.apron[k]] - tolerance;
      if (stored > 0.0 && stored * stored > (offsets.vector(k, p_.h) + best.nearest.offset).squaredNorm())
        e.suspects |= std::uint32_t{1} << k;
    }
  }
}

/// Copies the closest-feature codes and distances of block b and of the one-node layer around it
/// (from its 26 neighbours; -1 and infinity where absent) into 10x10x10 arrays (x + 1, y + 1,
/// z + 1), rows y0..y1 of the planes z0..z1 only (apron coordinates).
void DistanceBand::fill_apron(std::int32_t b, int y0, int y1, int z0, int z1, Scratch& scratch) const {
  const Block& blk = blocks_[b];
  constexpr float kFar = std::numeric_limits<float>::infinity();
  for (int z = z0; z <= z1; ++z) {
    const int oz = z == 0 ? -1 : z == 9 ? 1 : 0;
    for (int y = y0; y <= y1; ++y) {
      const int oy = y == 0 ? -1 : y == 9 ? 1 : 0;
      const int row = 8 * ((y + 7) & 7) + 64 * ((z + 7) & 7); // local index of x = 0
      std::int32_t* code = &scratch.apron[10 * y + 100 * z];
      float* dist = &scratch.apron_dist[10 * y + 100 * z];
      const std::int32_t left = blk.neighbours[neighbour_slot(-1, oy, oz)];
      const std::int32_t middle = blk.neighbours[neighbour_slot(0, oy, oz)];
      const std::int32_t right = blk.neighbours[neighbour_slot(1, oy, oz)];
      code[0] = left >= 0 ? blocks_[left].closest[row + 7] : -1;
      dist[0] = left >= 0 ? blocks_[left].dist[row + 7] : kFar;
      if (middle >= 0) {
        std::copy_n(&blocks_[middle].closest[row], 8, code + 1);
        std::copy_n(&blocks_[middle].dist[row], 8, dist + 1);
      } else {
        std::fill_n(code + 1, 8, -1);
        std::fill_n(dist + 1, 8, kFar);
      }
      code[9] = right >= 0 ? blocks_[right].closest[row] : -1;
      dist[9] = right >= 0 ? blocks_[right].dist[row] : kFar;
    }
  }
}

/// Re-evaluates the queued nodes from all their computed neighbours, one at a time. A node that
/// gets nearer queues the neighbours that its new closest point shows to be wrong in turn, and
/// joins the front when it now spreads. Rare: where parts of the patch face each other.
void DistanceBand::repair(std::vector<std::uint32_t>& queue, std::uint32_t layer) {
  Scratch& scratch = scratch_[0];
  if (scratch.stamp.size() != patch_.triangles.size()) scratch.stamp.assign(patch_.triangles.size(), 0);
  const NeighbourOffsets& offsets = kNeighbours;
  const double tolerance = kRepairTolerance * p_.h;
  auto neighbour = [&](std::int32_t b, int l, int k, std::int32_t& nb, int& nl) {
    const std::array<int, 3>& u = offsets.step[k];
    const int nx = (l & 7) + u[0];
    const int ny = ((l >> 3) & 7) + u[1];
    const int nz = (l >> 6) + u[2];
    nb = blocks_[b].neighbours[neighbour_slot(nx >> 3, ny >> 3, nz >> 3)];
    nl = (nx & 7) | ((ny & 7) << 3) | ((nz & 7) << 6);
    return nb >= 0 && ((blocks_[nb].computed[nl >> 6] >> (nl & 63)) & 1) != 0;
  };
  while (!queue.empty()) {
    const std::uint32_t node = queue.back();
    queue.pop_back();
    const auto b = static_cast<std::int32_t>(node / kBlockNodes);
    const int l = static_cast<int>(node % kBlockNodes);
    Block& blk = blocks_[b];
    const std::uint64_t bit = std::uint64_t{1} << (l & 63);
    blk.queued[l >> 6] &= ~bit;

    std::array<std::int32_t, 27> candidates;
    int count = 0;
    candidates[count++] = blk.closest[l] >> 3;
    for (int k = 0; k < 26; ++k) {
      std::int32_t nb = -1;
      int nl = 0;
      if (neighbour(b, l, k, nb, nl)) candidates[count++] = blocks_[nb].closest[nl] >> 3;
    }
    const Vec3 x = node_position(b, l);
    const Closest best = closest_among(x, candidates.data(), count, scratch);
    const double d = std::sqrt(best.nearest.squared);
    if (!(static_cast<float>(d) < blk.dist[l])) continue;
    blk.dist[l] = static_cast<float>(d);
    blk.closest[l] = 8 * best.tri + best.nearest.feature;
    if (anchors(best.nearest, best.tri, d)) blk.anchoring[l >> 6] |= bit;
    else blk.anchoring[l >> 6] &= ~bit;
    if (!(blk.spreading[l >> 6] & bit) && spreads(best.nearest, best.tri, d)) {
      blk.spreading[l >> 6] |= bit;
      blk.front[l >> 6] |= bit;
      if (blk.front_stamp != layer) {
        blk.front_stamp = layer;
        front_blocks_.push_back(b);
      }
    }
    for (int k = 0; k < 26; ++k) {
      std::int32_t nb = -1;
      int nl = 0;
      if (!neighbour(b, l, k, nb, nl)) continue;
      Block& nbk = blocks_[nb];
      const double stored = nbk.dist[nl] - tolerance;
      const std::uint64_t nbit = std::uint64_t{1} << (nl & 63);
      if (stored > 0.0 && !(nbk.queued[nl >> 6] & nbit) &&
          stored * stored > (offsets.vector(k, p_.h) + best.nearest.offset).squaredNorm()) {
        nbk.queued[nl >> 6] |= nbit;
        queue.push_back(static_cast<std::uint32_t>(nb) * kBlockNodes + static_cast<std::uint32_t>(nl));
      }
    }
  }
}

void DistanceBand::grow() {
  std::vector<std::int32_t> touched;
  std::vector<std::uint32_t> nodes;
  std::vector<std::size_t> starts; // nodes of touched[k] are nodes[starts[k] .. starts[k + 1])
  std::vector<Evaluation> results;
  std::vector<std::uint32_t> queue;
  for (std::uint32_t layer = 1; !front_blocks_.empty(); ++layer) {
    touched.clear();
    for (const std::int32_t b : front_blocks_) spread_front(b, layer, touched);
    front_blocks_.clear();
    nodes.clear();
    starts.clear();
    for (const std::int32_t b : touched) {
      starts.push_back(nodes.size());
      Block& blk = blocks_[b];
      for (int s = 0; s < 8; ++s) {
        for (std::uint64_t m = blk.pending[s]; m; m &= m - 1)
          nodes.push_back(static_cast<std::uint32_t>(b) * kBlockNodes + 64 * s + std::countr_zero(m));
        blk.pending[s] = 0;
      }
    }
    starts.push_back(nodes.size());
    results.resize(nodes.size());
    detail::parallel_for(touched.size(), 8, [&](std::size_t worker, std::size_t begin, std::size_t end) {
      for (std::size_t k = begin; k < end; ++k)
        evaluate_block(touched[k], nodes, starts[k], starts[k + 1], scratch_[worker], results);
    });
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      const Evaluation& e = results[i];
      if (e.closest < 0) continue;
      const auto b = static_cast<std::int32_t>(nodes[i] / kBlockNodes);
      const int l = static_cast<int>(nodes[i] % kBlockNodes);
      Block& blk = blocks_[b];
      const std::uint64_t bit = std::uint64_t{1} << (l & 63);
      blk.dist[l] = e.dist;
      blk.closest[l] = e.closest;
      blk.computed[l >> 6] |= bit;
      ++computed_nodes_;
      if (e.anchors) blk.anchoring[l >> 6] |= bit;
      if (e.spreads) {
        blk.front[l >> 6] |= bit;
        blk.spreading[l >> 6] |= bit;
        if (blk.front_stamp != layer) {
          blk.front_stamp = layer;
          front_blocks_.push_back(b);
        }
      }
      for (std::uint32_t m = e.suspects; m; m &= m - 1) {
        const std::array<int, 3>& u = kNeighbours.step[std::countr_zero(m)];
        const int nx = (l & 7) + u[0];
        const int ny = ((l >> 3) & 7) + u[1];
        const int nz = (l >> 6) + u[2];
        const std::int32_t nb = blk.neighbours[neighbour_slot(nx >> 3, ny >> 3, nz >> 3)];
        const int nl = (nx & 7) | ((ny & 7) << 3) | ((nz & 7) << 6);
        Block& nbk = blocks_[nb];
        const std::uint64_t nbit = std::uint64_t{1} << (nl & 63);
        if (nbk.queued[nl >> 6] & nbit) continue;
        nbk.queued[nl >> 6] |= nbit;
        queue.push_back(static_cast<std::uint32_t>(nb) * kBlockNodes + static_cast<std::uint32_t>(nl));
      }
    }
    repair(queue, layer);
  }
}

} // namespace st::offset_detail
