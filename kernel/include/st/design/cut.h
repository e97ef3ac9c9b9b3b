#pragma once
// Cutting a region out of a surface along a closed surface curve (paper: "Segmentation with signed
// distance"), through the triangles.
//
// The paper gives every vertex a signed distance to the curve and clips at zero; its sign heuristic
// fails where the surface folds back near the curve. Here the sides are decided by topology instead:
// an edge is cut where the curve crosses it an odd number of times, at the exact crossing point (or,
// within the edge's cut margin of an end, at the end: the curve passes through that vertex, which
// becomes a rim vertex, and no sliver is made next to it, tolerances.h; rim vertices closer than
// tol::kMinCutDistance_mm to each other are merged, so the rim lies within twice that of the curve); the
// vertices on the left and on the right of every cut edge seed two floods across uncut manifold
// edges. The side that closes first (or the one holding the `inside` point) is the region. When the
// two floods meet, the curve does not separate the surface (it runs around a handle or through a
// hole) and the cut is refused. Work is proportional to the region, not to the whole mesh.
//
// With an `inside` point, a walk over the surface from its face towards the curve (each step across
// an edge to a face nearer the nearest cut face) finds its side first, and only that side is flooded:
// the same faces in the same order as when the two sides take turns, and a curve that does not
// separate is still refused (the flood reaches the other side's first faces). The other side is not
// flooded beyond them, so it no longer refuses, as the turns sometimes did, a region that the rest of
// the surface touches at a single vertex (a pinch of the mesh, away from the curve): the region is
// whole there. Where the walk stalls (a fold of the surface), the sides take turns as without it.

#include "st/core/mesh.h"
#include "st/design/surface_curve.h"
#include "st/core/topology.h"

#include <array>
#include <optional>
#include <vector>

namespace st {

struct CutOptions {
  /// A point on or near the surface inside the region to keep; without it the region with the
  /// smaller area is kept.
  std::optional<Vec3> inside;
  /// The face the inside point lies on, when the caller knows it (else it is searched among the
  /// curve's local faces).
  Index inside_face = kInvalidIndex;
  /// Refuse a region that contains an open border or non-manifold edge (a hole in the bone mesh).
  bool require_closed_region = true;
};

struct CutResult {
  TriangleMesh region;              ///< the kept part, triangles oriented as in the input
  std::vector<Index> rim;           ///< the region's border loop (region vertex indices), region on its left
  std::vector<Index> source_vertex; ///< per region vertex: the input vertex, or kInvalidIndex for a cut vertex
                                    ///< (a rim vertex the curve passes through is an input vertex)
  /// Where a cut vertex lies: (1 - t) * input[edge[0]] + t * input[edge[1]]. For input vertices the
  /// edge is (v, v) and t = 0.
  struct Source {
    std::array<Index, 2> edge{kInvalidIndex, kInvalidIndex};
    double t = 0.0;
  };
  std::vector<Source> source; ///< per region vertex
  double area = 0.0;          ///< area of the region, mm^2
};

/// Cuts `topology.mesh()` along `curve` (from trace_surface_curve on the same topology).
/// Throws GeometryError when the curve does not separate the surface, when the region contains an
/// open border (with require_closed_region), or when its border is not one simple loop; the message
/// says where. A border that shows the curve crosses or touches itself (a second loop on the curve,
/// a vertex it passes twice) is CurveCrossesItself, so that callers can retry with other samples.
CutResult cut_region(const MeshTopology& topology, const SurfaceCurve& curve, const CutOptions& options = {});

} // namespace st
