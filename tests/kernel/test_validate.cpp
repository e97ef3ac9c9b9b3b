// The solid check counts what makes a mesh unprintable: border, non-manifold and inconsistently
// oriented edges, each where it is, on a closed sphere made open, doubled or turned.

#include "helpers.h"

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

} // namespace
} // namespace st
