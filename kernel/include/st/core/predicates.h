#pragma once
// Exact orientation predicates (Shewchuk, "Adaptive precision floating-point arithmetic and fast
// robust geometric predicates", 1997): a floating-point filter with a static error bound answers almost
// every call in a few nanoseconds; the rare undecided calls are evaluated exactly with floating-point
// expansions (and, for inputs whose magnitudes span more than about 600 binary orders, with big
// integers), so the returned sign is the sign of the exact determinant for every finite double input,
// including subnormal and huge coordinates.
//
// Requirements on the build: IEEE double arithmetic in round-to-nearest mode, no -ffast-math, double
// evaluation in double precision (FLT_EVAL_METHOD == 0, i.e. SSE2 on x86, not the x87 unit). The
// source refuses to compile otherwise. Non-finite input (NaN, infinity) gives an unspecified sign.

#include "st/core/mesh.h"

namespace st {

/// Sign of the 2D orientation determinant
///     | ax - cx   ay - cy |
///     | bx - cx   by - cy |
/// for the points a, b, c, each given as two doubles (x, y): +1 when a, b, c make a left turn
/// (counter-clockwise), -1 for a right turn (clockwise), 0 when they are exactly collinear
/// (including repeated points). Exact for all finite input.
int orient2d(const double* a, const double* b, const double* c);

/// Sign of the 3D orientation determinant
///     | ax - dx   ay - dy   az - dz |
///     | bx - dx   by - dy   bz - dz |
///     | cx - dx   cy - dy   cz - dz |
/// Shewchuk's convention: +1 when d lies BELOW the plane through a, b, c, where "below" is the side
/// opposite to the normal (b - a) x (c - a), i.e. seen from d the points a, b, c appear clockwise;
/// -1 when d lies above (a, b, c counter-clockwise seen from d); 0 when the four points are exactly
/// coplanar (also when a, b, c are collinear or points repeat). Equivalently the sign of
/// -((b - a) x (c - a)) . (d - a). Example: orient3d((0,0,0), (1,0,0), (0,1,0), (0,0,-1)) == +1.
/// Exact for all finite input.
int orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// orient3d(a, b, c, d) for many points d against one plane (a, b, c): the plane's differences and
/// 2x2 minors are computed once, so the floating-point filter costs a point three differences and two
/// dot products. Its error bound is orient3d's (the same determinant, expanded along d's row instead
/// of a column: the same products of single-rounded differences); what it cannot decide goes to
/// orient3d itself. The sign is orient3d's for every finite input.
class PlaneOrientation {
public:
  PlaneOrientation(const Vec3& a, const Vec3& b, const Vec3& c);
  [[nodiscard]] int operator()(const Vec3& d) const;

private:
  Vec3 a_, b_, c_;
  Vec3 minor_;     // (b - a) x (c - a), as the filter computes it
  Vec3 permanent_; // per component, the sum of the magnitudes of its two products
};

} // namespace st
