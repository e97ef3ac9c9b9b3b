#pragma once
// The ruled wall joining two closed border loops (paper: "Ruled surface", eq. 2-3).
//
// Triangles are either (P_i, P_i+1, Q_k) or (P_i, Q_k+1, Q_k): each contour segment is used by
// exactly one triangle and spans never cross, so the wall has m + n triangles for loops of m and n
// points. Among all such strips the one with the least total span length is found as a shortest path
// in the (m+1) x (n+1) grid graph by dynamic programming (the paper's label-setting algorithm).
// For closed loops the starting correspondence matters: several starting spans near the best-matching
// pair are tried and the cheapest strip is kept.
//
// Orientation: with P and Q running the same way round (e.g. both counter-clockwise seen from the
// outer side), the triangles use P_i -> P_i+1 and Q_k+1 -> Q_k, which closes a shell made of a
// surface bordered by P reversed (the template's inner surface) and a surface bordered by Q (the
// outer surface).

#include "st/core/mesh.h"

#include <vector>

namespace st {

struct RuledOptions {
  /// Number of starting spans tried for closed loops (around the closest pair).
  int start_candidates = 5;
  /// Refuse loops whose grid would exceed this many cells (memory), in millions.
  double max_cells_millions = 400.0;
};

struct RuledResult {
  std::vector<Triangle> triangles; ///< indices: P_i -> p_offset + i, Q_j -> q_offset + j
  double span_length = 0.0;        ///< total span length of the strip, mm
};

/// Wall between closed loops P (m >= 2 points) and Q (n >= 2 points). Throws InvalidInput for loops
/// that are too short or too large.
RuledResult ruled_surface(const std::vector<Vec3>& p, const std::vector<Vec3>& q, Index p_offset, Index q_offset,
                          const RuledOptions& options = {});

} // namespace st
