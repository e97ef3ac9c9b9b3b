#pragma once
// Union-find (disjoint sets) over the indices 0 .. n-1: connected components of vertices, pieces
// or fans. Path halving; join(a, b) puts a's set under b's root.

#include "st/core/mesh.h"

#include <cstddef>
#include <numeric>
#include <vector>

namespace st {

class UnionFind {
public:
  explicit UnionFind(std::size_t n = 0) { reset(n); }

  /// n singletons again (keeps the memory).
  void reset(std::size_t n) {
    parent_.resize(n);
    std::iota(parent_.begin(), parent_.end(), Index{0});
  }

  /// The root of i's set.
  Index find(Index i) {
    while (parent_[i] != i) i = parent_[i] = parent_[parent_[i]];
    return i;
  }

  /// Joins the sets of a and b under b's root; true when they were apart.
  bool join(Index a, Index b) {
    const Index ra = find(a);
    const Index rb = find(b);
    parent_[ra] = rb;
    return ra != rb;
  }

private:
  std::vector<Index> parent_;
};

} // namespace st
