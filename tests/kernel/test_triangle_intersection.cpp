// Tests of the exact triangle and segment intersection tests: named configurations (checked in every
// vertex order and both argument orders) and randomised comparisons on small integer coordinates
// against two independent exact references written here:
//   - two convex hulls A and B meet exactly when the origin lies in the hull of the nine differences
//     a_i - b_j, which by Caratheodory means in some point, segment, triangle or tetrahedron of them;
//   - for faces sharing vertices, A n B is the image of the polytope
//     {lambda, mu >= 0, sum lambda = sum mu = 1, sum lambda_i a_i = sum mu_j b_j}; it leaves the hull of
//     the shared vertices exactly when the image of one of its vertices (basic solutions, Cramer's rule)
//     does.

#include "st/boolean/triangle_intersection.h"

#include "exact_reference.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace {

using st::Index;
using st::Vec3;
using Tri = std::array<Vec3, 3>;
using namespace exact_reference;

// ---- helpers for the named cases ------------------------------------------------------------------

// triangles_intersect in all 6 x 6 vertex orders and both argument orders; all must agree.
void expect_intersect(const Tri& a, const Tri& b, bool expected) {
  std::array<int, 3> pa = {0, 1, 2};
  do {
    std::array<int, 3> pb = {0, 1, 2};
    do {
      const Vec3 &a0 = a[pa[0]], &a1 = a[pa[1]], &a2 = a[pa[2]];
      const Vec3 &b0 = b[pb[0]], &b1 = b[pb[1]], &b2 = b[pb[2]];
      ASSERT_EQ(st::triangles_intersect(a0, a1, a2, b0, b1, b2), expected)
          << "order " << pa[0] << pa[1] << pa[2] << " / " << pb[0] << pb[1] << pb[2];
      ASSERT_EQ(st::triangles_intersect(b0, b1, b2, a0, a1, a2), expected);
    } while (std::next_permutation(pb.begin(), pb.end()));
  } while (std::next_permutation(pa.begin(), pa.end()));
}

// segment_intersects_triangle in both segment directions and all triangle orders.
void expect_segment(const Vec3& p, const Vec3& q, const Tri& t, bool expected) {
  std::array<int, 3> o = {0, 1, 2};
  do {
    ASSERT_EQ(st::segment_intersects_triangle(p, q, t[o[0]], t[o[1]], t[o[2]]), expected);
    ASSERT_EQ(st::segment_intersects_triangle(q, p, t[o[0]], t[o[1]], t[o[2]]), expected);
  } while (std::next_permutation(o.begin(), o.end()));
}

// mesh_triangles_intersect in all rotations and reflections of both index triples, both orders.
void expect_mesh(const std::array<Index, 3>& ta, const Tri& pa, const std::array<Index, 3>& tb, const Tri& pb,
                 bool expected) {
  std::array<int, 3> oa = {0, 1, 2};
  do {
    std::array<int, 3> ob = {0, 1, 2};
    do {
      const std::array<Index, 3> ia = {ta[oa[0]], ta[oa[1]], ta[oa[2]]}, ib = {tb[ob[0]], tb[ob[1]], tb[ob[2]]};
      const Tri qa = {pa[oa[0]], pa[oa[1]], pa[oa[2]]}, qb = {pb[ob[0]], pb[ob[1]], pb[ob[2]]};
      ASSERT_EQ(st::mesh_triangles_intersect(ia, qa, ib, qb), expected);
      ASSERT_EQ(st::mesh_triangles_intersect(ib, qb, ia, qa), expected);
    } while (std::next_permutation(ob.begin(), ob.end()));
  } while (std::next_permutation(oa.begin(), oa.end()));
}

struct SimpleMesh {
  std::vector<Vec3> positions;
  std::vector<std::array<Index, 3>> faces;
};

// Counts the face pairs that mesh_triangles_intersect reports.
int count_self_intersections(const SimpleMesh& m) {
  int count = 0;
  for (std::size_t f = 0; f < m.faces.size(); ++f)
    for (std::size_t g = f + 1; g < m.faces.size(); ++g) {
      const auto& ta = m.faces[f];
      const auto& tb = m.faces[g];
      const Tri pa = {m.positions[ta[0]], m.positions[ta[1]], m.positions[ta[2]]};
      const Tri pb = {m.positions[tb[0]], m.positions[tb[1]], m.positions[tb[2]]};
      count += st::mesh_triangles_intersect(ta, pa, tb, pb);
    }
  return count;
}

// A disc fan around vertex 0: centre + ring of n points on the plane centre + cos u + sin v.
SimpleMesh disc_fan(int n, const Vec3& centre, const Vec3& u, const Vec3& v) {
  SimpleMesh m;
  m.positions.push_back(centre);
  for (int i = 0; i < n; ++i) {
    const double t = 2.0 * M_PI * i / n;
    m.positions.push_back(centre + std::cos(t) * u + std::sin(t) * v);
  }
  for (int i = 0; i < n; ++i) m.faces.push_back({0, Index(1 + i), Index(1 + (i + 1) % n)});
  return m;
}

// Octahedron subdivided `levels` times, projected to the unit sphere (convex and closed).
SimpleMesh sphere(int levels) {
  SimpleMesh m;
  m.positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  m.faces = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  for (int l = 0; l < levels; ++l) {
    std::vector<std::array<Index, 3>> next;
    std::vector<std::pair<std::pair<Index, Index>, Index>> mids;
    auto mid = [&](Index a, Index b) {
      const std::pair<Index, Index> key(std::min(a, b), std::max(a, b));
      for (const auto& [k, v] : mids)
        if (k == key) return v;
      m.positions.push_back((m.positions[a] + m.positions[b]).normalized());
      mids.push_back({key, Index(m.positions.size() - 1)});
      return Index(m.positions.size() - 1);
    };
    for (const auto& f : m.faces) {
      const Index a = mid(f[0], f[1]), b = mid(f[1], f[2]), c = mid(f[2], f[0]);
      next.push_back({f[0], a, c});
      next.push_back({f[1], b, a});
      next.push_back({f[2], c, b});
      next.push_back({a, b, c});
    }
    m.faces = next;
  }
  return m;
}

} // namespace

// ---- named configurations ---------------------------------------------------------------------------

TEST(TriangleIntersection, SeparatedTriangles) {
  const Tri a = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  expect_intersect(a, {Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(0, 1, 1)}, false);          // parallel planes
  expect_intersect(a, {Vec3(5, 5, -1), Vec3(6, 5, 1), Vec3(5, 6, 1)}, false);         // far away
  expect_intersect(a, {Vec3(0.6, 0.6, -1), Vec3(0.6, 0.6, 1), Vec3(2, 2, 0)}, false); // boxes overlap
  // b crosses a's plane, but on the line of the two planes they miss each other.
  expect_intersect(a, {Vec3(0.6, 0.6, -1), Vec3(0.6, 0.6, 1), Vec3(3, -1, 0)}, false);
}

TEST(TriangleIntersection, CrossingAndPiercing) {
  const Tri a = {Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(0, 4, 0)};
  // b stands upright through a's interior, crossing two of a's edges' plane lines: a proper crossing.
  expect_intersect(a, {Vec3(1, 1, -1), Vec3(1, 1, 1), Vec3(-1, 3, 0)}, true);
  // One edge of b pierces a's interior; b's other vertices are far out.
  expect_intersect(a, {Vec3(1, 1, -1), Vec3(1, 1, 1), Vec3(10, 10, 0)}, true);
  // Two triangles linked like chain links: each pierces the other.
  expect_intersect({Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(1, 2, 0)}, {Vec3(1, 1, -1), Vec3(1, 1, 1), Vec3(1, -2, 0.5)},
                   true);
}

TEST(TriangleIntersection, TouchingAtAVertexAnEdgeOrTheFace) {
  const Tri a = {Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(0, 4, 0)};
  expect_intersect(a, {Vec3(0, 0, 0), Vec3(-1, 0, 1), Vec3(0, -1, 1)}, true);  // common vertex only
  expect_intersect(a, {Vec3(2, 0, 0), Vec3(2, -1, 1), Vec3(3, -1, 1)}, true);  // b's vertex on a's edge
  expect_intersect(a, {Vec3(2, 2, 0), Vec3(3, 3, 1), Vec3(3, 2, 1)}, true);    // on the hypotenuse
  expect_intersect(a, {Vec3(1, 1, 0), Vec3(1, 1, 1), Vec3(2, 1, 1)}, true);    // b's vertex on a's face
  expect_intersect(a, {Vec3(1, -1, 0), Vec3(1, 1, 0), Vec3(1, 0, 3)}, true);   // b's edge lies across a's face
  expect_intersect(a, {Vec3(2, -1, 1), Vec3(2, 1, -1), Vec3(5, -3, 2)}, true); // edge touches edge at (2, 0, 0)
  expect_intersect(a, {Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(2, 0, 3)}, true);    // common edge, a hinge
  expect_intersect(a, {Vec3(1, 0, 0), Vec3(3, 0, 0), Vec3(2, -2, -3)}, true);  // part of an edge
  // The same configurations moved off by the smallest possible amount no longer touch.
  expect_intersect(a, {Vec3(1, 1, 0x1p-1074), Vec3(1, 1, 1), Vec3(2, 1, 1)}, false);
  expect_intersect(a, {Vec3(2, -0x1p-52, 0), Vec3(2, -1, 1), Vec3(3, -1, 1)}, false);
  expect_intersect(a, {Vec3(2, 2 + 0x1p-51, 0), Vec3(3, 3, 1), Vec3(3, 2, 1)}, false);
}

TEST(TriangleIntersection, CoplanarTriangles) {
  const Tri a = {Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(0, 4, 0)};
  expect_intersect(a, {Vec3(1, 1, 0), Vec3(5, 1, 0), Vec3(1, 5, 0)}, true);        // overlapping
  expect_intersect(a, {Vec3(1, 1, 0), Vec3(2, 1, 0), Vec3(1, 2, 0)}, true);        // contained
  expect_intersect(a, {Vec3(-1, -1, 0), Vec3(9, -1, 0), Vec3(-1, 9, 0)}, true);    // containing
  expect_intersect(a, a, true);                                                    // identical
  expect_intersect(a, {Vec3(2, -1, 0), Vec3(5, 2, 0), Vec3(2, 5, 0)}, true);       // edges cross, no vertex inside
  expect_intersect(a, {Vec3(-1, 1, 0), Vec3(5, 1, 0), Vec3(2, -3, 0)}, true);      // star of David style
  expect_intersect(a, {Vec3(4, 0, 0), Vec3(5, 0, 0), Vec3(5, 1, 0)}, true);        // touching at a vertex
  expect_intersect(a, {Vec3(2, 2, 0), Vec3(5, 5, 0), Vec3(5, 2, 0)}, true);        // vertex on the hypotenuse
  expect_intersect(a, {Vec3(1, 0, 0), Vec3(3, 0, 0), Vec3(2, -1, 0)}, true);       // along part of an edge
  expect_intersect(a, {Vec3(4, 0, 0), Vec3(0, 4, 0), Vec3(4, 4, 0)}, true);        // common edge, other side
  expect_intersect(a, {Vec3(2.5, 2.5, 0), Vec3(5, 5, 0), Vec3(5, 2.5, 0)}, false); // close but disjoint
  expect_intersect(a, {Vec3(-1, -1, 0), Vec3(-5, -1, 0), Vec3(-1, -5, 0)}, false);
  // Coplanar in a tilted plane x + y + z = 1 (exact in binary).
  const Tri t = {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  expect_intersect(t, {Vec3(0.5, 0.5, 0), Vec3(0.5, 0, 0.5), Vec3(0, 0.5, 0.5)}, true);
  expect_intersect(t, {Vec3(1, 1, -1), Vec3(2, 0, -1), Vec3(1.5, 1, -1.5)}, false);
  expect_intersect(t, {Vec3(0.5, 0.5, 0), Vec3(1, 1, -1), Vec3(2, 0, -1)}, true);
}

TEST(TriangleIntersection, DegenerateTrianglesAreSegmentsOrPoints) {
  const Tri a = {Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(0, 4, 0)};
  const Tri needle = {Vec3(1, 1, -1), Vec3(1, 1, 1), Vec3(1, 1, 0.5)}; // collinear: the segment z in [-1, 1]
  expect_intersect(a, needle, true);
  expect_intersect(a, {Vec3(1, 1, 1), Vec3(1, 1, 2), Vec3(1, 1, 3)}, false);
  expect_intersect(a, {Vec3(1, 1, 0), Vec3(1, 1, 0), Vec3(1, 1, 0)}, true);  // a point on the face
  expect_intersect(a, {Vec3(3, 3, 0), Vec3(3, 3, 0), Vec3(3, 3, 0)}, false); // a point beside it
  expect_intersect(a, {Vec3(-1, 2, 0), Vec3(5, 2, 0), Vec3(2, 2, 0)}, true); // a segment in the plane
  expect_intersect(a, {Vec3(5, 2, 0), Vec3(6, 2, 0), Vec3(7, 2, 0)}, false);
  // Both degenerate: crossing, skew, collinear overlapping and collinear apart.
  expect_intersect({Vec3(0, 0, 0), Vec3(2, 2, 0), Vec3(1, 1, 0)}, {Vec3(0, 2, 0), Vec3(2, 0, 0), Vec3(0, 2, 0)}, true);
  expect_intersect({Vec3(0, 0, 0), Vec3(2, 2, 0), Vec3(1, 1, 0)}, {Vec3(0, 2, 1), Vec3(2, 0, 1), Vec3(0, 2, 1)}, false);
  expect_intersect({Vec3(0, 0, 0), Vec3(2, 2, 2), Vec3(1, 1, 1)}, {Vec3(2, 2, 2), Vec3(3, 3, 3), Vec3(5, 5, 5)}, true);
  expect_intersect({Vec3(0, 0, 0), Vec3(2, 2, 2), Vec3(1, 1, 1)}, {Vec3(3, 3, 3), Vec3(4, 4, 4), Vec3(5, 5, 5)}, false);
  expect_intersect({Vec3(1, 2, 3), Vec3(1, 2, 3), Vec3(1, 2, 3)}, {Vec3(1, 2, 3), Vec3(1, 2, 3), Vec3(1, 2, 3)}, true);
  expect_intersect({Vec3(1, 2, 3), Vec3(1, 2, 3), Vec3(1, 2, 3)}, {Vec3(1, 2, 4), Vec3(1, 2, 4), Vec3(1, 2, 4)}, false);
  // A nearly degenerate sliver that is not degenerate: its tip stays out of the other triangle.
  const Tri sliver = {Vec3(0, 0, 0), Vec3(1e8, 0, 0), Vec3(5e7, 0x1p-40, 0)};
  expect_intersect(sliver, {Vec3(5e7, 0x1p-39, -1), Vec3(5e7, 0x1p-39, 1), Vec3(5e7, 1, 0)}, false);
  expect_intersect(sliver, {Vec3(5e7, 0x1p-41, -1), Vec3(5e7, 0x1p-41, 1), Vec3(5e7, 1, 0)}, true);
}

TEST(TriangleIntersection, LargeCoordinatesDecidedExactly) {
  // Triangles around 1e8 whose contact is decided by the last bit.
  const double z = 1e8;
  const Tri a = {Vec3(1e8, 1e8, z), Vec3(1e8 + 4, 1e8, z), Vec3(1e8, 1e8 + 4, z)};
  expect_intersect(a, {Vec3(1e8 + 1, 1e8 + 1, z), Vec3(1e8 + 1, 1e8 + 1, z + 1), Vec3(1e8 + 2, 1e8 + 1, z + 1)}, true);
  expect_intersect(
      a, {Vec3(1e8 + 1, 1e8 + 1, std::nextafter(z, 2e8)), Vec3(1e8 + 1, 1e8 + 1, z + 1), Vec3(1e8 + 2, 1e8 + 1, z + 1)},
      false);
  // A tilted plane (normal (8, -12, 4)) at x = 1e8: b's vertex exactly on an edge's midpoint, b's
  // other vertices below the plane; then the vertex one ulp below the plane as well.
  const Tri t = {Vec3(1e8, 0, 0), Vec3(1e8 + 2, 2, 2), Vec3(1e8, 2, 6)};
  const Vec3 mid(1e8 + 1, 1, 1);
  expect_intersect(t, {mid, Vec3(1e8 + 3, 1, -5), Vec3(1e8 + 3, 0, -7)}, true);
  expect_intersect(t, {Vec3(std::nextafter(1e8 + 1, 0.0), 1, 1), Vec3(1e8 + 3, 1, -5), Vec3(1e8 + 3, 0, -7)}, false);
}

TEST(TriangleIntersection, SegmentAgainstTriangle) {
  const Tri t = {Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(0, 4, 0)};
  expect_segment(Vec3(1, 1, -1), Vec3(1, 1, 1), t, true);  // through the interior
  expect_segment(Vec3(5, 5, -1), Vec3(5, 5, 1), t, false); // beside it
  expect_segment(Vec3(1, 1, 0), Vec3(1, 1, 1), t, true);   // ends on the face
  expect_segment(Vec3(1, 1, 1e-300), Vec3(1, 1, 1), t, false);
  expect_segment(Vec3(0, 0, -1), Vec3(0, 0, 1), t, true);   // through a vertex
  expect_segment(Vec3(2, 0, -1), Vec3(2, 0, 1), t, true);   // through an edge
  expect_segment(Vec3(-1, 1, 0), Vec3(5, 1, 0), t, true);   // in the plane, across
  expect_segment(Vec3(-1, 0, 0), Vec3(5, 0, 0), t, true);   // along an edge
  expect_segment(Vec3(-1, 5, 0), Vec3(5, -1, 0), t, true);  // along the hypotenuse's line
  expect_segment(Vec3(-1, 6, 0), Vec3(6, -1, 0), t, false); // in the plane, parallel to the hypotenuse
  expect_segment(Vec3(-1, -1, 0), Vec3(-3, 5, 0), t, false);
  expect_segment(Vec3(1, 1, 0), Vec3(1, 1, 0), t, true); // a point segment
  expect_segment(Vec3(1, 1, 2), Vec3(1, 1, 2), t, false);
  expect_segment(Vec3(1, 1, 1), Vec3(3, 3, -1), t, true); // crosses the plane on the hypotenuse
  expect_segment(Vec3(1, 1, 1), Vec3(3.5, 3.5, -1), t, false);
  const Tri flat = {Vec3(0, 0, 0), Vec3(2, 2, 2), Vec3(1, 1, 1)}; // a degenerate triangle
  expect_segment(Vec3(0, 2, 0), Vec3(2, 0, 2), flat, true);
  expect_segment(Vec3(0, 2, 0), Vec3(2, 0, 3), flat, false);
  expect_segment(Vec3(3, 3, 3), Vec3(4, 4, 4), flat, false);
  expect_segment(Vec3(2, 2, 2), Vec3(4, 4, 4), flat, true);
}

// ---- faces of one mesh --------------------------------------------------------------------------------

TEST(MeshTriangleIntersection, FlatDiscFanNeighboursDoNotIntersect) {
  const SimpleMesh flat = disc_fan(24, Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0));
  EXPECT_EQ(count_self_intersections(flat), 0);
  // Away from the origin and in a tilted plane the points are only nearly coplanar.
  const SimpleMesh tilted = disc_fan(24, Vec3(1e3, -2e3, 5e2), Vec3(0.6, 0.8, 0), Vec3(-0.48, 0.36, 0.8));
  EXPECT_EQ(count_self_intersections(tilted), 0);
  // An axis-aligned plane far away: exactly coplanar, every edge-neighbour decision by orient2d.
  const SimpleMesh far = disc_fan(24, Vec3(1e8, 1e8, 1e8), Vec3(0, 3, 0), Vec3(0, 0, 3));
  EXPECT_EQ(count_self_intersections(far), 0);
}

TEST(MeshTriangleIntersection, ClosedConvexMeshHasNoSelfIntersection) {
  const SimpleMesh s = sphere(2);
  ASSERT_EQ(s.faces.size(), 128u);
  EXPECT_EQ(count_self_intersections(s), 0);
}

TEST(MeshTriangleIntersection, EdgeNeighbours) {
  const Vec3 u(0, 0, 0), w(2, 0, 0);
  // Folded onto each other: coplanar, opposite vertices on the same side of the edge.
  expect_mesh({0, 1, 2}, {u, w, Vec3(1, 2, 0)}, {1, 0, 3}, {w, u, Vec3(0.5, 1, 0)}, true);
  expect_mesh({0, 1, 2}, {u, w, Vec3(1, 2, 0)}, {1, 0, 3}, {w, u, Vec3(5, 0.01, 0)}, true);
  // Flat, on opposite sides: a regular edge.
  expect_mesh({0, 1, 2}, {u, w, Vec3(1, 2, 0)}, {1, 0, 3}, {w, u, Vec3(1, -2, 0)}, false);
  // A dihedral angle, however small.
  expect_mesh({0, 1, 2}, {u, w, Vec3(1, 2, 0)}, {1, 0, 3}, {w, u, Vec3(1, 2, 0x1p-1000)}, false);
  expect_mesh({0, 1, 2}, {u, w, Vec3(1, 2, 0)}, {1, 0, 3}, {w, u, Vec3(1, -2, 3)}, false);
  // Degenerate faces on the edge's line: a needle inside the edge, and two needles overlapping past it.
  expect_mesh({0, 1, 2}, {u, w, Vec3(1, 2, 0)}, {1, 0, 3}, {w, u, Vec3(1, 0, 0)}, false);
  expect_mesh({0, 1, 2}, {u, w, Vec3(3, 0, 0)}, {1, 0, 3}, {w, u, Vec3(1, 2, 0)}, false);
  expect_mesh({0, 1, 2}, {u, w, Vec3(3, 0, 0)}, {1, 0, 3}, {w, u, Vec3(4, 0, 0)}, true);
  expect_mesh({0, 1, 2}, {u, w, Vec3(3, 0, 0)}, {1, 0, 3}, {w, u, Vec3(-1, 0, 0)}, false);
}

TEST(MeshTriangleIntersection, VertexNeighbours) {
  const Vec3 v(0, 0, 0);
  const Tri a = {v, Vec3(2, 0, 0), Vec3(0, 2, 0)};
  // b's opposite edge pierces a.
  expect_mesh({0, 1, 2}, a, {0, 3, 4}, {v, Vec3(0.5, 0.5, 1), Vec3(0.5, 0.5, -1)}, true);
  // b's opposite edge crosses a's plane just beside a, and b meets that plane along a ray from v that
  // passes a hair outside a's wedge.
  expect_mesh({0, 1, 2}, a, {0, 3, 4}, {v, Vec3(3, -0x1p-40, 1), Vec3(3, -0x1p-40, -1)}, false);
  expect_mesh({0, 1, 2}, a, {0, 3, 4}, {v, Vec3(3, 0, 1), Vec3(3, 0, -1)}, true); // along a's edge
  // b wholly above a's plane but for v.
  expect_mesh({0, 1, 2}, a, {0, 3, 4}, {v, Vec3(1, 1.5, 1), Vec3(1.5, 1, 1)}, false);
  // The corner of a cube: two faces meeting only at the corner.
  expect_mesh({0, 1, 2}, {v, Vec3(1, 0, 0), Vec3(1, 1, 0)}, {0, 3, 4}, {v, Vec3(0, 0, 1), Vec3(0, 1, 1)}, false);
  expect_mesh({0, 1, 2}, {v, Vec3(1, 0, 0), Vec3(1, 1, 0)}, {0, 3, 4}, {v, Vec3(0, 1, 1), Vec3(1, 1, 1)}, false);
  // The line of the two planes runs into both wedges in the same direction (the faces overlap near v
  // although b's opposite edge stays away from a), or in opposite directions (only v in common).
  expect_mesh({0, 1, 2}, a, {0, 3, 4}, {v, Vec3(3, 3, 1), Vec3(3, 3, -1)}, true);
  expect_mesh({0, 1, 2}, a, {0, 3, 4}, {v, Vec3(-1, -1, 1), Vec3(-1, -1, -1)}, false);
  // Coplanar wedges: overlapping, sharing a boundary ray, apart, opposite.
  expect_mesh({0, 1, 2}, a, {0, 3, 4}, {v, Vec3(1, 0.2, 0), Vec3(1, 3, 0)}, true);
  expect_mesh({0, 1, 2}, a, {0, 3, 4}, {v, Vec3(5, 0, 0), Vec3(1, -1, 0)}, true);
  expect_mesh({0, 1, 2}, a, {0, 3, 4}, {v, Vec3(-1, 1, 0), Vec3(-1, 0.5, 0)}, false);
  expect_mesh({0, 1, 2}, a, {0, 3, 4}, {v, Vec3(-2, 0, 0), Vec3(0, -2, 0)}, false);
  // A degenerate face through v (v between its other corners) touches only at v ...
  expect_mesh({0, 1, 2}, a, {0, 3, 4}, {v, Vec3(-1, -1, 1), Vec3(1, 1, -1)}, false);
  // ... unless it runs into the other face.
  expect_mesh({0, 1, 2}, a, {0, 3, 4}, {v, Vec3(-1, -1, 0), Vec3(1, 1, 0)}, true);
}

TEST(MeshTriangleIntersection, DuplicateAndRepeatedIndices) {
  const Tri p = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  expect_mesh({0, 1, 2}, p, {0, 1, 2}, p, true);
  EXPECT_TRUE(st::mesh_triangles_intersect({0, 1, 2}, p, {2, 1, 0}, {p[2], p[1], p[0]}));
  // A face with a repeated index is the segment between its two positions.
  EXPECT_FALSE(st::mesh_triangles_intersect({0, 0, 1}, {p[0], p[0], p[1]}, {0, 1, 2}, p));
  EXPECT_FALSE(st::mesh_triangles_intersect({0, 0, 3}, {p[0], p[0], Vec3(-1, 0, 0)}, {0, 1, 2}, p));
  EXPECT_TRUE(st::mesh_triangles_intersect({0, 0, 3}, {p[0], p[0], Vec3(0.5, 0.1, 0)}, {0, 1, 2}, p));
}

TEST(MeshTriangleIntersection, FoldedStripIsFound) {
  // A strip of four triangles whose last triangle is folded back flat onto the first.
  SimpleMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0.2, 0.2, 0}};
  m.faces = {{0, 1, 2}, {1, 3, 2}, {2, 3, 4}};
  EXPECT_EQ(count_self_intersections(m), 2); // face 2 lies over face 0 (sharing vertex 2) and face 1
}

// ---- randomised comparison with the exact references ----------------------------------------------------

TEST(TriangleIntersection, RandomPairsMatchExactReference) {
  Randomizer r(20240531);
  int pairs = 0, intersecting = 0, coplanar = 0, degenerate = 0, sharing = 0;
  for (int n = 0; n < 120000; ++n) {
    const auto [ia, ib] = random_pair(r, n % 6);
    const bool expected = reference_hulls_meet({ia.begin(), ia.end()}, {ib.begin(), ib.end()});
    const ExactMap map = ExactMap::random(r);
    const Vec3 a0 = map(ia[0]), a1 = map(ia[1]), a2 = map(ia[2]), b0 = map(ib[0]), b1 = map(ib[1]), b2 = map(ib[2]);
    ASSERT_EQ(st::triangles_intersect(a0, a1, a2, b0, b1, b2), expected) << "pair " << n;
    ASSERT_EQ(st::triangles_intersect(b1, b2, b0, a2, a1, a0), expected) << "pair " << n;
    ++pairs;
    intersecting += expected;
    const bool deg = collinear_int(ia) || collinear_int(ib);
    degenerate += deg;
    bool in_plane = !deg;
    for (const I3& q : ib) in_plane = in_plane && det3(sub(ia[1], ia[0]), sub(ia[2], ia[0]), sub(q, ia[0])) == 0;
    coplanar += in_plane;
    bool share = false;
    for (const I3& p : ia)
      for (const I3& q : ib) share = share || p == q;
    sharing += share;
    // Segment against triangle, with the reference on the segment's two points.
    if (n % 3 == 0) {
      const bool seg_expected = reference_hulls_meet({ia[0], ia[1]}, {ib.begin(), ib.end()});
      ASSERT_EQ(st::segment_intersects_triangle(a0, a1, b0, b1, b2), seg_expected) << "pair " << n;
    }
  }
  EXPECT_GE(pairs, 100000);
  EXPECT_GT(intersecting, pairs / 5);
  EXPECT_LT(intersecting, pairs * 4 / 5);
  EXPECT_GT(coplanar, 20000);
  EXPECT_GT(degenerate, 20000);
  EXPECT_GT(sharing, 20000);
}

TEST(MeshTriangleIntersection, RandomFacePairsMatchExactReference) {
  Randomizer r(777);
  // Index patterns over six vertices: none, one, two or three shared, and repeated indices.
  const std::array<std::array<Index, 3>, 2> patterns[] = {
      {{{0, 1, 2}, {3, 4, 5}}}, {{{0, 1, 2}, {0, 3, 4}}}, {{{0, 1, 2}, {1, 0, 3}}}, {{{0, 1, 2}, {0, 1, 3}}},
      {{{0, 1, 2}, {2, 1, 0}}}, {{{0, 0, 1}, {0, 2, 3}}}, {{{0, 0, 1}, {0, 1, 2}}}, {{{0, 1, 1}, {1, 2, 3}}}};
  int checked = 0, intersecting = 0, per_pattern[8] = {};
  for (int n = 0; n < 24000; ++n) {
    const int kind = n % 8;
    std::array<Index, 3> ta = patterns[kind][0], tb = patterns[kind][1];
    std::rotate(ta.begin(), ta.begin() + r.uniform(0, 2), ta.end());
    std::rotate(tb.begin(), tb.begin() + r.uniform(0, 2), tb.end());
    if (r.uniform(0, 1)) std::swap(ta[0], ta[1]);
    if (r.uniform(0, 1)) std::swap(tb[0], tb[1]);
    I3 pos[6];
    const bool planar = r.uniform(0, 2) == 0;
    for (I3& p : pos) p = planar ? I3{r.uniform(0, 3), r.uniform(0, 3), 0} : r.point(0, 2);
    const ITri ia = {pos[ta[0]], pos[ta[1]], pos[ta[2]]}, ib = {pos[tb[0]], pos[tb[1]], pos[tb[2]]};
    std::array<Index, 3> sa = ta, sb = tb;
    std::sort(sa.begin(), sa.end());
    std::sort(sb.begin(), sb.end());
    std::vector<I3> shared;
    std::vector<Index> shared_ids;
    for (Index i : ta)
      if (std::find(tb.begin(), tb.end(), i) != tb.end() &&
          std::find(shared_ids.begin(), shared_ids.end(), i) == shared_ids.end()) {
        shared_ids.push_back(i);
        shared.push_back(pos[i]);
      }
    const bool expected = sa == sb || reference_meet_beyond(ia, ib, shared);
    const ExactMap map = ExactMap::random(r);
    const Tri pa = {map(ia[0]), map(ia[1]), map(ia[2])}, pb = {map(ib[0]), map(ib[1]), map(ib[2])};
    ASSERT_EQ(st::mesh_triangles_intersect(ta, pa, tb, pb), expected) << "pair " << n << " kind " << kind;
    ASSERT_EQ(st::mesh_triangles_intersect(tb, pb, ta, pa), expected) << "pair " << n << " kind " << kind;
    if (shared.empty()) {
      ASSERT_EQ(reference_hulls_meet({ia.begin(), ia.end()}, {ib.begin(), ib.end()}), expected);
    }
    ++checked;
    intersecting += expected;
    per_pattern[kind] += expected;
  }
  EXPECT_EQ(checked, 24000);
  for (int k = 0; k < 8; ++k) {
    if (k != 6) {
      EXPECT_GT(per_pattern[k], 50) << "pattern " << k;
    }
  }
  // A face with a repeated index lying on an edge of its neighbour never reaches beyond that edge.
  EXPECT_EQ(per_pattern[6], 0);
  EXPECT_LT(intersecting, checked * 9 / 10);
}
