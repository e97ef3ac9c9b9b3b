#pragma once
// The kernel's tolerances, in one place. Lengths are relative to a model scale (a mean edge length or
// a cell size) unless their name ends in _mm.

namespace st::tol {

/// A cut never lands closer than this fraction of an edge's length to its end points, so no sliver
/// triangle is made: a crossing closer than that to an end passes through the end instead (the cut
/// moves by at most this fraction of an edge).
inline constexpr double kEdgeCutMargin = 1e-3;

/// ... and never closer than this to them, mm: STL stores float32 (about 6e-5 mm apart at 1 m from
/// the origin), so points closer than this could merge in the file and leave zero-area triangles.
inline constexpr double kMinCutDistance_mm = 2e-3;

/// The margin of an edge of this length, as a fraction of it: the larger of the two above, at most
/// half the edge. A crossing within the margin of an end is a crossing through that end (the cut
/// passes through the vertex; see cut.h).
inline double edge_cut_margin(double edge_length) {
  const double fraction = edge_length > 0.0 ? kMinCutDistance_mm / edge_length : 0.5;
  return fraction < kEdgeCutMargin ? kEdgeCutMargin : (fraction > 0.5 ? 0.5 : fraction);
}

/// The offset's grid nodes lie this fraction of a cell below the patch's bounding box (offset.cpp).
inline constexpr double kGridOriginShift = 0.3819660112501051;

/// Relative step of the cut-curve samples, as a fraction of the mean edge length of the surface.
inline constexpr double kCurveSampleSpacing = 0.5;

/// Upper bound on the number of curve samples (a long loop on a fine mesh is sampled more coarsely).
inline constexpr int kMaxCurveSamples = 200000;

/// Grid values this close to the iso value (in cell sizes) are moved off it, so no contour vertex
/// comes closer to a grid node than about this fraction of a cell (no near-duplicate vertices).
inline constexpr double kIsoValueMargin = 1e-2;

/// Default largest distance of a control point from the surface before it is refused, mm.
inline constexpr double kMaxSnapDistance_mm = 5.0;

/// Largest cell size of the distance field as a fraction of the offset distance (the template's
/// thickness): a coarser grid cannot resolve the offset surface. The one limit of the resolution.
inline constexpr double kMaxCellSizePerOffset = 0.5;

/// Largest number of distance-field cells a design may use before it is refused (memory budget).
inline constexpr double kMaxFieldCells = 6.0e7;

/// Limits of a template's thickness and clearance, mm: beyond them a plan is a unit error.
inline constexpr double kMaxThickness_mm = 50.0;
inline constexpr double kMaxClearance_mm = 5.0;

/// Limits of a tube's sizes, mm: a sleeve 1 m wide or 10 m long (or offset, or drilled as deep) is
/// a unit error, not a plan.
inline constexpr double kMaxTubeRadius_mm = 1e3;
inline constexpr double kMaxTubeLength_mm = 1e4;

/// Largest mesh file read, bytes (2 GiB: a binary STL of about 43 million triangles). Larger files,
/// and anything that is not a regular file (a directory, a device such as /dev/zero, a FIFO), are
/// refused before reading.
inline constexpr unsigned long long kMaxMeshFileBytes = 2ull << 30;

/// Largest case, plan or catalogue file read, bytes (64 MiB).
inline constexpr unsigned long long kMaxTextFileBytes = 64ull << 20;

} // namespace st::tol
