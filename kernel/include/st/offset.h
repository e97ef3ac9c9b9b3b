#pragma once
// Offset surface of an open triangle patch (paper, "Offset surface generation"): the unsigned
// distance field of the inner surface is sampled in a narrow band on a sparse grid and contoured at
// the template thickness.
//
// Method.
//  1. Grid nodes x = origin + h*(i, j, k) (origin = bounding-box minimum of the input, integer
//     i, j, k) are stored sparsely, in 8x8x8 blocks found through a hash map; only blocks the band
//     touches exist, so memory grows with the band (about area * 2(T + 4h) / h^3 nodes), not with
//     the bounding box.
//  2. Seed: exact point-triangle distances for every node within 1.5 h of a triangle.
//  3. Band growth, one layer of 26-neighbours at a time: a new node evaluates exactly the closest
//     triangles of its already computed neighbours and keeps the nearest (closest-point
//     propagation). Nodes with d <= T + 2h spread further.
//  4. Marching tetrahedra on the Freudenthal (Kuhn) split of each grid cube into 6 tetrahedra along
//     its main diagonal; only cubes whose 8 nodes were computed are contoured. The contour of a
//     piecewise-linear field over a triangulation is an embedded 2-manifold: no self-intersections
//     and no edge used by more than two triangles. Node values closer than tol::kIsoValueMargin * h
//     to T are moved to T + tol::kIsoValueMargin * h, so no contour vertex sits on a node. Each
//     crossed grid edge gives exactly one vertex, so the output is welded.
//
// Accuracy. The field is exact within 1.5 h of the patch and where a node's closest triangle is the
// closest triangle of one of its neighbours, which is the case everywhere except, rarely, near the
// medial axis of the patch (where two distant parts of the patch are equally close); there the
// value is an upper bound. Contour vertices lie at distance T from the patch up to the linear
// interpolation error (O(h^2 / T) on rounded parts, zero on flat parts). The mesh has many small
// and some sliver triangles (a few per grid cube), as marching tetrahedra always gives.

#include "st/mesh.h"
#include "st/tolerances.h"

#include <cstddef>

namespace st {

struct OffsetOptions {
  /// Offset distance T (the template thickness), mm. Must be finite and > 0.
  double distance = 2.5;
  /// Grid spacing h, mm. 0 chooses min(T/8, max(T/16, 0.5 * mean edge length)), made coarser
  /// (by steps of 10 %) when the band would exceed `max_cells`. An explicit value must be finite,
  /// >= 0 and at most T/2.
  double cell_size = 0.0;
  /// true: only the sheet on the normal side of the patch (the side counter-clockwise triangles face)
  /// and the rounded part around the patch's border. The band does not grow past nodes lying behind
  /// the patch by more than min(T/2, T - 2h) (measured along the angle-weighted pseudo-normal of the
  /// closest point's vertex, edge or face), so no back sheet is made. The result is then an open
  /// surface whose free border runs around the rounded rim, roughly 30 degrees below the patch's
  /// border; where two border fans of that rim meet in one point the vertex is duplicated, so the
  /// result is a 2-manifold with border.
  /// false: the whole offset, both sides and the rim: a closed 2-manifold.
  bool front_only = true;
  /// Refuse (InvalidInput, before allocating) when the estimated number of band nodes exceeds this.
  double max_cells = tol::kMaxFieldCells;
};

struct OffsetResult {
  /// The contour {d = T}: #V by 3 positions, #F by 3 triangles, welded, oriented so that triangle
  /// normals point toward increasing distance (away from the input patch).
  TriangleMesh surface;
  /// Number of grid nodes where the distance was computed.
  std::size_t band_voxels = 0;
  /// The grid spacing h used, mm.
  double cell_size = 0.0;
};

/// Offset of `surface` (an open, consistently oriented triangle patch; degenerate triangles are
/// allowed) by `options.distance`. Runs on up to std::thread::hardware_concurrency() threads.
/// Throws InvalidInput when the distance or cell size is not finite or out of range, when the mesh
/// is empty or has non-finite coordinates or bad indices, or when the band would need more than
/// `options.max_cells` nodes at the explicitly requested cell size (or more than 2^19 cells along
/// one axis).
OffsetResult offset_surface(const TriangleMesh& surface, const OffsetOptions& options = {});

} // namespace st
