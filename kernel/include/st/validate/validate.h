#pragma once
// Checks that a mesh is a printable solid, and that a template fits its bone. Used by the design
// pipeline, the command-line tool and the tests alike.

#include "st/core/mesh.h"

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace st {

struct SolidReport {
  std::size_t vertices = 0;
  std::size_t triangles = 0;
  std::size_t border_edges = 0;         ///< half-edges with no partner (0 for a closed mesh)
  std::size_t nonmanifold_edges = 0;    ///< edges used by more than two triangles
  std::size_t misoriented_edges = 0;    ///< edges whose two triangles run the same way
  std::size_t nonmanifold_vertices = 0; ///< vertices whose triangles form more than one fan
  std::size_t degenerate_triangles = 0; ///< zero area or repeated corners
  std::size_t self_intersections = 0;   ///< intersecting triangle pairs (counting stops at max_reported)
  std::size_t components = 0;
  double area = 0.0;                ///< mm^2
  double volume = 0.0;              ///< signed, mm^3
  std::vector<Vec3> problem_points; ///< a few places where something is wrong

  [[nodiscard]] bool closed() const { return border_edges == 0; }
  [[nodiscard]] bool manifold() const { return nonmanifold_edges == 0 && nonmanifold_vertices == 0; }
  [[nodiscard]] bool oriented() const { return misoriented_edges == 0 && volume > 0.0; }
  /// Closed, 2-manifold, outward oriented, no degenerate triangle, no self-intersection.
  [[nodiscard]] bool valid() const {
    return closed() && manifold() && oriented() && degenerate_triangles == 0 && self_intersections == 0;
  }
  [[nodiscard]] std::string summary() const;
};

class AabbTree;

struct SolidOptions {
  bool check_self_intersections = true;
  std::size_t max_reported = 100; ///< stop counting self-intersections here
  const AabbTree* tree = nullptr; ///< a tree over all of the mesh's faces when the caller has one
  /// Or, when `tree` is null, where to get one: asked once the topology is checked, when the
  /// self-intersection check starts (for a caller building the tree beside the check).
  std::function<const AabbTree&()> tree_source;
};

/// Topology, orientation and self-intersection check of a triangle mesh as a solid. Self-intersections
/// are decided exactly for every pair of faces whose boxes overlap, but for three kinds of pair proven
/// unable to cross and passed over: faces around a corner whose fan is a height field over an axis
/// plane, faces within a patch (a node of the faces' tree) that projects one to one onto an axis
/// plane (all its faces turn one way and its border is one loop projecting to a simple polygon), and
/// faces without a common corner one of which lies strictly on one side of the other's plane
/// (AabbTree::overlapping_pairs, with a margin far wider than the rounding). The count is that of
/// testing every pair.
SolidReport check_solid(const TriangleMesh& mesh, const SolidOptions& options = {});

/// Distance statistics of points to a surface (exact closest-point distances), mm.
struct DistanceStats {
  double min = 0.0, max = 0.0, mean = 0.0;
  std::size_t count = 0;
};
/// `near_vertex[i]`, when given, names a vertex of `surface` near points[i] (the one it was moved
/// from, say; kInvalidIndex for none): its distance bounds the search from above, and a point on it
/// lies at 0 without a search. Any vertex keeps the result the same; a near one makes it cheaper.
/// `tree`, one over all of surface's faces when the caller has one (built here when null). Throws
/// InvalidInput for a point that is not finite, naming it, or a tree over another mesh.
DistanceStats distances_to_surface(const std::vector<Vec3>& points, const TriangleMesh& surface,
                                   const std::vector<Index>& near_vertex = {}, const AabbTree* tree = nullptr);

/// Distance statistics of points to the closed polyline `poly` (segments from each of its points to
/// the next, the last to the first): each point's distance to its nearest segment, summed in the
/// points' order. The segments are read near each point only (a grid of cells as long as the longest
/// segment, ring by ring until the next ring lies farther than the nearest found; all of them for a
/// point farther than four rings): the same result as over all segments. Empty `poly`: every
/// distance infinite.
DistanceStats distances_to_polyline(const std::vector<Vec3>& points, const std::vector<Vec3>& poly);

} // namespace st
