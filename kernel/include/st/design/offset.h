#pragma once
// Offset surface of an open triangle patch (paper, "Offset surface generation"): the unsigned
// distance field of the inner surface is sampled in a narrow band on a sparse grid and contoured at
// the template thickness T.
//
// Method.
//  1. Grid nodes x = origin + h*(i, j, k) (origin = bounding-box minimum of the input less 0.38 h on
//     each axis, tol::kGridOriginShift; integer i, j, k) are stored sparsely, in 8x8x8 blocks found
//     through a hash map; only blocks the band touches exist, so memory grows with the band (about
//     area * 2(T + 4h) / h^3 nodes, 8 bytes each plus a little per block), not with the bounding box.
//  2. Seed: the exact point-triangle distance of every node within 1.5 h of the patch (each
//     triangle evaluates only the nodes whose closest point can lie on it).
//  3. Band growth, one layer of 26-neighbours at a time, while d <= T + 2h: a new node evaluates
//     exactly the closest triangles of its computed neighbours and keeps the nearest (closest-point
//     propagation); when that is a vertex or an edge, the triangles around it are evaluated too.
//     Layers of 26-neighbours reach some nodes first from the wrong part of the patch (where two
//     parts are about equally far); a node whose stored distance exceeds its distance to a
//     neighbour's closest point is evaluated again, and so on from it (see "Accuracy").
//  4. Contouring of the cubes whose 8 nodes were computed. Node values closer than
//     tol::kIsoValueMargin * h to T are moved to T + tol::kIsoValueMargin * h, so no contour vertex
//     sits on a node. Each crossed grid edge gives exactly one vertex, so the output is welded.
//     Marching cubes (default): each cube's contour is the set of polygons whose sides are its
//     segments on the cube's faces; a face with two corners below on a diagonal joins them or not as
//     the bilinear interpolant of its four values does (asymptotic decider), decided from the same
//     numbers by the two cubes sharing the face, so the contour is a welded 2-manifold. Polygons of
//     more than four sides are triangulated without new vertices, best worst triangle first. About
//     two triangles per crossed cube; not certified free of self-intersections (a skew polygon's
//     triangles can, rarely, meet another sheet in the same cube): the template's check decides and
//     falls back to tetrahedra.
//     Marching tetrahedra (`tetrahedra`): the Freudenthal (Kuhn) split of each cube into 6
//     tetrahedra along its main diagonal. The contour of a piecewise-linear field over a
//     triangulation is an embedded 2-manifold: no self-intersections and no edge used by more than
//     two triangles; about three times as many triangles as the cubes, some of them slivers.
//
// Accuracy. Node values are exact within 1.5 h of the patch; beyond, they are the distance to the
// nearest triangle found by propagation, an upper bound of the true distance that equals it except
// where a triangle's region of closest points is not entered through any neighbour (seen on CT bone
// meshes: up to about 0.1 h, at a few nodes). Contour vertices lie at distance T up to the linear
// interpolation error: O(h^2 / T) on rounded parts, zero on flat parts, and up to about h/2 (rarely
// more) at the concave creases of the offset, where the offsets of two parts of the patch meet.

#include "st/core/mesh.h"
#include "st/core/tolerances.h"

#include <cstddef>

namespace st {

struct OffsetOptions {
  /// Offset distance T (the template thickness), mm. Must be finite and > 0.
  double distance = 2.5;
  /// Grid spacing h, mm. 0 chooses min(T/8, max(T/16, 0.5 * mean edge length)) and makes it
  /// coarser, by steps of 10 % up to T/2, while the band would exceed `max_cells`. An explicit value
  /// must be finite and at most T/2.
  double cell_size = 0.0;
  /// true: only the sheet on the normal side of the patch (the side its counter-clockwise triangles
  /// face) and the rounded rim around the patch's border, down to min(T/2, T - 2h) behind the
  /// border (measured along the angle-weighted pseudo-normal of the closest vertex or edge, about
  /// 30 degrees below the border for the default h). The band does not grow behind the patch's
  /// interior, so no back sheet is made. The result is an open surface, a 2-manifold with border:
  /// its free border runs around the rim where the band stops (ragged at the scale of h), a vertex
  /// where two border fans touch is duplicated, and the small pieces the stopping band can cut off
  /// the rim (connected components without a vertex in front of the patch) are removed.
  /// false: the whole offset, both sides and the rim: a closed 2-manifold.
  bool front_only = true;
  /// false: marching cubes (fewer, better triangles); true: marching tetrahedra (certified free of
  /// self-intersections). See step 4 above.
  bool tetrahedra = false;
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

/// Offset of `surface`, an open, consistently oriented triangle patch (degenerate triangles are
/// allowed; where its normal side faces its back side within 2T, front_only may omit the sheet),
/// by `options.distance`. Runs on up to std::thread::hardware_concurrency() threads (at most 8).
/// Throws InvalidInput when the distance, cell size or max_cells is not finite or out of range, when
/// the mesh is empty, has non-finite coordinates, bad indices or 2^28 triangles or more, when the
/// band would need more than `options.max_cells` nodes at the requested cell size (estimated before
/// allocating; the band is also stopped at 4 * max_cells nodes), or when the patch spans more than
/// about 2^19 cells along an axis.
OffsetResult offset_surface(const TriangleMesh& surface, const OffsetOptions& options = {});

} // namespace st
