#pragma once
// A set of cells of a uniform grid: the cells around some points, asked whether another point's cell
// is among them. Used to find what lies near a few places without a tree (the faces near the rim, the
// faces near hidden samples).

#include "st/core/mesh.h"

#include <cmath>
#include <cstdint>
#include <unordered_set>

namespace st::detail {

class CellSet {
public:
  /// Cells of side `cell` mm (> 0).
  explicit CellSet(double cell) : cell_(cell) {}

  /// Marks p's cell and its 26 neighbours.
  void mark_around(const Vec3& p) {
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) cells_.insert(key(p, dx, dy, dz));
  }

  /// Whether p's cell is marked.
  bool contains(const Vec3& p) const { return cells_.count(key(p, 0, 0, 0)) != 0; }

private:
  // 21 bits per axis (the grid wraps every 2^21 cells, far beyond any mesh at these cell sizes).
  std::uint64_t key(const Vec3& p, int dx, int dy, int dz) const {
    const auto c = [this](double x, int o) {
      return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(x / cell_)) + o) & 0x1fffff;
    };
    return c(p.x(), dx) << 42 | c(p.y(), dy) << 21 | c(p.z(), dz);
  }

  double cell_;
  std::unordered_set<std::uint64_t> cells_;
};

} // namespace st::detail
