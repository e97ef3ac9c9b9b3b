#pragma once
// Mesh decimation by quadric-error edge collapses (Garland & Heckbert, "Surface simplification using
// quadric error metrics", SIGGRAPH 1997), for the fine, sliver-rich surfaces that marching tetrahedra
// produce: flat regions and sliver triangles cost almost nothing and go first.
//
// Edges are collapsed in order of increasing quadric cost (plus a small edge-length tie-break, so
// short edges of flat regions go first; the queue is a bucket queue with lazy deletion by vertex
// stamps, exact to a factor 2^(1/16) in the key) to the point minimising the summed squared distance
// to the planes of the input triangles merged so far (falling back to the best point on the edge when
// that point is ill-defined or farther from the edge midpoint than the edge is long). Sliver input
// triangles (quality below 0.05) enter the quadrics with a weight proportional to their quality: their
// planes are numerically arbitrary. Refused collapses are retried in up to 8 passes, while a pass
// still collapses more than 2% of the remaining faces. A collapse is refused when
//  - it would break 2-manifoldness: link condition (the end points share exactly the one or two
//    neighbours opposite the edge), no triangle folded onto another (a neighbour of valence 3), no
//    interior edge joining two border vertices, no ear triangle removed;
//  - it touches a fixed vertex: with keep_border, border vertices never move and are never removed
//    (an interior neighbour may still merge INTO a border vertex, which stays where it is); vertices
//    where the input is not a 2-manifold (non-manifold edges, several fans) are always fixed;
//  - a changed triangle would become (nearly) degenerate (quality below 1e-6), turn its normal by more
//    than max_normal_change_deg (checked for triangles of quality >= 0.05 before the collapse), or
//    face away from the original surface (normal against the summed input normals of its corners'
//    regions);
//  - the worst changed triangle would have quality 4*sqrt(3)*area / (sum of squared edge lengths)
//    below min_triangle_quality and be worse than the worst triangle of the neighbourhood before
//    (removed triangles included): so slivers are collapsed away even where every alternative
//    is still below the minimum;
//  - the edge is longer than target_edge_length, or a new edge would be longer than 1.5 times it;
//  - the deviation bound fails (see below).
//
// What is guaranteed about the deviation: every vertex of the output that is not an input vertex lies
// within max_error of the PLANE of every input triangle of quality >= 0.05 that was merged into it
// (each input triangle belongs to the regions of its corners; a collapse merges the two regions;
// sliver planes are left out, their corners are held by their neighbours' planes). The bound is checked
// exactly, plane by plane, unless the quadric already proves it (sqrt of the sum of squared plane
// distances >= the largest one). This is the classic Garland-Heckbert distance; it bounds the distance
// of output vertices to the input surface on smooth surfaces, and of input vertices to the output only
// approximately (plus the sagitta of an output triangle over a curved input, which the bound keeps of
// the same order as max_error). It is not a Hausdorff-distance certificate. Self-intersections are
// prevented only locally (no fold, no flip); distant parts of the surface are not tested against each
// other (for surfaces whose parts are much farther apart than max_error they cannot meet).
//
// Input: any TriangleMesh (#V by 3 positions, #F by 3 indices). Triangles with a repeated corner are
// dropped; zero-area triangles are removed by collapsing their short edge where the rules above allow
// (a collapse improving a degenerate triangle is accepted); the number left (only where every
// removal is blocked, e.g. three collinear border vertices) is reported.
// Throws InvalidInput for non-finite coordinates, out-of-range indices or invalid options.
// Cost: O(#F) expected (times the passes), single-threaded; memory about 150 bytes per input triangle.

#include "st/core/mesh.h"

#include <cstddef>
#include <vector>

namespace st {

struct DecimateOptions {
  /// Edges longer than this are not collapsed, and no collapse makes an edge longer than 1.5 times
  /// this (mm); 0: no length limit (decimate as far as the other criteria allow).
  double target_edge_length = 0.0;
  /// Largest distance (mm) of a moved vertex from the plane of any input triangle merged into it
  /// (see above). Must be >= 0.
  double max_error = 0.05;
  /// Border vertices never move and are never removed, so the border loops keep their vertices,
  /// positions (bit-identical) and order. When false, border edges may collapse too (their
  /// end points are held by quadrics of planes through the border edges, orthogonal to the surface).
  bool keep_border = true;
  /// Refuse collapses making a triangle's quality 4*sqrt(3)*area / (sum of squared edge lengths)
  /// (1 for equilateral, 0 for degenerate) lower than this, unless it was already lower. In [0, 1].
  double min_triangle_quality = 0.1;
  /// Refuse collapses that turn any changed triangle's normal by more than this (degrees), in (0, 180].
  double max_normal_change_deg = 30.0;
  /// Input vertices that must not be touched at all (neither moved nor merged into), by index;
  /// empty or one flag per input vertex.
  std::vector<char> frozen;
};

struct DecimateResult {
  TriangleMesh mesh; ///< only the used vertices, triangles in input orientation
  /// For each output vertex: the index of the input vertex it is, at a bit-identical position, or
  /// kInvalidIndex when it moved. With keep_border, every border vertex maps to its input vertex: the
  /// caller finds the rim of the input in the output this way.
  std::vector<Index> vertex_source;
  std::size_t collapses = 0;       ///< edge collapses performed
  std::size_t degenerate_left = 0; ///< zero-area triangles that could not be removed (see above)
};

/// Simplifies `mesh` by edge collapses as described above.
DecimateResult decimate(const TriangleMesh& mesh, const DecimateOptions& options = {});

} // namespace st
