#pragma once
// The distance band's sparse grid (private to offset_surface, st/design/offset.h): 8x8x8 blocks of
// nodes found by an open-addressing hash map, slices as 64-bit masks.

#include "st/core/mesh.h"

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
inline std::int64_t floor_int(double x) {
  const auto i = static_cast<std::int64_t>(x);
  return i - (x < static_cast<double>(i) ? 1 : 0);
}
inline std::int64_t ceil_int(double x) {
  const auto i = static_cast<std::int64_t>(x);
  return i + (x > static_cast<double>(i) ? 1 : 0);
}

struct Block {
  std::array<float, kBlockNodes> dist;           // unsigned distance, mm (valid where computed)
  std::array<std::int32_t, kBlockNodes> closest; // 8 * triangle + Feature, -1 where not computed
  SliceMasks computed;
  SliceMasks pending;                      // candidates of the layer being built
  SliceMasks front;                        // nodes that spread in the next layer
  SliceMasks spreading;                    // nodes that spread (all layers)
  SliceMasks anchoring;                    // nodes whose cubes are contoured (see contour())
  SliceMasks queued;                       // nodes waiting for repair
  std::array<std::int32_t, 27> neighbours; // block indices, -1 where absent
  std::array<std::int64_t, 3> coord;       // block coordinates (stored index >> 3)
  std::uint32_t pending_stamp;             // layer in which the block was listed for candidates
  std::uint32_t front_stamp;               // layer in which the block was listed for the front
};

inline std::uint64_t block_key(std::int64_t bx, std::int64_t by, std::int64_t bz) {
  return (static_cast<std::uint64_t>(bx) << 34) | (static_cast<std::uint64_t>(by) << 17) |
         static_cast<std::uint64_t>(bz);
}

/// Value of `m` (the slice masks of one block and of its neighbours at +x, +y, +x+y, same slice)
/// seen one node further along x and/or y: bit (x, y) of the result is bit (x + sx, y + sy).
inline std::uint64_t shift_x(std::uint64_t m, std::uint64_t next_x) {
  return ((m >> 1) & ~kColumn7) | ((next_x & kColumn0) << 7);
}
inline std::uint64_t shift_y(std::uint64_t m, std::uint64_t next_y) { return (m >> 8) | (next_y << 56); }

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

} // namespace st::offset_detail
