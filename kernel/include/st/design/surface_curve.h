#pragma once
// The closed boundary curve on the bone surface (paper: "Points for segmentation", "Edge loop
// generation").
//
// The user's sparse control points are snapped onto the surface, a closed centripetal Catmull-Rom
// (cardinal) spline is laid through them and sampled densely, and every sample is brought onto the
// surface by a closest-point query. Unlike the paper, which re-projected samples through the z-buffer
// of the current view, this needs no view and works headless.
//
// Consecutive samples are then joined ON the surface by walking across triangles in the plane through
// both samples that contains the mean surface normal there. The result is the exact sequence of mesh
// edges the curve crosses, with the crossing position on each: the cut (cut.h) follows it through the
// triangles, so the template rim is smooth and does not zig-zag along mesh edges.
//
// Only the triangles near the control points are indexed, and only the connected part of the mesh the
// points lie on is followed: far-away geometry and other components (CT noise islands, the head
// rest) neither slow it down nor capture the curve.

#include "st/core/mesh.h"
#include "st/core/tolerances.h"
#include "st/core/topology.h"

#include <optional>
#include <string>
#include <vector>

namespace st {

struct CurveOptions {
  /// A control point farther than this from the surface is refused (InvalidInput), mm.
  double max_snap_distance = tol::kMaxSnapDistance_mm;
  /// Spacing of the spline samples, mm; 0 picks half the mean edge length of the surface there.
  double sample_spacing = 0.0;
  /// Optional extra point (e.g. the "inside" point) whose neighbourhood must be indexed too.
  std::optional<Vec3> also_index;
  /// Refuse a curve that crosses itself (CurveCrossesItself, a GeometryError).
  bool check_self_crossing = true;
  /// What the curve is, for messages ("boundary", "outer cut").
  std::string name = "boundary";
};

/// The curve leaves face `halfedge / 3` through that half-edge, at from + t * (to - from).
/// Within the edge's cut margin of an end (tolerances.h), the curve passes through that end instead:
/// `through` is that vertex, t stays at the margin.
struct EdgeCrossing {
  Index halfedge = kInvalidIndex;
  double t = 0.5;
  Index through = kInvalidIndex;
};

struct SurfaceCurve {
  std::vector<Vec3> control_points; ///< the user's points snapped onto the surface
  std::vector<Index> control_faces; ///< the face each snapped point lies on
  std::vector<Vec3> samples;        ///< dense spline samples on the surface
  std::vector<Index> sample_faces;
  std::vector<EdgeCrossing> crossings; ///< mesh edges crossed, in order along the closed curve
  std::vector<Vec3> polyline;          ///< the curve on the surface: samples and crossings in order
  std::vector<Index> local_faces;      ///< the connected faces near the curve that were indexed
  double length = 0.0;                 ///< length of `polyline`, mm
};

/// Computes the closed surface curve through `control_points` (in order; the loop closes from the
/// last to the first point).
/// Throws InvalidInput for fewer than 3 points, non-finite coordinates, repeated consecutive points,
/// or a point farther than max_snap_distance from the surface (naming the point).
/// Throws GeometryError when the points do not lie on one connected part of the mesh, when the
/// curve runs into an open border or a non-manifold edge (naming where), when it crosses itself, or
/// when the surface cannot be followed between two samples (a gap or fold).
SurfaceCurve trace_surface_curve(const MeshTopology& topology, const std::vector<Vec3>& control_points,
                                 const CurveOptions& options = {});

/// The closed curve joining points that already lie on the surface, each on the given face, by
/// straight walks over the surface: no snapping, no spline, no index (for the outer cut, whose points
/// are ray hits). local_faces stays empty. Throws as trace_surface_curve for the walks.
SurfaceCurve join_surface_points(const MeshTopology& topology, const std::vector<Vec3>& points,
                                 const std::vector<Index>& faces, const CurveOptions& options = {});

/// Closed centripetal Catmull-Rom spline through `points`, sampled so that consecutive samples are
/// about `spacing` apart (at least one sample per control point, starting with points[0]).
std::vector<Vec3> closed_catmull_rom(const std::vector<Vec3>& points, double spacing);

} // namespace st
