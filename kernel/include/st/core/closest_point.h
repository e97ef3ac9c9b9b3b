#pragma once
// The closest point of a triangle to a point, by its Voronoi regions (Ericson, Real-Time Collision
// Detection 5.1.5), with the feature it lies on (a vertex, an edge, the face). One implementation for
// the offset's distance band (triangles prepared once, queried millions of times), the AABB tree's
// queries, the curve's snapping and the inspection.

#include "st/core/mesh.h"

#include <cmath>

namespace st {

enum Feature : int { kFace = 0, kVertex0, kVertex1, kVertex2, kEdge01, kEdge12, kEdge20 };

/// A triangle prepared for many closest-point queries (triangle_geometry()).
struct TriangleGeometry {
  Vec3 a, ab, ac;
  double abab = 0.0, abac = 0.0, acac = 0.0;
  double inv_gram = 0.0;   // 1 / |ab x ac|^2
  bool degenerate = false; // the smallest angle's sine is below 1e-6: handled as its three edges
};

/// The geometry of triangle (a, b, c).
inline TriangleGeometry triangle_geometry(const Vec3& a, const Vec3& b, const Vec3& c) {
  TriangleGeometry g;
  g.a = a;
  g.ab = b - a;
  g.ac = c - a;
  g.abab = g.ab.squaredNorm();
  g.abac = g.ab.dot(g.ac);
  g.acac = g.ac.squaredNorm();
  const Vec3 n = g.ab.cross(g.ac);
  const double gram = n.squaredNorm();
  g.degenerate = !(gram > 1e-12 * g.abab * g.acac) || !(gram > 0.0);
  g.inv_gram = g.degenerate ? 0.0 : 1.0 / gram;
  return g;
}

struct Nearest {
  double squared = 0.0;
  Vec3 offset = Vec3::Zero(); // query point minus closest point
  int feature = kFace;        // where the closest point lies
};

/// Closest point of segment s-e to p, with its feature (at_s, at_e or inside).
inline Nearest nearest_on_segment(const Vec3& p, const Vec3& s, const Vec3& e, int at_s, int at_e, int inside) {
  const Vec3 se = e - s;
  const double len2 = se.squaredNorm();
  const double t = len2 > 0.0 ? (p - s).dot(se) / len2 : 0.0;
  Nearest n;
  if (t <= 0.0) {
    n.offset = p - s;
    n.feature = at_s;
  } else if (t >= 1.0) {
    n.offset = p - e;
    n.feature = at_e;
  } else {
    n.offset = p - (s + t * se);
    n.feature = inside;
  }
  n.squared = n.offset.squaredNorm();
  return n;
}

/// Closest point of the triangle to p, by the Voronoi region of p: a vertex, an edge or the face
/// (the region tests are dot products with the edges, reusing d1 = ab.ap and d2 = ac.ap).
inline Nearest nearest_on_triangle(const TriangleGeometry& g, const Vec3& p) {
  const Vec3 ap = p - g.a;
  if (g.degenerate) {
    const Vec3 b = g.a + g.ab;
    const Vec3 c = g.a + g.ac;
    Nearest best = nearest_on_segment(p, g.a, b, kVertex0, kVertex1, kEdge01);
    Nearest n = nearest_on_segment(p, b, c, kVertex1, kVertex2, kEdge12);
    if (n.squared < best.squared) best = n;
    n = nearest_on_segment(p, c, g.a, kVertex2, kVertex0, kEdge20);
    if (n.squared < best.squared) best = n;
    return best;
  }
  Nearest n;
  const double d1 = g.ab.dot(ap);
  const double d2 = g.ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) {
    n.offset = ap;
    n.feature = kVertex0;
  } else {
    // ab.(p - b), ac.(p - b), ab.(p - c), ac.(p - c)
    const double d3 = d1 - g.abab;
    const double d4 = d2 - g.abac;
    const double d5 = d1 - g.abac;
    const double d6 = d2 - g.acac;
    const double vc = g.abab * d2 - g.abac * d1; // = d1*d4 - d3*d2
    const double vb = g.acac * d1 - g.abac * d2; // = d5*d2 - d1*d6
    if (d3 >= 0.0 && d4 <= d3) {
      n.offset = ap - g.ab;
      n.feature = kVertex1;
    } else if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
      n.offset = ap - (d1 / (d1 - d3)) * g.ab;
      n.feature = kEdge01;
    } else if (d6 >= 0.0 && d5 <= d6) {
      n.offset = ap - g.ac;
      n.feature = kVertex2;
    } else if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
      n.offset = ap - (d2 / (d2 - d6)) * g.ac;
      n.feature = kEdge20;
    } else {
      const double va = d3 * d6 - d5 * d4;
      const double e1 = d4 - d3;
      const double e2 = d5 - d6;
      if (va <= 0.0 && e1 >= 0.0 && e2 >= 0.0) {
        const double w = e1 / (e1 + e2);
        n.offset = ap - g.ab - w * (g.ac - g.ab);
        n.feature = kEdge12;
      } else {
        n.offset = ap - (vb * g.inv_gram) * g.ab - (vc * g.inv_gram) * g.ac;
        n.feature = kFace;
      }
    }
  }
  n.squared = n.offset.squaredNorm();
  return n;
}

/// Closest point of triangle (a, b, c) to p; exactly a corner when it is one.
inline Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Nearest n = nearest_on_triangle(triangle_geometry(a, b, c), p);
  switch (n.feature) {
  case kVertex0: return a;
  case kVertex1: return b;
  case kVertex2: return c;
  default: return p - n.offset;
  }
}

} // namespace st
