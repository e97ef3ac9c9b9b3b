#pragma once
// Splitting one triangle along the intersection segments that cross it (the corefinement step of the
// Boolean operations): a constrained triangulation of the face with its corners, the points on its
// edges, the points inside it, and the segments between them as constraints.
//
// Combinatorics come from the caller (which edge a point lies on and where along it; which points
// are joined), so points on an edge are put on that edge even where rounding moved them by an ulp;
// every geometric decision inside the face is an exact orientation test on the face's own 2D frame.
// The result triangulates the face exactly once, keeps every segment as an edge, never makes a
// triangle of three points on one original edge, and is Delaunay where no constraint forbids it.

#include "st/core/mesh.h"

#include <array>
#include <utility>
#include <vector>

namespace st {

struct FacePoint {
  Index id = kInvalidIndex; ///< the caller's vertex id
  int edge = -1;            ///< 0, 1, 2: on the edge from corner k to corner k+1; -1: inside the face
  double t = 0.0;           ///< on an edge: parameter in (0, 1) from corner `edge` to the next corner
  Vec3 position = Vec3::Zero();
};

/// A corner of the face cut off by the curve closer to it than the coordinates resolve: the curve
/// crosses the face from its edge leaving the corner to its edge arriving at it, and both crossings
/// round to one point. That point replaces the corner: the face keeps the part beyond it, and its
/// neighbours across the two edges, each split at the point, meet along the line from the corner to it.
struct CutCorner {
  int corner = -1;          ///< 0, 1, 2; -1: none
  Index id = kInvalidIndex; ///< the point (one of `points`)
  double t_leaving = 0.0;   ///< where it lies on the edge from the corner to the next one
  double t_arriving = 1.0;  ///< and on the edge from the previous corner to it
};

struct FaceSplitInput {
  std::array<Vec3, 3> corners;
  std::array<Index, 3> corner_ids{};
  std::vector<FacePoint> points;                 ///< distinct ids, none equal to a corner id
  std::vector<std::pair<Index, Index>> segments; ///< constraints between point (or corner) ids
  CutCorner cut;                                 ///< a corner the curve cuts off, if any
};

/// Triangles (caller's ids) covering the face (less its cut corner), oriented as (corner 0, corner 1,
/// corner 2). Throws GeometryError when the points cannot be placed consistently (a point outside the
/// face, segments that cross, a point on an edge inside the cut corner), which callers treat as a
/// degenerate configuration.
std::vector<Triangle> split_face(const FaceSplitInput& input);

} // namespace st
