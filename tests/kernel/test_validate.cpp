// The solid check counts what makes a mesh unprintable: border, non-manifold and inconsistently
// oriented edges, each where it is, on a closed sphere made open, doubled or turned.

#include "helpers.h"

#include "st/core/errors.h"
#include "st/validate/validate.h"

#include <gtest/gtest.h>

#include <utility>

namespace st {
namespace {

using test::make_icosphere;

TEST(SolidCheck, ClosedSphereIsValid) {
  const TriangleMesh sphere = make_icosphere(10.0, 3);
  const SolidReport r = check_solid(sphere);
  EXPECT_TRUE(r.valid()) << r.summary();
  EXPECT_EQ(r.border_edges, 0u);
  EXPECT_EQ(r.components, 1u);
}

TEST(SolidCheck, CountsTheBorderOfAHole) {
  TriangleMesh sphere = make_icosphere(10.0, 3);
  const Vec3 corner = sphere.positions[sphere.triangles[7][0]];
  sphere.triangles.erase(sphere.triangles.begin() + 7);
  const SolidReport r = check_solid(sphere);
  EXPECT_FALSE(r.valid());
  EXPECT_EQ(r.border_edges, 3u) << r.summary();
  EXPECT_EQ(r.nonmanifold_edges, 0u);
  EXPECT_EQ(r.misoriented_edges, 0u);
  ASSERT_FALSE(r.problem_points.empty());
  EXPECT_LT((r.problem_points.front() - corner).norm(), 3.0); // at the hole
}

TEST(SolidCheck, CountsAFaceTurnedTheWrongWay) {
  TriangleMesh sphere = make_icosphere(10.0, 3);
  std::swap(sphere.triangles[11][1], sphere.triangles[11][2]);
  const SolidReport r = check_solid(sphere);
  EXPECT_FALSE(r.valid());
  EXPECT_EQ(r.misoriented_edges, 3u) << r.summary();
  EXPECT_EQ(r.border_edges, 0u);
  EXPECT_EQ(r.nonmanifold_edges, 0u);
}

TEST(SolidCheck, CountsEdgesOfADoubledFace) {
  TriangleMesh sphere = make_icosphere(10.0, 3);
  sphere.triangles.push_back(sphere.triangles[5]);
  const SolidReport r = check_solid(sphere);
  EXPECT_FALSE(r.valid());
  EXPECT_EQ(r.nonmanifold_edges, 3u) << r.summary();
  EXPECT_EQ(r.border_edges, 0u);
}

TEST(SolidCheck, CountsAFaceAddedAcrossTwoEdges) {
  // A face the other way round over an existing one: each of its edges is used three times.
  TriangleMesh sphere = make_icosphere(10.0, 3);
  Triangle t = sphere.triangles[5];
  std::swap(t[1], t[2]);
  sphere.triangles.push_back(t);
  const SolidReport r = check_solid(sphere);
  EXPECT_EQ(r.nonmanifold_edges, 3u) << r.summary();
  EXPECT_EQ(r.misoriented_edges, 0u);
}

// A near vertex per point (the one it was moved from) only shortens the search: the same distances
// as without, a point on its vertex at 0; at a clearance and at the template's thickness; with
// vertices that are not near at all; and a list of the wrong length refused.
TEST(DistancesToSurface, NearVerticesGiveTheSameDistances) {
  const TriangleMesh sphere = make_icosphere(10.0, 4);
  const std::vector<Vec3> normals = vertex_normals(sphere);
  std::vector<Index> own(sphere.vertex_count()), far(sphere.vertex_count());
  for (Index v = 0; v < sphere.vertex_count(); ++v) {
    own[v] = v;
    far[v] = (v * 7919u) % sphere.vertex_count();
  }
  for (const double off : {0.0, 0.1, 2.5, -1.0}) {
    std::vector<Vec3> points = sphere.positions;
    for (Index v = 0; v < sphere.vertex_count(); ++v) points[v] += off * normals[v];
    const DistanceStats plain = distances_to_surface(points, sphere);
    for (const std::vector<Index>* near : {&own, &far}) {
      const DistanceStats hinted = distances_to_surface(points, sphere, *near);
      EXPECT_EQ(hinted.min, plain.min) << off;
      EXPECT_EQ(hinted.max, plain.max) << off;
      EXPECT_EQ(hinted.mean, plain.mean) << off;
    }
    if (off == 0.0) EXPECT_EQ(plain.max, 0.0);
  }
  EXPECT_THROW(distances_to_surface(sphere.positions, sphere, std::vector<Index>{0, 1}), InvalidInput);
  std::vector<Index> beyond(sphere.vertex_count(), sphere.vertex_count());
  EXPECT_THROW(distances_to_surface(sphere.positions, sphere, beyond), InvalidInput);
}

} // namespace
} // namespace st
