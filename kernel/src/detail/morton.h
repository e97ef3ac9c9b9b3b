#pragma once
// Morton (Z-order) codes of points on a grid of 2^21 cells a side: sorted by them, points near each
// other in space are mostly near each other in order (the AABB tree's triangles, the fit's points).

#include "st/core/mesh.h"

#include <cstdint>

namespace st::detail {

/// The low 21 bits of v, spread to every third bit.
inline std::uint64_t spread_bits(std::uint64_t v) {
  v &= 0x1fffffULL;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

/// Cells a side of the grid.
constexpr double kMortonCells = double((1 << 21) - 1);

/// The Morton code of p's cell, `scale` cells per mm from `origin` (a coordinate below, above the grid
/// or not a number: cell 0).
inline std::uint64_t morton_code(const Vec3& p, const Vec3& origin, double scale) {
  std::uint64_t code = 0;
  for (int k = 0; k < 3; ++k) {
    const double q = (p[k] - origin[k]) * scale;
    const auto cell = static_cast<std::uint64_t>(q >= 0.0 && q <= kMortonCells ? q : 0.0);
    code |= spread_bits(cell) << (2 - k);
  }
  return code;
}

} // namespace st::detail
