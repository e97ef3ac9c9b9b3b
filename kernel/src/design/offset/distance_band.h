#pragma once
// The narrow band of distances around the patch (private to offset_surface, st/design/offset.h):
// exact distances near the patch, closest-point propagation outwards, marching cubes or tetrahedra
// on the contoured cubes (contouring.cpp), and the clean-up of the contour (contour_repair.cpp).

#include "design/offset/patch.h"
#include "design/offset/sparse_grid.h"
#include "detail/parallel.h"
#include "st/core/tolerances.h"

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

// ---- the distance band ----------------------------------------------------------------------------

struct BandParams {
  Vec3 origin = Vec3::Zero();
  double h = 1.0;
  double iso = 1.0;
  double limit = 1.0;       // nodes up to this distance spread and anchor
  double seed_radius = 1.0; // exact distances within this radius of each triangle
  double margin = 0.0;      // front_only: how far behind the border a node may lie and anchor
  bool front_only = true;
  bool tetrahedra = false; // marching tetrahedra instead of cubes
  double node_cap = 0.0;   // refuse to allocate more block nodes than this
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
  /// Marching cubes (or tetrahedra) on the contoured cubes.
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
    return node_position(8 * blk.coord[0] + (l & 7), 8 * blk.coord[1] + ((l >> 3) & 7), 8 * blk.coord[2] + (l >> 6));
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
  void evaluate_block(std::int32_t b, const std::vector<std::uint32_t>& nodes, std::size_t begin, std::size_t end,
                      Scratch& scratch, std::vector<Evaluation>& out) const;
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

/// front_only: removes the connected components without a vertex in front of the patch.
void remove_back_islands(Contour& contour, const Patch& patch);
/// Gives each extra fan around a pinched candidate vertex its own copy of the vertex.
void split_pinched_vertices(TriangleMesh& mesh, const std::vector<Index>& candidates);

} // namespace st::offset_detail
