#pragma once
// Boolean operations on closed triangle meshes by corefinement (paper: "Collision detection and
// merging"; done exactly along the intersection curve instead of the paper's ruled strips):
//   1. candidate face pairs from bounding-box trees over the faces near the other mesh only;
//   2. each pair decided with exact orientation predicates; a crossing pair gives one intersection
//      segment whose ends are edge-face crossings, each computed once and shared by every face that
//      holds it, so both meshes are split at identical points;
//   3. every crossed face is split along its segments (a constrained triangulation, face_split.h);
//   4. the pieces between intersection curves are classified inside/outside the other mesh by the
//      exact side test at the curve (no ray casting near the surface), pieces the curves do not reach
//      by connection to faces far away or by a ray;
//   5. the kept pieces are stitched: the intersection curves are shared edges, so the result is
//      closed and 2-manifold wherever the operands are.
// Touching and coplanar configurations (a vertex on a face, an edge on an edge, coplanar faces) are
// detected exactly; the second operand is then moved by a tiny, deterministic offset (10 ulp of the
// coordinates) and the operation repeated, which is reported in the result.

#include "st/core/mesh.h"

#include <cstdint>
#include <string>
#include <vector>

namespace st {

enum class BooleanOp { Union, Difference, Intersection };

struct BooleanOptions {
  /// Faces of the first operand that rest on something the result must not enter (the template's
  /// inner surface, on the bone). Union only: pieces of the second operand beyond these faces are
  /// dropped and these faces kept inside it, i.e. the result is (A u B) minus the far side of the
  /// seat. Empty: no seat.
  std::vector<std::uint8_t> seat;
  /// Check that both operands are closed, 2-manifold and oriented (a half-edge pass each).
  bool check_operands = true;
  /// Round the result's coordinates to float32 (what an STL holds) and retry with a perturbation if
  /// that would fold a triangle near the intersection curve.
  bool round_to_float = true;
  /// After rounding, check exactly that the faces made or moved near the intersection curve close up
  /// and cross no face around them, and retry with a perturbation when they do not. A caller that
  /// checks the whole result (check_solid, which tests every pair of faces) may leave it to that check
  /// and, when the result fails it, do the operation again with this on.
  bool check_result = true;
  int max_attempts = 6;
};

struct BooleanResult {
  TriangleMesh mesh;
  std::vector<std::uint8_t> from_b; ///< per result face: 1 when it comes from the second operand
  std::vector<Index> source_face;   ///< per result face: the operand's face it is (part of)
  std::size_t intersecting_pairs = 0;
  std::size_t curve_segments = 0; ///< edges along the intersection curves
  std::size_t split_faces = 0;
  std::size_t collapsed_edges = 0; ///< curve edges under 256 float ulp collapsed (see boolean.cpp)
  double curve_tolerance = 0.0;    ///< that length, mm: how far a collapse may move the curve
  int attempts = 1;                ///< > 1 when a degenerate contact needed a perturbation
  double perturbation = 0.0;       ///< size of the offset applied to the second operand, mm
  double seconds = 0.0;
};

/// A op B for closed, 2-manifold, outward-oriented meshes A and B. Throws InvalidInput when an operand
/// is empty, non-finite, open or non-manifold (naming it and where), GeometryError when no attempt gives
/// a consistent result.
BooleanResult mesh_boolean(const TriangleMesh& a, const TriangleMesh& b, BooleanOp op,
                           const BooleanOptions& options = {});

/// Which operand and why, for messages: "first operand (template): 3 open edges near (x, y, z)".
void check_closed_manifold(const TriangleMesh& mesh, const std::string& what);

} // namespace st
