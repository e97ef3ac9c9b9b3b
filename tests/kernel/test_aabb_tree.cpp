// The tree's answers equal a brute-force search over every triangle: closest points, first ray hits
// (to a rounding error where a ray meets an edge), the triangles in a box and the overlapping pairs. Its boxes are kept
// in single precision, rounded outwards; the meshes here sit 100 km from the origin, where a float's step (8 mm) is far
// coarser than their 0.14-0.17 mm triangles, so a box rounded the wrong way would lose triangles.

#include "helpers.h"

#include "st/core/aabb_tree.h"
#include "st/core/closest_point.h"
#include "st/core/ray_triangle.h"
#include "st/io/mesh_io.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <span>
#include <stdexcept>
#include <utility>
#include <vector>

namespace st {
namespace {

using test::make_grid_patch;
using test::make_icosphere;

const Vec3 kFar(1.0e5, -2.5e5 + 0.3, 7.0e4 + 0.7);

// A sphere of 1280 faces (edges about 0.14 mm) and a wavy grid of regular cells, both far away.
std::vector<TriangleMesh> meshes() {
  TriangleMesh grid = make_grid_patch(24, -2.0, 2.0, -2.0, 2.0, [](double u, double v) {
    return Vec3(u, v, 0.3 * std::sin(2.0 * u) * std::cos(1.5 * v));
  });
  for (Vec3& p : grid.positions) p += kFar;
  return {make_icosphere(1.0, 3, kFar), grid};
}

// The same and a flat grid (faces whose boxes have no thickness).
std::vector<TriangleMesh> meshes_and_flat() {
  std::vector<TriangleMesh> all = meshes();
  all.push_back(make_grid_patch(10, 0.0, 5.0, 0.0, 5.0, [](double u, double v) { return Vec3(u, v, 1.0); }));
  return all;
}

// The distance from p to the nearest of `faces` of `mesh` (all of them when empty), triangle by triangle.
double brute_distance(const TriangleMesh& mesh, std::span<const Index> faces, const Vec3& p) {
  double best = std::numeric_limits<double>::infinity();
  const auto meet = [&](const Triangle& t) {
    best = std::min(
        best,
        (closest_point_on_triangle(p, mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]) - p).norm());
  };
  if (faces.empty())
    for (const Triangle& t : mesh.triangles) meet(t);
  for (const Index f : faces) meet(mesh.triangles[f]);
  return best;
}

std::vector<Vec3> probes(const TriangleMesh& mesh, int count, unsigned seed) {
  std::mt19937 rng(seed);
  const BoundingBox box = bounding_box(mesh).inflated(0.5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3> out;
  for (int i = 0; i < count; ++i) out.push_back(box.min + Vec3(u(rng), u(rng), u(rng)).cwiseProduct(box.size()));
  // And the corners themselves: a point on a vertex is at distance 0 from several faces.
  for (Index v = 0; v < mesh.vertex_count(); v += 37) out.push_back(mesh.positions[v]);
  return out;
}

TEST(AabbTree, ClosestPointsEqualBruteForceFarFromTheOrigin) {
  for (const TriangleMesh& mesh : meshes()) {
    const AabbTree tree(mesh);
    for (const Vec3& p : probes(mesh, 300, 7)) {
      const double best = brute_distance(mesh, {}, p);
      const std::optional<ClosestPoint> found = tree.closest_point(p);
      ASSERT_TRUE(found.has_value());
      EXPECT_EQ(found->distance, best) << "at (" << p.transpose() << ")";
    }
  }
}

// The slab bounds only pass over nodes and faces: the closest points over them are the brute force's, for
// points off the surface along its normals (where the slabs open few nodes), random points, points
// on vertices, on a wavy grid, a flat one (slabs of no thickness), a sphere and a real scan.
TEST(AabbTree, ClosestPointsOverSlabsEqualBruteForce) {
  std::vector<TriangleMesh> all = meshes();
  all.push_back(make_grid_patch(30, -3.0, 3.0, -3.0, 3.0, [](double u, double v) { return Vec3(u, v, 2.0); }));
  all.push_back(read_mesh(test::examples_dir() + "/meshes/vertebrae_lumbar_L2-L5_ssm_mean.stl.gz"));
  for (const TriangleMesh& mesh : all) {
    const AabbTree tree(mesh);
    const AabbTree::Slabs slabs = tree.slabs();
    // About 1400 points on the small meshes, 240 on the scan of 131k faces (the brute force is the cost).
    const bool large = mesh.face_count() > 20000;
    std::vector<Vec3> points = probes(mesh, large ? 40 : 200, 11);
    const std::vector<Vec3> normals = vertex_normals(mesh);
    const Index along = large ? 50 : 300;
    for (Index v = 0; v < mesh.vertex_count(); v += std::max<Index>(1, mesh.vertex_count() / along))
      for (const double off : {0.05, 0.3, 2.5, -0.3}) points.push_back(mesh.positions[v] + off * normals[v]);
    // Searches from the top, from the previous point's closest face (near, as where the fit uses it),
    // and from a face anywhere: the same distance.
    Index previous = kInvalidIndex;
    std::mt19937 random(5);
    for (const Vec3& p : points) {
      const double best = brute_distance(mesh, {}, p);
      const Index anywhere = std::uniform_int_distribution<Index>(0, mesh.face_count() - 1)(random);
      for (const Index start : {kInvalidIndex, previous, anywhere}) {
        const auto found = tree.closest_point(p, std::numeric_limits<double>::infinity(), slabs, start);
        ASSERT_TRUE(found.has_value());
        EXPECT_EQ(found->distance, best) << "at (" << p.transpose() << ") from face " << start;
        previous = found->face;
      }
      // Bounded by the distance itself (as the fit's searches nearly are): found all the same.
      const auto bounded = tree.closest_point(p, best * (1.0 + 1e-9), slabs, anywhere);
      ASSERT_TRUE(bounded.has_value());
      EXPECT_EQ(bounded->distance, best);
    }
  }
  // A tree over some of the faces: each of its faces has a leaf from which the parents lead to the
  // root, the others none; searches from any face, held or not, give the brute force over its faces.
  const TriangleMesh& sphere = all[0];
  std::vector<Index> half;
  for (Index f = 0; f < sphere.face_count(); f += 2) half.push_back(f);
  const AabbTree part(sphere, half);
  const AabbTree::Slabs part_slabs = part.slabs();
  for (Index f = 0; f < sphere.face_count(); ++f) {
    Index node = part_slabs.leaf_of[f], depth = 0;
    ASSERT_EQ(node == kInvalidIndex, f % 2 == 1) << "face " << f;
    while (node != kInvalidIndex && node != 0 && depth++ < 64) node = part_slabs.parent[node];
    if (f % 2 == 0) EXPECT_EQ(node, 0U) << "face " << f << ": its leaf does not lead to the root";
  }
  for (const Vec3& p : probes(sphere, 50, 3)) {
    const auto top = part.closest_point(p, std::numeric_limits<double>::infinity(), part_slabs);
    ASSERT_TRUE(top.has_value());
    const double best = brute_distance(sphere, half, p);
    EXPECT_EQ(top->distance, best);
    for (const Index start : {Index{0}, Index{1}, sphere.face_count() - 1, sphere.face_count() + 7})
      EXPECT_EQ(part.closest_point(p, std::numeric_limits<double>::infinity(), part_slabs, start)->distance,
                top->distance);
    EXPECT_EQ(top->face % 2, 0U);
  }
  // A tree keeps a reference to its mesh: `all` outlives the trees. Slabs of another tree are refused,
  // even of a tree over as many faces of the same mesh.
  const AabbTree other(all[0]);
  EXPECT_THROW((void)AabbTree(all[1]).closest_point(Vec3::Zero(), 1.0, other.slabs()), std::logic_error);
  std::vector<Index> odd;
  for (Index f = 1; f < sphere.face_count(); f += 2) odd.push_back(f);
  const AabbTree odd_part(sphere, odd);
  EXPECT_THROW((void)odd_part.closest_point(Vec3::Zero(), 1.0, part_slabs), std::logic_error);
}

TEST(AabbTree, FirstHitsAndBoxesEqualBruteForceFarFromTheOrigin) {
  for (const TriangleMesh& mesh : meshes()) {
    const AabbTree tree(mesh);
    const Vec3 centre = bounding_box(mesh).center();
    for (const Vec3& p : probes(mesh, 200, 11)) {
      // The ray from the probe through the middle: its first hit.
      const Vec3 d = (centre - p).normalized();
      std::optional<double> first;
      for (const Triangle& t : mesh.triangles) {
        const auto hit = ray_triangle(p, d, mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
        if (hit && hit->t >= 0.0 && (!first || hit->t < *first)) first = hit->t;
      }
      const std::optional<RayHit> found = tree.first_hit(p, d);
      ASSERT_EQ(found.has_value(), first.has_value()) << "ray from (" << p.transpose() << ")";
      // Where the ray meets an edge the two faces' hits differ by rounding; the tree may report either.
      if (first) EXPECT_NEAR(found->t, *first, 1e-9);
      // The faces in a box of 0.3 mm about the probe: none missed.
      BoundingBox box;
      box.extend(p);
      box = box.inflated(0.15);
      std::set<Index> in_box;
      tree.for_each_in_box(box, [&](Index f) { in_box.insert(f); });
      for (Index f = 0; f < mesh.face_count(); ++f)
        if (triangle_box(mesh, f).overlaps(box)) EXPECT_TRUE(in_box.count(f)) << "face " << f;
    }
  }
}

// faces_meeting_box's codes reject exactly the faces whose boxes miss the box: random boxes, and boxes whose
// sides pass through the mesh's vertices (a face touching the box by a corner, an edge or a side meets it).
TEST(MeshBoxes, FacesMeetingABoxAreExactlyTheFacesWhoseBoxesMeetIt) {
  for (const TriangleMesh& mesh : meshes_and_flat()) {
    std::mt19937 rng(7);
    std::uniform_int_distribution<Index> vertex(0, mesh.vertex_count() - 1);
    const std::vector<Vec3> probe = probes(mesh, 60, 5);
    std::vector<BoundingBox> boxes;
    for (std::size_t i = 0; i + 1 < probe.size(); i += 2) {
      BoundingBox b;
      b.extend(probe[i]);
      b.extend(probe[i + 1]);
      boxes.push_back(b);
      BoundingBox on; // corners on two vertices: sides through them
      on.extend(mesh.positions[vertex(rng)]);
      on.extend(mesh.positions[vertex(rng)]);
      boxes.push_back(on);
    }
    BoundingBox flat_side; // one vertex's coordinates: a degenerate box
    flat_side.extend(mesh.positions[vertex(rng)]);
    boxes.push_back(flat_side);
    boxes.push_back(BoundingBox{}); // empty: no face
    for (const BoundingBox& box : boxes) {
      std::vector<Index> expected;
      for (Index f = 0; f < mesh.face_count(); ++f)
        if (triangle_box(mesh, f).overlaps(box)) expected.push_back(f);
      EXPECT_EQ(faces_meeting_box(mesh, box), expected);
    }
    // Several boxes at once (five to a pass: one pass, two, three, all; all of them hold the empty
    // one): the faces meeting any of them.
    std::shuffle(boxes.begin(), boxes.end(), rng);
    for (const std::size_t count : {std::size_t{2}, std::size_t{5}, std::size_t{6}, std::size_t{11}, boxes.size()}) {
      const std::span<const BoundingBox> some(boxes.data(), std::min(count, boxes.size()));
      std::vector<Index> expected;
      for (Index f = 0; f < mesh.face_count(); ++f)
        if (std::any_of(some.begin(), some.end(),
                        [&](const BoundingBox& b) { return triangle_box(mesh, f).overlaps(b); }))
          expected.push_back(f);
      EXPECT_EQ(faces_meeting_boxes(mesh, some), expected) << some.size() << " boxes";
    }
  }
}

// Boxes in frames of their own (tilted, as about a tube's axis): a face is left out exactly when its
// corners all lie beyond one side of every box, so every face with a point in a box is kept; one pass
// (one, five boxes) and two (seven).
TEST(MeshBoxes, FacesNearFramedBoxesKeepEveryFaceWithAPointInOne) {
  for (const TriangleMesh& mesh : meshes_and_flat()) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    std::uniform_int_distribution<Index> vertex(0, mesh.vertex_count() - 1);
    const double size = bounding_box(mesh).diagonal();
    std::vector<FramedBox> boxes;
    for (int i = 0; i < 7; ++i) {
      FramedBox b;
      b.axes = Eigen::Quaterniond(unit(rng), unit(rng), unit(rng), unit(rng)).normalized().toRotationMatrix();
      b.centre = mesh.positions[vertex(rng)];
      b.half =
          Vec3(0.05 + 0.1 * std::abs(unit(rng)), 0.05 + 0.1 * std::abs(unit(rng)), 0.3 * std::abs(unit(rng))) * size;
      boxes.push_back(b);
    }
    auto inside = [](const FramedBox& b, const Vec3& p) {
      return ((b.axes * (p - b.centre)).cwiseAbs().array() <= b.half.array()).all();
    };
    for (const std::size_t count : {std::size_t{1}, std::size_t{5}, std::size_t{7}}) {
      const std::span<const FramedBox> some(boxes.data(), count);
      const std::vector<Index> found = faces_near_framed_boxes(mesh, some);
      std::vector<Index> expected;
      for (Index f = 0; f < mesh.face_count(); ++f) {
        const Triangle& t = mesh.triangles[f];
        bool near = false;
        for (const FramedBox& b : some) {
          std::array<Vec3, 3> q;
          for (int k = 0; k < 3; ++k) q[k] = b.axes * (mesh.positions[t[k]] - b.centre);
          bool beyond = false;
          for (int k = 0; k < 3; ++k)
            beyond = beyond || (q[0][k] < -b.half[k] && q[1][k] < -b.half[k] && q[2][k] < -b.half[k]) ||
                     (q[0][k] > b.half[k] && q[1][k] > b.half[k] && q[2][k] > b.half[k]);
          near = near || !beyond;
          // A point of the face in the box: the face is kept.
          const Vec3 centroid = (mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) / 3.0;
          if (inside(b, centroid) || inside(b, mesh.positions[t[0]]))
            EXPECT_TRUE(std::binary_search(found.begin(), found.end(), f)) << "face " << f;
        }
        if (near) expected.push_back(f);
      }
      EXPECT_EQ(found, expected) << count << " boxes";
      EXPECT_LT(found.size(), mesh.face_count()) << "boxes over the whole mesh test nothing";
    }
  }
}

TEST(AabbTree, OverlappingPairsHoldEveryPairOfTouchingBoxes) {
  for (const TriangleMesh& mesh : meshes()) {
    const AabbTree tree(mesh);
    std::set<std::pair<Index, Index>> found;
    for (auto [a, b] : tree.overlapping_pairs()) found.insert(std::minmax(a, b));
    std::size_t expected = 0;
    for (Index a = 0; a < mesh.face_count(); ++a)
      for (Index b = a + 1; b < mesh.face_count(); ++b)
        if (triangle_box(mesh, a).overlaps(triangle_box(mesh, b))) {
          ++expected;
          EXPECT_TRUE(found.count({a, b})) << "faces " << a << " and " << b;
        }
    EXPECT_GE(found.size(), expected);
  }
}

} // namespace
} // namespace st
