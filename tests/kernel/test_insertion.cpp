// Insertion direction and undercuts: hidden area against analytic values (a sphere's shadow on a
// plane, a spherical cap beyond a hemisphere), the automatic direction, and the search's hidden areas
// against every segment tested with every bone face.

#include "helpers.h"

#include "design/insertion_samples.h"
#include "st/boolean/triangle_intersection.h"
#include "st/core/aabb_tree.h"
#include "st/core/errors.h"
#include "st/core/predicates.h"
#include "st/core/topology.h"
#include "st/design/cut.h"
#include "st/design/insertion.h"
#include "st/design/surface_curve.h"
#include "st/io/mesh_io.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

namespace st {
namespace {

/// Two meshes as one (the second's vertex indices shifted).
TriangleMesh joined(TriangleMesh a, const TriangleMesh& b) {
  const Index n = a.vertex_count();
  a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
  for (const Triangle& t : b.triangles) a.triangles.push_back({t[0] + n, t[1] + n, t[2] + n});
  return a;
}

TEST(Insertion, ABallHidesItsShadowOnThePlaneBelow) {
  // A ball of radius 5 floating 10 mm above a plane region: along the plane's inward normal it hides a
  // disk of its radius; along a direction 26.6 degrees off it, an ellipse of area pi r^2 / cos.
  const TriangleMesh plane = test::make_height_field(0, 60, 0, 60, 120, [](double, double) { return 0.0; });
  const TriangleMesh bone = joined(plane, test::make_icosphere(5.0, 5, Vec3(30, 30, 10)));
  const TriangleMesh region =
      test::faces_where(plane, [](const Vec3& c) { return std::abs(c.x() - 30) < 15 && std::abs(c.y() - 30) < 15; });
  const AabbTree tree(bone);
  const double disk = std::numbers::pi * 25.0;
  const Undercut straight = undercut(tree, region, Vec3(0, 0, -1), 0.1);
  EXPECT_NEAR(straight.area_mm2, 900.0, 1e-6);
  EXPECT_NEAR(straight.hidden_mm2, disk, 0.02 * disk);
  const Vec3 slanted = Vec3(1, 0, -2).normalized();
  const Undercut tilted = undercut(tree, region, slanted, 0.1);
  EXPECT_NEAR(tilted.hidden_mm2, disk / (2.0 / std::sqrt(5.0)), 0.02 * disk / (2.0 / std::sqrt(5.0)));
  // Per face: the faces under the ball's centre are hidden, those at the region's corners are not.
  ASSERT_EQ(straight.hidden.size(), region.face_count());
  for (Index f = 0; f < region.face_count(); ++f) {
    const Triangle& t = region.triangles[f];
    const Vec3 c = (region.positions[t[0]] + region.positions[t[1]] + region.positions[t[2]]) / 3.0;
    const double r = std::hypot(c.x() - 30, c.y() - 30);
    if (r < 4.0) EXPECT_EQ(straight.hidden[f], 1.0f);
    if (r > 6.0) EXPECT_EQ(straight.hidden[f], 0.0f);
  }
}

TEST(Insertion, ACapBeyondAHemisphereIsHiddenBeyondItsEquator) {
  // A cap of half-angle 120 degrees of a sphere of radius 20 around an oblique axis: along the axis
  // the part beyond the equator, of area -2 pi R^2 cos(120 deg), cannot be reached; along any other
  // direction more of it. The automatic direction finds the axis.
  const double R = 20.0;
  const TriangleMesh sphere = test::make_icosphere(R, 5);
  const Vec3 axis = Vec3(1, 2, 3).normalized();
  const TriangleMesh cap = test::faces_where(sphere, [&](const Vec3& c) { return c.normalized().dot(axis) > -0.5; });
  const AabbTree tree(sphere);
  double back_facing = 0.0; // on a convex polyhedron, exactly the faces that look away
  for (Index f = 0; f < cap.face_count(); ++f)
    if (triangle_normal(cap, f).dot(axis) < 0.0) back_facing += 0.5 * triangle_normal(cap, f).norm();
  const Undercut along = undercut(tree, cap, -axis, 0.5);
  EXPECT_NEAR(along.hidden_mm2, back_facing, 1e-9 * back_facing);
  const double analytic = -2.0 * std::numbers::pi * R * R * std::cos(2.0 * std::numbers::pi / 3.0);
  EXPECT_NEAR(along.hidden_mm2, analytic, 0.02 * analytic);
  // Within 30 degrees of the axis the same part is hidden (the cap holds every hemisphere there).
  const Vec3 off = (-axis + 0.3 * axis.cross(Vec3::UnitX()).normalized()).normalized();
  EXPECT_NEAR(undercut(tree, cap, off, 0.5).hidden_mm2, analytic, 0.02 * analytic);
}

TEST(Insertion, TheAutomaticDirectionFindsTheAxisOfAHemisphere) {
  // A hemisphere of radius 20: along its axis nothing is hidden; tilted by phi, a half lune of area
  // phi R^2 is. The search, started 40 degrees off the axis, finds it within 2 degrees.
  const TriangleMesh sphere = test::make_icosphere(20.0, 5);
  const Vec3 axis = Vec3(1, 2, 3).normalized();
  const TriangleMesh cap = test::faces_where(sphere, [&](const Vec3& c) { return c.normalized().dot(axis) > 0.0; });
  const AabbTree tree(sphere);
  const Vec3 start =
      (-axis + std::tan(40.0 * std::numbers::pi / 180.0) * axis.cross(Vec3::UnitX()).normalized()).normalized();
  const Vec3 found = least_undercut_direction(tree, cap, start);
  EXPECT_LT(std::acos(std::clamp(found.dot(-axis), -1.0, 1.0)) * 180.0 / std::numbers::pi, 2.0);
  // From the mean normal (the default start) too.
  const Vec3 from_mean = least_undercut_direction(tree, cap);
  EXPECT_LT(std::acos(std::clamp(from_mean.dot(-axis), -1.0, 1.0)) * 180.0 / std::numbers::pi, 2.0);
}

TEST(Insertion, TheAutomaticDirectionOfAnUnevenCapHidesNoMoreThanItsAxis) {
  // The same cap, but its region's mean normal tilted away from the axis by cutting one side
  // shorter: the least undercut is still along the axis, which the search must find off its start.
  const TriangleMesh sphere = test::make_icosphere(20.0, 5);
  const Vec3 axis = Vec3(-2, 1, 1).normalized();
  const Vec3 side = axis.cross(Vec3::UnitZ()).normalized();
  const TriangleMesh cap = test::faces_where(sphere, [&](const Vec3& c) {
    const Vec3 n = c.normalized();
    return n.dot(axis) > -0.3 && n.dot(side) < 0.6;
  });
  const AabbTree tree(sphere);
  const Vec3 found = least_undercut_direction(tree, cap);
  const Undercut best = undercut(tree, cap, found, 0.5);
  // Nothing of the region beyond the hemisphere around `found` ...
  for (Index f = 0; f < cap.face_count(); ++f)
    if (best.hidden[f] > 0.0f) EXPECT_GE(triangle_normal(cap, f).dot(found), 0.0);
  // ... and no direction of a small ring around it does better.
  EXPECT_LE(best.hidden_mm2, undercut(tree, cap, -axis, 0.5).hidden_mm2 + 1e-9);
}

/// The reference for the search's areas: each sample's segment as insertion.h states it, tested
/// against every face of the bone with the exact test alone (after the boxes, which hold what meets).
double hidden_by_every_face(const insertion_detail::Sight& sight, const TriangleMesh& region,
                            const std::vector<insertion_detail::Sample>& samples, const Vec3& d) {
  const TriangleMesh& bone = sight.bone.mesh();
  std::vector<BoundingBox> boxes(bone.face_count());
  for (Index g = 0; g < bone.face_count(); ++g) boxes[g] = triangle_box(bone, g);
  double total = 0.0;
  for (const insertion_detail::Sample& s : samples) {
    const Triangle& t = region.triangles[s.face];
    const Vec3 &a = region.positions[t[0]], &b = region.positions[t[1]], &c = region.positions[t[2]];
    const int side = orient3d(a, b, c, a + d);
    bool hidden = side < 0;
    if (!hidden) {
      Vec3 p0 = s.point - sight.lift * d;
      if (side == 0) p0 += sight.lift * (b - a).cross(c - a).normalized();
      const Vec3 q = p0 - sight.reach * d;
      BoundingBox segment;
      segment.extend(p0);
      segment.extend(q);
      for (Index g = 0; g < bone.face_count() && !hidden; ++g) {
        const Triangle& f = bone.triangles[g];
        hidden = boxes[g].overlaps(segment) &&
                 segment_intersects_triangle(p0, q, bone.positions[f[0]], bone.positions[f[1]], bone.positions[f[2]]);
      }
    }
    if (hidden) total += s.area;
  }
  return total;
}

/// hidden_areas against the reference, for the directions together and one at a time: every area
/// without a bound; with the middle reference area as the bound, the areas under it as they are, and
/// those over it as they are or infinity, never infinity for one under it. Returns how many were left
/// at infinity.
int expect_areas_of_every_face(const AabbTree& tree, const TriangleMesh& region,
                               const std::vector<insertion_detail::Sample>& samples, const std::vector<Vec3>& ds) {
  const insertion_detail::Sight sight = insertion_detail::sight_of(tree, 20.0);
  std::vector<double> reference;
  for (const Vec3& d : ds) reference.push_back(hidden_by_every_face(sight, region, samples, d));
  const double infinity = std::numeric_limits<double>::infinity();
  std::vector<double> sorted = reference;
  std::sort(sorted.begin(), sorted.end());
  const double bound = sorted[sorted.size() / 2];
  int left = 0;
  auto expect = [&](const std::vector<double>& areas, double with, std::size_t first) {
    for (std::size_t i = 0; i < areas.size(); ++i) {
      const double r = reference[first + i];
      SCOPED_TRACE("direction " + std::to_string(first + i) + ", reference area " + std::to_string(r));
      if (areas[i] == infinity) {
        ++left;
        EXPECT_GT(r, with);
      } else {
        EXPECT_NEAR(areas[i], r, 1e-9 * r + 1e-12);
      }
    }
  };
  expect(insertion_detail::hidden_areas(sight, region, samples, ds, infinity), infinity, 0);
  expect(insertion_detail::hidden_areas(sight, region, samples, ds, bound), bound, 0);
  for (std::size_t i = 0; i < ds.size(); ++i)
    expect(insertion_detail::hidden_areas(sight, region, samples, {ds[i]}, bound), bound, i);
  EXPECT_TRUE(std::any_of(reference.begin(), reference.end(), [](double r) { return r > 0.0; }));
  return left;
}

TEST(Insertion, TheSearchHidesWhatEverySegmentTestedAgainstEveryBoneFaceHides) {
  // A regular grid (exact coordinates; segments along its grid lines and through its vertices) with a
  // ball above it, one resting on it and one near the end of the segments' 20 mm, seen along
  // axis-aligned, diagonal and random directions; then the labial surface of a real maxilla scan
  // against its whole bone, along random directions.
  const TriangleMesh plane = test::make_height_field(0, 32, 0, 32, 32, [](double, double) { return 0.0; });
  const TriangleMesh bone = joined(
      joined(joined(plane, test::make_icosphere(4.0, 3, Vec3(16, 16, 8))), test::make_icosphere(3.0, 3, Vec3(8, 8, 3))),
      test::make_icosphere(2.0, 3, Vec3(24, 24, 17)));
  const AabbTree tree(bone);
  std::vector<Vec3> ds = {Vec3(0, 0, -1), Vec3(1, 0, -1).normalized(), Vec3(1, 1, -2).normalized(),
                          Vec3(0, -1, -2).normalized(), Vec3(1, 0, 0)};
  std::mt19937 random(7);
  std::uniform_real_distribution<double> spread(-0.6, 0.6);
  for (int k = 0; k < 4; ++k) ds.push_back(Vec3(spread(random), spread(random), -1.0).normalized());
  const int left = expect_areas_of_every_face(tree, plane, insertion_detail::samples_of(plane, 0.0, 1), ds) +
                   expect_areas_of_every_face(tree, plane, insertion_detail::samples_of(plane, 0.4, 1), ds);

  const CaseFile c = read_case(test::examples_dir() + "/cases/maxilla-labial-auto.json");
  const TriangleMesh maxilla = read_mesh(c.bone);
  const TemplateOptions o = test::case_options(c);
  const MeshTopology topology(maxilla);
  CurveOptions curve_options;
  curve_options.max_snap_distance = o.max_snap_distance;
  curve_options.also_index = o.inside;
  CutOptions cut_options;
  cut_options.inside = o.inside;
  const TriangleMesh region =
      cut_region(topology, trace_surface_curve(topology, o.boundary_points, curve_options), cut_options).region;
  const AabbTree maxilla_tree(maxilla);
  const std::vector<insertion_detail::Sample> samples = insertion_detail::samples_of(region, 0.0, 5);
  std::vector<Vec3> around;
  for (int k = 0; k < 5; ++k) around.push_back(Vec3(spread(random), 1.0, spread(random)).normalized());
  expect_areas_of_every_face(maxilla_tree, region, samples, around);
  EXPECT_GT(left, 0); // the bound is put to use
}

TEST(Insertion, RefusesAZeroDirectionAndSpacing) {
  const TriangleMesh sphere = test::make_icosphere(10.0, 2);
  const AabbTree tree(sphere);
  EXPECT_THROW(undercut(tree, sphere, Vec3::Zero(), 0.5), InvalidInput);
  EXPECT_THROW(undercut(tree, sphere, Vec3(0, 0, std::nan("")), 0.5), InvalidInput);
  EXPECT_THROW(undercut(tree, sphere, Vec3(0, 0, 1), 0.0), InvalidInput);
}

} // namespace
} // namespace st
