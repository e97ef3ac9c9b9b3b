#pragma once
// Morton (Z-order) codes of points on a grid of 2^21 cells a side: sorted by them, points near each
// other in space are mostly near each other in order (the AABB tree's triangles, the fit's points),
// and the sort that puts items in that order (a stable radix sort of any 64-bit keys: the Boolean's
// edge keys too).

#include "st/core/mesh.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

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

/// An item (its index) and its Morton code (or another 64-bit key).
struct MortonKeyed {
  std::uint64_t code;
  std::size_t item;
};

/// Sorts by code, keeping the order of equal codes (items in their input order: the order is the
/// same on any machine): least significant digit first, 11 bits a pass, digits every code shares
/// skipped.
inline void sort_by_code(std::vector<MortonKeyed>& keyed) {
  if (keyed.empty()) return;
  std::vector<MortonKeyed> other(keyed.size());
  constexpr int kBits = 11;
  constexpr std::size_t kBuckets = std::size_t{1} << kBits;
  std::uint64_t spread = 0;
  for (const MortonKeyed& k : keyed) spread |= k.code ^ keyed.front().code;
  for (int shift = 0; shift < 64; shift += kBits) {
    if (((spread >> shift) & (kBuckets - 1)) == 0) continue; // every code has the same digit here
    std::array<std::size_t, kBuckets + 1> start{};
    for (const MortonKeyed& k : keyed) ++start[((k.code >> shift) & (kBuckets - 1)) + 1];
    for (std::size_t b = 0; b < kBuckets; ++b) start[b + 1] += start[b];
    for (const MortonKeyed& k : keyed) other[start[(k.code >> shift) & (kBuckets - 1)]++] = k;
    keyed.swap(other);
  }
}

} // namespace st::detail
