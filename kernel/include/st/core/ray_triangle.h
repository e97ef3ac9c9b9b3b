#pragma once
// Where a ray meets a triangle (Moller-Trumbore): the AABB tree's ray queries and the Boolean
// operation's inside test share it.

#include "st/core/mesh.h"

#include <cmath>
#include <optional>

namespace st {

/// A ray's hit: origin + t * direction = (1 - u - v) a + u b + v c.
struct RayTriangleHit {
  double t = 0.0;
  double u = 0.0;
  double v = 0.0;
};

/// The hit of the line origin + t * direction (any t) with triangle (a, b, c), barycentrics within
/// [-slack, 1 + slack] (edges and corners included), or nothing when it misses or runs parallel to
/// the triangle's plane.
inline std::optional<RayTriangleHit> ray_triangle(const Vec3& origin, const Vec3& direction, const Vec3& a,
                                                  const Vec3& b, const Vec3& c, double slack = 0.0) {
  const Vec3 e1 = b - a, e2 = c - a;
  const Vec3 pv = direction.cross(e2);
  const double det = e1.dot(pv);
  if (std::abs(det) < 1e-300) return std::nullopt;
  const double inv = 1.0 / det;
  const Vec3 tv = origin - a;
  const double u = tv.dot(pv) * inv;
  if (u < -slack || u > 1.0 + slack) return std::nullopt;
  const Vec3 qv = tv.cross(e1);
  const double v = direction.dot(qv) * inv;
  if (v < -slack || u + v > 1.0 + slack) return std::nullopt;
  return RayTriangleHit{e2.dot(qv) * inv, u, v};
}

} // namespace st
