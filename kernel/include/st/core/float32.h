#pragma once
// Coordinates rounded to float32, what an STL file holds, so that the mesh the kernel checks is the
// mesh it writes.

#include "st/core/mesh.h"

namespace st {

/// x rounded to the nearest float32 value, as a double. Through a volatile float on purpose: GCC 12
/// at -O2 and above (SLP vectorizer) folds two neighbouring double -> float -> double conversions,
/// such as a Vec3's x and y, into nothing, so that a plain cast expression may leave them unrounded
/// (test_float32.cpp catches it).
inline double to_float32(double x) {
  volatile float f = static_cast<float>(x);
  return f;
}

/// p with each coordinate rounded to float32.
inline Vec3 to_float32(const Vec3& p) { return {to_float32(p.x()), to_float32(p.y()), to_float32(p.z())}; }

/// Whether every coordinate of p is a float32 value (it survives a round trip through float32).
inline bool is_float32(const Vec3& p) {
  return to_float32(p.x()) == p.x() && to_float32(p.y()) == p.y() && to_float32(p.z()) == p.z();
}

/// Rounds every position of `mesh` to float32.
inline void round_to_float32(TriangleMesh& mesh) {
  for (Vec3& p : mesh.positions) p = to_float32(p);
}

} // namespace st
