#include "st/offset.h"
#include "detail/format.h"

#include "detail/parallel.h"
#include "st/errors.h"
#include "st/tolerances.h"

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

namespace st {
namespace {

// ---- sparse grid layout ---------------------------------------------------------------------------
// A node is addressed by stored indices (I, J, K) = grid indices + kIndexOffset, each below 2^20.
// Nodes live in 8x8x8 blocks, found by a hash map from the block coordinates (I, J, K) >> 3 and
// linked to their 26 neighbours; a node is referred to by 512 * block index + local index, local
// index l = x + 8y + 64z. The 64 nodes of one z-slice form one 64-bit mask (bit x + 8y), so that
// growing the band and finding the contoured cubes are bit operations on 8 words per block.

constexpr int kBlockNodes = 512;
constexpr std::int64_t kIndexOffset = std::int64_t{1} << 19;
constexpr std::uint64_t kColumn0 = 0x0101010101010101ULL; // slice bits with x == 0
constexpr std::uint64_t kColumn7 = 0x8080808080808080ULL; // slice bits with x == 7

/// A node is repaired when its distance exceeds an upper bound shown by a neighbour by more than
/// this many cell sizes (float storage makes smaller differences meaningless).
constexpr double kRepairTolerance = 1e-4;

/// Index of the block offset (ox, oy, oz) in {-1, 0, 1}^3 in a block's neighbour table; 13 is itself
/// and 26 - s is the opposite of s.
constexpr int neighbour_slot(int ox, int oy, int oz) { return (ox + 1) + 3 * (oy + 1) + 9 * (oz + 1); }

using SliceMasks = std::array<std::uint64_t, 8>;

/// Number of set bits, inline (without -mpopcnt, std::popcount is a library call).
constexpr int bit_count(std::uint64_t m) {
  m = m - ((m >> 1) & 0x5555555555555555ULL);
  m = (m & 0x3333333333333333ULL) + ((m >> 2) & 0x3333333333333333ULL);
  m = (m + (m >> 4)) & 0x0F0F0F0F0F0F0F0FULL;
  return static_cast<int>((m * 0x0101010101010101ULL) >> 56);
}

// floor and ceil to integers without a library call (the default x86-64 target has no roundsd).
std::int64_t floor_int(double x) {
  const auto i = static_cast<std::int64_t>(x);
  return i - (x < static_cast<double>(i) ? 1 : 0);
}
std::int64_t ceil_int(double x) {
  const auto i = static_cast<std::int64_t>(x);
  return i + (x > static_cast<double>(i) ? 1 : 0);
}

struct Block {
  std::array<float, kBlockNodes> dist;           // unsigned distance, mm (valid where computed)
  std::array<std::int32_t, kBlockNodes> closest; // 8 * triangle + Feature, -1 where not computed
  SliceMasks computed;
  SliceMasks pending;                            // candidates of the layer being built
  SliceMasks front;                              // nodes that spread in the next layer
  SliceMasks spreading;                          // nodes that spread (all layers)
  SliceMasks anchoring;                          // nodes whose cubes are contoured (see contour())
  SliceMasks queued;                             // nodes waiting for repair
  std::array<std::int32_t, 27> neighbours;       // block indices, -1 where absent
  std::array<std::int64_t, 3> coord;             // block coordinates (stored index >> 3)
  std::uint32_t pending_stamp;                   // layer in which the block was listed for candidates
  std::uint32_t front_stamp;                     // layer in which the block was listed for the front
};

std::uint64_t block_key(std::int64_t bx, std::int64_t by, std::int64_t bz) {
  return (static_cast<std::uint64_t>(bx) << 34) | (static_cast<std::uint64_t>(by) << 17) |
         static_cast<std::uint64_t>(bz);
}

/// Value of `m` (the slice masks of one block and of its neighbours at +x, +y, +x+y, same slice)
/// seen one node further along x and/or y: bit (x, y) of the result is bit (x + sx, y + sy).
std::uint64_t shift_x(std::uint64_t m, std::uint64_t next_x) {
  return ((m >> 1) & ~kColumn7) | ((next_x & kColumn0) << 7);
}
std::uint64_t shift_y(std::uint64_t m, std::uint64_t next_y) { return (m >> 8) | (next_y << 56); }

// ---- open-addressing hash map, 64-bit keys to 32-bit values ----------------------------------------

class HashMap64 {
public:
  explicit HashMap64(std::size_t expected) {
    std::size_t capacity = 64;
    while (capacity < 2 * expected) capacity *= 2;
    allocate(capacity);
  }

  /// The value stored for `key`, or -1.
  [[nodiscard]] std::int32_t find(std::uint64_t key) const {
    for (std::size_t i = slot(key);; i = (i + 1) & mask_) {
      if (entries_[i].key == key) return entries_[i].value;
      if (entries_[i].key == kEmpty) return -1;
    }
  }

  /// Stores (key, value) unless `key` is present; returns the stored value and whether it is new.
  std::pair<std::int32_t, bool> insert(std::uint64_t key, std::int32_t value) {
    if (2 * (size_ + 1) > entries_.size()) grow();
    std::size_t i = slot(key);
    for (; entries_[i].key != kEmpty; i = (i + 1) & mask_)
      if (entries_[i].key == key) return {entries_[i].value, false};
    entries_[i] = {key, value};
    ++size_;
    return {value, true};
  }

private:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};
  struct Entry {
    std::uint64_t key;
    std::int32_t value;
  };

  [[nodiscard]] std::size_t slot(std::uint64_t key) const {
    key ^= key >> 29;
    key *= 0x9E3779B97F4A7C15ULL; // Fibonacci hashing: the top bits of the product
    return static_cast<std::size_t>(key >> shift_);
  }

  void allocate(std::size_t capacity) {
    entries_.assign(capacity, Entry{kEmpty, -1});
    mask_ = capacity - 1;
    shift_ = 64 - std::countr_zero(capacity);
  }

  void grow() {
    const std::vector<Entry> old = std::move(entries_);
    allocate(2 * old.size());
    for (const Entry& e : old) {
      if (e.key == kEmpty) continue;
      std::size_t i = slot(e.key);
      while (entries_[i].key != kEmpty) i = (i + 1) & mask_;
      entries_[i] = e;
    }
  }

  std::vector<Entry> entries_;
  std::size_t mask_ = 0;
  int shift_ = 0;
  std::size_t size_ = 0;
};

// ---- point-triangle distance -----------------------------------------------------------------------

enum Feature : int { kFace = 0, kVertex0, kVertex1, kVertex2, kEdge01, kEdge12, kEdge20 };

struct TriangleGeometry {
  Vec3 a, ab, ac;
  double abab = 0.0, abac = 0.0, acac = 0.0;
  double inv_gram = 0.0; // 1 / |ab x ac|^2
  Vec3 normal = Vec3::Zero(); // unit, zero when degenerate
  double plane = 0.0;         // normal.a: |normal.p - plane| is a lower bound of the distance
  bool degenerate = false;
};

struct Nearest {
  double squared = 0.0;
  Vec3 offset = Vec3::Zero(); // query point minus closest point
  int feature = kFace;  // where the closest point lies
};

Nearest nearest_on_segment(const Vec3& p, const Vec3& s, const Vec3& e, int at_s, int at_e,
                           int inside) {
  const Vec3 se = e - s;
  const double len2 = se.squaredNorm();
  const double t = len2 > 0.0 ? (p - s).dot(se) / len2 : 0.0;
  Nearest n;
  if (t <= 0.0) {
    n.offset = p - s;
    n.feature = at_s;
  } else if (t >= 1.0) {
    n.offset = p - e;
    n.feature = at_e;
  } else {
    n.offset = p - (s + t * se);
    n.feature = inside;
  }
  n.squared = n.offset.squaredNorm();
  return n;
}

/// Closest point of the triangle to p, by the Voronoi region of p: a vertex, an edge or the face
/// (the region tests are dot products with the edges, reusing d1 = ab.ap and d2 = ac.ap).
Nearest nearest_on_triangle(const TriangleGeometry& g, const Vec3& p) {
  const Vec3 ap = p - g.a;
  if (g.degenerate) {
    const Vec3 b = g.a + g.ab;
    const Vec3 c = g.a + g.ac;
    Nearest best = nearest_on_segment(p, g.a, b, kVertex0, kVertex1, kEdge01);
    Nearest n = nearest_on_segment(p, b, c, kVertex1, kVertex2, kEdge12);
    if (n.squared < best.squared) best = n;
    n = nearest_on_segment(p, c, g.a, kVertex2, kVertex0, kEdge20);
    if (n.squared < best.squared) best = n;
    return best;
  }
  Nearest n;
  const double d1 = g.ab.dot(ap);
  const double d2 = g.ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) {
    n.offset = ap;
    n.feature = kVertex0;
  } else {
    // ab.(p - b), ac.(p - b), ab.(p - c), ac.(p - c)
    const double d3 = d1 - g.abab;
    const double d4 = d2 - g.abac;
    const double d5 = d1 - g.abac;
    const double d6 = d2 - g.acac;
    const double vc = g.abab * d2 - g.abac * d1; // = d1*d4 - d3*d2
    const double vb = g.acac * d1 - g.abac * d2; // = d5*d2 - d1*d6
    if (d3 >= 0.0 && d4 <= d3) {
      n.offset = ap - g.ab;
      n.feature = kVertex1;
    } else if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
      n.offset = ap - (d1 / (d1 - d3)) * g.ab;
      n.feature = kEdge01;
    } else if (d6 >= 0.0 && d5 <= d6) {
      n.offset = ap - g.ac;
      n.feature = kVertex2;
    } else if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
      n.offset = ap - (d2 / (d2 - d6)) * g.ac;
      n.feature = kEdge20;
    } else {
      const double va = d3 * d6 - d5 * d4;
      const double e1 = d4 - d3;
      const double e2 = d5 - d6;
      if (va <= 0.0 && e1 >= 0.0 && e2 >= 0.0) {
        const double w = e1 / (e1 + e2);
        n.offset = ap - g.ab - w * (g.ac - g.ab);
        n.feature = kEdge12;
      } else {
        n.offset = ap - (vb * g.inv_gram) * g.ab - (vc * g.inv_gram) * g.ac;
        n.feature = kFace;
      }
    }
  }
  n.squared = n.offset.squaredNorm();
  return n;
}

// ---- the patch: per-triangle geometry and pseudo-normals ---------------------------------------------

struct Patch {
  const TriangleMesh* mesh = nullptr;
  std::vector<TriangleGeometry> triangles;
  std::vector<Vec3> face_normals;   // unit, zero for degenerate triangles
  std::vector<std::array<Vec3, 3>> side_normals; // unit outward normals of the planes through each
                                                 // edge perpendicular to the triangle (edge k: k, k+1)
  std::vector<std::int32_t> edge_of; // 3 per triangle: edge k runs from corner k to corner k+1
  std::vector<Vec3> edge_normals;   // unit sum of the adjacent face normals
  std::vector<Vec3> vertex_normals; // unit angle-weighted sum of the incident face normals
  std::vector<Index> vertex_face_offsets, vertex_faces; // triangles around each vertex (rows)
  std::vector<Index> edge_face_offsets, edge_faces;     // triangles along each edge (rows)
  std::vector<std::uint8_t> border_edge;   // 1 for edges used by one triangle
  std::vector<std::uint8_t> border_vertex; // 1 for vertices of such edges
  std::vector<std::array<float, 3>> side_slack; // per triangle and edge k: how far outside the
                                                // edge's plane (in units of the distance) the
                                                // points whose closest point is on the edge or its
                                                // end points can lie: 1 on the border, else the
                                                // sine of the largest angle between this triangle's
                                                // normal and those around the edge's end points
  double area = 0.0;
  double border_length = 0.0;       // total length of edges used by one triangle

  /// Pseudo-normal of the closest feature (Baerentzen & Aanaes): a point lies behind the patch when
  /// its offset from the closest point has a negative dot product with it.
  [[nodiscard]] const Vec3& pseudo_normal(std::int32_t t, int feature) const {
    if (feature == kFace) return face_normals[t];
    if (feature <= kVertex2) return vertex_normals[mesh->triangles[t][feature - kVertex0]];
    return edge_normals[edge_of[3 * t + (feature - kEdge01)]];
  }

  /// Whether the closest feature lies on the patch's border.
  [[nodiscard]] bool on_border(std::int32_t t, int feature) const {
    if (feature == kFace) return false;
    if (feature <= kVertex2) return border_vertex[mesh->triangles[t][feature - kVertex0]] != 0;
    return border_edge[edge_of[3 * t + (feature - kEdge01)]] != 0;
  }
};

Patch build_patch(const TriangleMesh& mesh, bool with_pseudo_normals) {
  Patch patch;
  patch.mesh = &mesh;
  const std::size_t nf = mesh.triangles.size();
  patch.triangles.resize(nf);
  patch.face_normals.resize(nf);
  patch.side_normals.assign(nf, {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()});
  patch.edge_of.resize(3 * nf);
  for (std::size_t t = 0; t < nf; ++t) {
    const Triangle& tri = mesh.triangles[t];
    TriangleGeometry& g = patch.triangles[t];
    g.a = mesh.positions[tri[0]];
    g.ab = mesh.positions[tri[1]] - g.a;
    g.ac = mesh.positions[tri[2]] - g.a;
    g.abab = g.ab.squaredNorm();
    g.abac = g.ab.dot(g.ac);
    g.acac = g.ac.squaredNorm();
    const Vec3 n = g.ab.cross(g.ac);
    const double gram = n.squaredNorm();
    // A triangle whose smallest angle has a sine below 1e-6 is handled as its three edges.
    g.degenerate = !(gram > 1e-12 * g.abab * g.acac) || !(gram > 0.0);
    g.inv_gram = g.degenerate ? 0.0 : 1.0 / gram;
    patch.face_normals[t] = g.degenerate ? Vec3::Zero() : Vec3(n / std::sqrt(gram));
    g.normal = patch.face_normals[t];
    g.plane = g.normal.dot(g.a);
    if (!g.degenerate) {
      const std::array<Vec3, 3> q = {g.a, g.a + g.ab, g.a + g.ac};
      for (int k = 0; k < 3; ++k) patch.side_normals[t][k] = (q[(k + 1) % 3] - q[k]).cross(g.normal).normalized();
    }
    patch.area += 0.5 * std::sqrt(gram);
  }

  HashMap64 edge_ids(3 * nf / 2 + 16);
  std::vector<std::int32_t> edge_uses;
  std::vector<double> edge_length;
  for (std::size_t t = 0; t < nf; ++t) {
    const Triangle& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const Index u = tri[k];
      const Index v = tri[(k + 1) % 3];
      const std::uint64_t key = (static_cast<std::uint64_t>(std::min(u, v)) << 32) | std::max(u, v);
      const auto [id, is_new] = edge_ids.insert(key, static_cast<std::int32_t>(edge_uses.size()));
      if (is_new) {
        edge_uses.push_back(0);
        edge_length.push_back((mesh.positions[u] - mesh.positions[v]).norm());
      }
      ++edge_uses[id];
      patch.edge_of[3 * t + k] = id;
    }
  }
  patch.border_edge.assign(edge_uses.size(), 0);
  patch.border_vertex.assign(mesh.positions.size(), 0);
  for (std::size_t e = 0; e < edge_uses.size(); ++e)
    if (edge_uses[e] == 1) {
      patch.border_length += edge_length[e];
      patch.border_edge[e] = 1;
    }
  for (std::size_t c = 0; c < 3 * nf; ++c)
    if (patch.border_edge[patch.edge_of[c]]) {
      patch.border_vertex[mesh.triangles[c / 3][c % 3]] = 1;
      patch.border_vertex[mesh.triangles[c / 3][(c + 1) % 3]] = 1;
    }

  // Compressed rows: vertex -> triangles, edge -> triangles.
  auto build_rows = [nf](std::size_t rows, auto&& row_of, std::vector<Index>& offsets, std::vector<Index>& items) {
    offsets.assign(rows + 1, 0);
    for (std::size_t c = 0; c < 3 * nf; ++c) ++offsets[row_of(c) + 1];
    for (std::size_t r = 0; r < rows; ++r) offsets[r + 1] += offsets[r];
    items.resize(offsets[rows]);
    std::vector<Index> fill(offsets.begin(), offsets.end() - 1);
    for (std::size_t c = 0; c < 3 * nf; ++c) items[fill[row_of(c)]++] = static_cast<Index>(c / 3);
  };
  build_rows(mesh.positions.size(), [&](std::size_t c) { return mesh.triangles[c / 3][c % 3]; },
             patch.vertex_face_offsets, patch.vertex_faces);
  build_rows(edge_uses.size(), [&](std::size_t c) { return static_cast<Index>(patch.edge_of[c]); },
             patch.edge_face_offsets, patch.edge_faces);

  patch.side_slack.assign(nf, {1.0f, 1.0f, 1.0f});
  for (std::size_t t = 0; t < nf; ++t) {
    if (patch.triangles[t].degenerate) continue;
    const Vec3& n = patch.face_normals[t];
    std::array<double, 3> lowest{}; // smallest cosine to a normal around each corner
    for (int k = 0; k < 3; ++k) {
      const Index v = mesh.triangles[t][k];
      double c = 1.0;
      for (Index j = patch.vertex_face_offsets[v]; j < patch.vertex_face_offsets[v + 1]; ++j)
        if (!patch.triangles[patch.vertex_faces[j]].degenerate) c = std::min(c, n.dot(patch.face_normals[patch.vertex_faces[j]]));
      lowest[k] = c;
    }
    for (int k = 0; k < 3; ++k) {
      if (patch.border_edge[patch.edge_of[3 * t + k]]) continue;
      const double c = std::min(lowest[k], lowest[(k + 1) % 3]);
      patch.side_slack[t][k] = c <= 0.0 ? 1.0f : static_cast<float>(std::sqrt(std::max(0.0, 1.0 - c * c)));
    }
  }

  if (with_pseudo_normals) {
    patch.edge_normals.assign(edge_uses.size(), Vec3::Zero());
    patch.vertex_normals.assign(mesh.positions.size(), Vec3::Zero());
    for (std::size_t t = 0; t < nf; ++t) {
      const Vec3& n = patch.face_normals[t];
      if (patch.triangles[t].degenerate) continue;
      const Triangle& tri = mesh.triangles[t];
      for (int k = 0; k < 3; ++k) {
        patch.edge_normals[patch.edge_of[3 * t + k]] += n;
        const Vec3 e1 = (mesh.positions[tri[(k + 1) % 3]] - mesh.positions[tri[k]]).normalized();
        const Vec3 e2 = (mesh.positions[tri[(k + 2) % 3]] - mesh.positions[tri[k]]).normalized();
        const double angle = std::acos(std::clamp(e1.dot(e2), -1.0, 1.0));
        patch.vertex_normals[tri[k]] += angle * n;
      }
    }
    for (Vec3& n : patch.edge_normals) n = n.squaredNorm() > 0.0 ? Vec3(n.normalized()) : n;
    for (Vec3& n : patch.vertex_normals) n = n.squaredNorm() > 0.0 ? Vec3(n.normalized()) : n;
  }
  return patch;
}

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
  constexpr int pair_order[16][4] = {
      {}, {}, {}, {0, 1, 2, 3}, {}, {0, 2, 3, 1}, {1, 2, 0, 3}, {},
      {}, {0, 3, 1, 2}, {1, 3, 2, 0}, {}, {2, 3, 0, 1}, {}, {}, {}};
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

// ---- the distance band ----------------------------------------------------------------------------

struct BandParams {
  Vec3 origin = Vec3::Zero();
  double h = 1.0;
  double iso = 1.0;
  double limit = 1.0;       // nodes up to this distance spread
  double seed_radius = 1.0; // exact distances within this radius of each triangle
  double margin = 0.0;      // front_only: how far behind the border a node may lie and anchor
  bool front_only = true;
  double node_cap = 0.0;    // refuse to allocate more block nodes than this
  std::size_t expected_nodes = 0;
};

struct Contour {
  TriangleMesh mesh;
  std::vector<Index> border_candidates; // vertices on grid edges next to a cube left out
  std::vector<std::int32_t> source;     // per vertex, front_only: closest-feature code of the node
                                        // the vertex's grid edge starts from
};

class DistanceBand {
public:
  DistanceBand(const Patch& patch, const BandParams& params)
      : patch_(patch), p_(params), blocks_map_(expected_blocks(params)), scratch_(detail::thread_count()) {
    blocks_.reserve(expected_blocks(params));
  }

  /// Exact distances for the nodes within seed_radius of the patch.
  void seed();
  /// Closest-point propagation, one layer of 26-neighbours at a time, up to the limit.
  void grow();
  /// Marching tetrahedra on the contoured cubes.
  [[nodiscard]] Contour contour() const;
  [[nodiscard]] std::size_t computed_nodes() const { return computed_nodes_; }

private:
  static std::size_t expected_blocks(const BandParams& params) {
    return std::min<std::size_t>(params.expected_nodes / 256 + 64, std::size_t{1} << 18);
  }

  struct Evaluation {
    float dist;
    std::int32_t closest;
    bool spreads;
    bool anchors;
    std::uint32_t suspects; // neighbours (bit k: offset k) whose distance this node shows to be wrong
  };

  struct Closest {
    Nearest nearest;
    std::int32_t tri = -1;
  };

  /// Per-thread memory of evaluate_block(): a stamp per patch triangle marks the triangles already
  /// evaluated for the current node; the aprons hold the block's neighbourhood.
  struct Scratch {
    std::vector<std::uint32_t> stamp;
    std::uint32_t current = 0;
    std::array<std::int32_t, 1000> apron{};
    std::array<float, 1000> apron_dist{};
  };

  [[nodiscard]] Vec3 node_position(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return p_.origin + p_.h * Vec3(static_cast<double>(i - kIndexOffset), static_cast<double>(j - kIndexOffset),
                                   static_cast<double>(k - kIndexOffset));
  }
  [[nodiscard]] Vec3 node_position(std::int32_t b, int l) const {
    const Block& blk = blocks_[b];
    return node_position(8 * blk.coord[0] + (l & 7), 8 * blk.coord[1] + ((l >> 3) & 7),
                         8 * blk.coord[2] + (l >> 6));
  }
  /// The contoured value of a node: distances within kIsoValueMargin * h of T move to T + margin.
  [[nodiscard]] double field_value(float d) const {
    const double shift = tol::kIsoValueMargin * p_.h;
    return std::abs(d - p_.iso) < shift ? p_.iso + shift : static_cast<double>(d);
  }

  std::int32_t find_or_create_block(std::int64_t bx, std::int64_t by, std::int64_t bz);
  std::int32_t neighbour_or_create(std::int32_t b, int slot);
  [[nodiscard]] std::array<std::array<std::int64_t, 3>, 2> seed_range(std::size_t t) const;
  [[nodiscard]] bool block_may_hold_seeds(std::size_t t, const std::array<std::int64_t, 3>& block) const;
  void rasterize(std::size_t t, std::int32_t b);
  [[nodiscard]] bool spreads(const Nearest& nearest, std::int32_t t, double d) const;
  [[nodiscard]] bool anchors(const Nearest& nearest, std::int32_t t, double d) const;
  void spread_front(std::int32_t b, std::uint32_t layer, std::vector<std::int32_t>& touched);
  void deposit(std::int32_t target, const std::uint64_t* masks, int first, int count, std::uint32_t layer,
               std::vector<std::int32_t>& touched);
  void evaluate_block(std::int32_t b, const std::vector<std::uint32_t>& nodes, std::size_t begin,
                      std::size_t end, Scratch& scratch, std::vector<Evaluation>& out) const;
  void fill_apron(std::int32_t b, int y0, int y1, int z0, int z1, Scratch& scratch) const;
  [[nodiscard]] Closest closest_among(const Vec3& x, const std::int32_t* candidates, int count, Scratch& scratch) const;
  void repair(std::vector<std::uint32_t>& queue, std::uint32_t layer);

  const Patch& patch_;
  BandParams p_;
  std::vector<Block> blocks_;
  HashMap64 blocks_map_;
  std::vector<std::int32_t> front_blocks_;
  std::vector<Scratch> scratch_;
  std::size_t computed_nodes_ = 0;
};

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
  const TriangleGeometry& g = patch_.triangles[t];
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
  const TriangleGeometry& g = patch_.triangles[t];
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
  const TriangleGeometry& g = patch_.triangles[t];
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
  std::array<double, 3> slack{};        // how far outside edge k a node may be
  std::array<double, 3> column_slack{}; // the same for a column's point on the plane
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
        if (anchors(near, static_cast<std::int32_t>(t), d))
          blk.anchoring[l >> 6] |= bit;
        else
          blk.anchoring[l >> 6] &= ~bit;
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

void DistanceBand::deposit(std::int32_t target, const std::uint64_t* masks, int first, int count,
                           std::uint32_t layer, std::vector<std::int32_t>& touched) {
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
    const TriangleGeometry& g = patch_.triangles[t];
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
    if (anchors(best.nearest, best.tri, d))
      blk.anchoring[l >> 6] |= bit;
    else
      blk.anchoring[l >> 6] &= ~bit;
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
    std::array<SliceMasks, 7> crossed_edges; // [direction - 1]
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

// ---- after contouring ------------------------------------------------------------------------------

/// front_only: removes the connected components without a vertex in front of the patch. The edge of
/// the contoured region behind the rim is ragged at the scale of h and can cut small pieces off the
/// rim; the front sheet and everything joined to it stay. "In front" is judged with the closest
/// triangle of the node the vertex's grid edge starts from; once a component has one such vertex,
/// no other of its vertices is tested.
void remove_back_islands(Contour& contour, const Patch& patch) {
  TriangleMesh& mesh = contour.mesh;
  const std::size_t nv = mesh.positions.size();
  std::vector<Index> parent(nv);
  for (Index v = 0; v < nv; ++v) parent[v] = v;
  auto root = [&](Index v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (const Triangle& t : mesh.triangles) {
    const Index a = root(t[0]);
    const Index b = root(t[1]);
    const Index c = root(t[2]);
    parent[b] = a;
    parent[c] = a;
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
  std::vector<Index> parent;
  std::vector<std::pair<Index, Index>> copies; // (fan root, new vertex)
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    const Index v = candidates[i];
    const Index begin = offsets[i];
    const Index degree = offsets[i + 1] - begin;
    if (degree < 2) continue;
    parent.resize(degree);
    for (Index k = 0; k < degree; ++k) parent[k] = k;
    auto root = [&](Index k) {
      while (parent[k] != k) k = parent[k] = parent[parent[k]];
      return k;
    };
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
        const Index ra = root(a);
        const Index rb = root(b);
        if (ra != rb) {
          parent[ra] = rb;
          --groups;
        }
      }
    }
    if (groups == 1) continue;
    const Index keep = root(0);
    copies.clear();
    for (Index a = 0; a < degree; ++a) {
      const Index r = root(a);
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

// ---- sizing ---------------------------------------------------------------------------------------------

/// front_only: how far behind the border the rim is contoured, min(T/2, T - 2h) (shorter for
/// coarse cells, whose contour is rough anyway).
double front_margin(double distance, double h) { return std::max(0.0, std::min(0.5 * distance, distance - 2.0 * h)); }

/// Expected number of computed nodes: the slabs on both sides of the patch, the half-cylinder
/// around its border and a ball, all of radius "reach", capped by the grown bounding box.
double estimate_nodes(const Patch& patch, const BoundingBox& box, double distance, double h, bool front_only) {
  const double reach = distance + 4.0 * h;
  const double behind = front_only ? 3.0 * h : reach;
  const double pi = std::numbers::pi;
  const double volume = patch.area * (reach + behind) + patch.border_length * 0.5 * pi * reach * reach +
                        4.0 / 3.0 * pi * reach * reach * reach;
  const Vec3 size = box.size().array() + 2.0 * reach;
  return std::min(volume, size.prod()) / (h * h * h);
}

std::string format_budget_error(double h, double nodes, double budget) {
  char msg[240];
  std::snprintf(msg, sizeof msg,
                "offset: resolution h=%.4g mm needs about %.1f million cells, over the budget of %.1f "
                "million; use a coarser resolution",
                h, nodes * 1e-6, budget * 1e-6);
  return msg;
}

} // namespace

OffsetResult offset_surface(const TriangleMesh& surface, const OffsetOptions& options) {
  const double distance = options.distance;
  if (!std::isfinite(distance) || distance <= 0.0)
    throw InvalidInput("offset: the distance must be finite and > 0 mm, got " + detail::number(distance));
  if (!std::isfinite(options.cell_size) || options.cell_size < 0.0)
    throw InvalidInput("offset: the cell size must be finite and >= 0 mm (0 = automatic), got " +
                       detail::number(options.cell_size));
  if (options.cell_size > tol::kMaxCellSizePerOffset * distance)
    throw InvalidInput("offset: the cell size " + detail::mm(options.cell_size) + " is over half the distance " +
                       detail::mm(distance));
  if (std::isnan(options.max_cells) || options.max_cells <= 0.0)
    throw InvalidInput("offset: max_cells must be > 0");
  if (surface.empty()) throw InvalidInput("offset: the surface has no triangles");
  if (surface.triangles.size() >= (std::size_t{1} << 28))
    throw InvalidInput("offset: the surface has more than 2^28 triangles");
  check_mesh(surface, "offset");

  const Patch patch = build_patch(surface, options.front_only);
  const BoundingBox box = bounding_box(surface);

  double h = options.cell_size;
  if (h == 0.0) {
    h = std::min(distance / 8.0, std::max(distance / 16.0, 0.5 * mean_edge_length(surface)));
    while (estimate_nodes(patch, box, distance, h, options.front_only) > options.max_cells && h < 0.5 * distance)
      h = std::min(0.5 * distance, 1.1 * h);
  }
  const double expected = estimate_nodes(patch, box, distance, h, options.front_only);
  if (expected > options.max_cells) throw InvalidInput(format_budget_error(h, expected, options.max_cells));

  // Every node lies within "reach" of the patch; keep the stored indices inside [8, 2^20 - 8).
  const double reach = distance + 4.0 * h;
  const double span = (box.size().maxCoeff() + 2.0 * reach) / h + 16.0;
  if (!(span < static_cast<double>(kIndexOffset) - 16.0)) {
    char msg[200];
    std::snprintf(msg, sizeof msg,
                  "offset: the patch spans %.0f cells along one axis at h=%.4g mm, over the grid limit "
                  "of %lld; use a coarser resolution",
                  span, h, static_cast<long long>(kIndexOffset) - 16);
    throw InvalidInput(msg);
  }

  BandParams params;
  params.origin = box.min;
  params.h = h;
  params.iso = distance;
  params.limit = distance + 2.0 * h;
  params.seed_radius = 1.5 * h;
  params.margin = front_margin(distance, h);
  params.front_only = options.front_only;
  params.node_cap = 4.0 * options.max_cells;
  params.expected_nodes = static_cast<std::size_t>(expected);

  DistanceBand band(patch, params);
  band.seed();
  band.grow();

  OffsetResult result;
  Contour contour = band.contour();
  if (options.front_only) {
    remove_back_islands(contour, patch);
    split_pinched_vertices(contour.mesh, contour.border_candidates);
  }
  result.surface = std::move(contour.mesh);
  result.band_voxels = band.computed_nodes();
  result.cell_size = h;
  return result;
}

} // namespace st
