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

struct FaceSplitInput {
  std::array<Vec3, 3> corners;
  std::array<Index, 3> corner_ids{};
  std::vector<FacePoint> points;                 ///< distinct ids, none equal to a corner id
  std::vector<std::pair<Index, Index>> segments; ///< constraints between point (or corner) ids
};

/// Triangles (caller's ids) covering the face, oriented as (corner 0, corner 1, corner 2). Throws
/// GeometryError when the points cannot be placed consistently (a point outside the face, segments
/// that cross), which callers treat as a degenerate configuration.
std::vector<Triangle> split_face(const FaceSplitInput& input);

} // namespace st
