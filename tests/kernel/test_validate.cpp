// The solid check counts what makes a mesh unprintable: border, non-manifold and inconsistently
// oriented edges, each where it is, on a closed sphere made open, doubled or turned.

#include "helpers.h"

#include "st/core/aabb_tree.h"
#include "st/core/closest_point.h"
#include "st/core/errors.h"
#include "st/boolean/triangle_intersection.h"
#include "st/core/topology.h"
#include "st/io/mesh_io.h"
#include "st/validate/validate.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <random>
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

// The solid check's table of corners answers every half-edge as MeshTopology::edge_uses does, on
// meshes with holes, turned, doubled and overlapping faces and faces with a repeated corner (left out
// by both).
TEST(SolidCheck, CornerTableUsesEdgesAsTheTopologyDoes) {
  const std::vector<TriangleMesh> meshes = test::awkward_meshes();
  for (const TriangleMesh& mesh : meshes) {
    const auto repeats = [&](Index f) {
      const Triangle& t = mesh.triangles[f];
      return t[0] == t[1] || t[1] == t[2] || t[2] == t[0];
    };
    const MeshTopology topology(mesh);
    const CornerTable table(topology, repeats);
    for (Index h = 0; h < 3 * mesh.face_count(); ++h) {
      if (repeats(h / 3)) continue;
      const MeshTopology::EdgeUses a = topology.edge_uses(h, repeats), b = table.edge_uses(h);
      EXPECT_EQ(a.reverse, b.reverse) << h;
      EXPECT_EQ(a.same, b.same) << h;
      EXPECT_EQ(a.opposite, b.opposite) << h;
      EXPECT_EQ(a.lowest, b.lowest) << h;
    }
  }
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
    // A tree over the surface from the caller: the same search.
    const AabbTree tree(sphere);
    const DistanceStats given = distances_to_surface(points, sphere, {}, &tree);
    EXPECT_EQ(given.min, plain.min) << off;
    EXPECT_EQ(given.max, plain.max) << off;
    EXPECT_EQ(given.mean, plain.mean) << off;
  }
  const TriangleMesh copy = sphere;
  const AabbTree other(copy);
  EXPECT_THROW(distances_to_surface(sphere.positions, sphere, {}, &other), InvalidInput);
  EXPECT_THROW(distances_to_surface(sphere.positions, sphere, std::vector<Index>{0, 1}), InvalidInput);
  std::vector<Index> beyond(sphere.vertex_count(), sphere.vertex_count());
  EXPECT_THROW(distances_to_surface(sphere.positions, sphere, beyond), InvalidInput);
  // A surface none of whose faces has finite corners has no distance to give: refused, by name.
  TriangleMesh unreadable = sphere;
  for (Vec3& q : unreadable.positions) q.x() = std::numeric_limits<double>::quiet_NaN();
  const std::string message = test::invalid_input_of([&] { (void)distances_to_surface({Vec3::Zero()}, unreadable); });
  EXPECT_NE(message.find("finite corners"), std::string::npos) << message;
}

// The points are searched in space-filling-curve order and each search is bounded by the previous
// point's: the distances are still each point's exact one, and their sum is taken in the points' own
// order (per 1024 points, then over those sums), the same bits as every face tried in turn. Points in
// a random order, on vertices, on edges and off the surface; a point that is not a number is refused.
TEST(DistancesToSurface, AnyOrderOfPointsGivesEachItsClosestFace) {
  const TriangleMesh sphere = make_icosphere(10.0, 3);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Vec3> points;
  for (Index f = 0; f < sphere.face_count(); f += 3) {
    const Triangle& t = sphere.triangles[f];
    points.push_back(sphere.positions[t[0]]);                                  // on a vertex
    points.push_back(0.5 * (sphere.positions[t[1]] + sphere.positions[t[2]])); // on an edge
    points.push_back(Vec3(unit(random), unit(random), unit(random)) * 14.0);   // anywhere near
  }
  std::shuffle(points.begin(), points.end(), random);
  ASSERT_GT(points.size(), 1024u); // more than one chunk
  const DistanceStats stats = distances_to_surface(points, sphere);
  double least = std::numeric_limits<double>::infinity(), most = 0.0, sum = 0.0, chunk = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    double best = std::numeric_limits<double>::infinity();
    for (Index f = 0; f < sphere.face_count(); ++f) {
      const Triangle& t = sphere.triangles[f];
      const Vec3 q =
          closest_point_on_triangle(points[i], sphere.positions[t[0]], sphere.positions[t[1]], sphere.positions[t[2]]);
      best = std::min(best, (points[i] - q).squaredNorm());
    }
    best = std::sqrt(best);
    least = std::min(least, best);
    most = std::max(most, best);
    chunk += best;
    if ((i + 1) % 1024 == 0 || i + 1 == points.size()) {
      sum += chunk;
      chunk = 0.0;
    }
  }
  EXPECT_EQ(stats.count, points.size());
  EXPECT_EQ(stats.min, least);
  EXPECT_EQ(stats.max, most);
  EXPECT_EQ(stats.mean, sum / static_cast<double>(points.size()));
  EXPECT_EQ(stats.min, 0.0); // the points on vertices
  points[17].y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(distances_to_surface(points, sphere), InvalidInput);
}

// A cube of n x n squares a side (corners welded), flat faces: the coplanar neighbours a fold makes.
TriangleMesh subdivided_cube(int n) {
  TriangleMesh out;
  std::map<std::array<double, 3>, Index> index;
  auto add_side = [&](const std::function<Vec3(double, double)>& map) {
    const TriangleMesh side = test::make_grid_patch(n, 0.0, 1.0, 0.0, 1.0, map);
    for (const Triangle& t : side.triangles) {
      Triangle w;
      for (int k = 0; k < 3; ++k) {
        const Vec3& p = side.positions[t[k]];
        const auto [it, added] = index.emplace(std::array<double, 3>{p.x(), p.y(), p.z()}, out.vertex_count());
        if (added) out.positions.push_back(p);
        w[k] = it->second;
      }
      out.triangles.push_back(w);
    }
  };
  // Each side's normal, d/du x d/dv, points out of the unit cube.
  add_side([](double u, double v) { return Vec3(v, u, 0.0); });
  add_side([](double u, double v) { return Vec3(u, v, 1.0); });
  add_side([](double u, double v) { return Vec3(u, 0.0, v); });
  add_side([](double u, double v) { return Vec3(v, 1.0, u); });
  add_side([](double u, double v) { return Vec3(0.0, v, u); });
  add_side([](double u, double v) { return Vec3(1.0, u, v); });
  return out;
}

// The pairs of faces that cross, by testing every pair.
std::size_t crossing_pairs(const TriangleMesh& mesh) {
  std::size_t count = 0;
  for (Index a = 0; a < mesh.face_count(); ++a)
    for (Index b = a + 1; b < mesh.face_count(); ++b) {
      const Triangle &ta = mesh.triangles[a], &tb = mesh.triangles[b];
      const std::array<Vec3, 3> pa{mesh.positions[ta[0]], mesh.positions[ta[1]], mesh.positions[ta[2]]};
      const std::array<Vec3, 3> pb{mesh.positions[tb[0]], mesh.positions[tb[1]], mesh.positions[tb[2]]};
      count += mesh_triangles_intersect(ta, pa, tb, pb) ? 1 : 0;
    }
  return count;
}

// The check passes over the pairs of faces around a corner whose fan is a height field; everything
// else it tests. Its count equals testing every pair, on a sphere and a flat-faced cube, with corners
// pushed through the surface, folded over their fans (in the cube's plane too: coplanar overlaps),
// dragged onto a neighbour (exact positions) and moved at random.
TEST(SolidCheck, CountsTheCrossingsThatTestingEveryPairFinds) {
  SolidOptions all;
  all.max_reported = std::numeric_limits<std::size_t>::max();
  std::mt19937 rng(5);
  int with_crossings = 0;
  for (const TriangleMesh& base : {make_icosphere(10.0, 3), subdivided_cube(8)}) {
    const TriangleMesh topology_copy = base;
    const MeshTopology topology(topology_copy);
    const std::vector<Vec3> normals = vertex_normals(base);
    const BoundingBox box = bounding_box(base);
    for (int trial = 0; trial < 12; ++trial) {
      TriangleMesh mesh = base;
      std::uniform_int_distribution<Index> pick(0, base.vertex_count() - 1);
      const Index v = pick(rng);
      const Index w = base.triangles[topology.faces_of(v)[0]][0] == v ? base.triangles[topology.faces_of(v)[0]][1]
                                                                      : base.triangles[topology.faces_of(v)[0]][0];
      const Vec3 along = base.positions[w] - base.positions[v];
      switch (trial % 4) {
      case 0: mesh.positions[v] -= 1.5 * box.size().maxCoeff() * normals[v]; break; // through the surface
      case 1: mesh.positions[v] += 2.5 * along; break;                              // folded over its fan
      case 2: mesh.positions[v] = base.positions[w]; break;                         // onto a neighbour
      default: {
        std::normal_distribution<double> jitter(0.0, 0.02 * box.size().maxCoeff());
        for (Vec3& p : mesh.positions) p += Vec3(jitter(rng), jitter(rng), jitter(rng));
      }
      }
      const SolidReport r = check_solid(mesh, all);
      if (r.degenerate_triangles > 0) continue; // the check stops before the pairs then
      const std::size_t expected = crossing_pairs(mesh);
      EXPECT_EQ(r.self_intersections, expected) << "trial " << trial << ", " << r.summary();
      with_crossings += expected > 0;
    }
  }
  EXPECT_GE(with_crossings, 8); // the trials do make crossings
  // A fan whose every face turns the same way about its centre but which winds around it twice,
  // climbing and coming back down: its two layers cross.
  TriangleMesh twice;
  twice.positions.push_back(Vec3::Zero());
  constexpr int kAround = 9; // 80 degrees a face
  for (int i = 0; i < kAround; ++i) {
    const double angle = 4.0 * std::numbers::pi * i / kAround;
    const double radius = 1.0 + 0.1 * (i % 3);
    twice.positions.emplace_back(radius * std::cos(angle), radius * std::sin(angle), 0.3 * std::cos(0.5 * angle));
  }
  for (Index i = 0; i < kAround; ++i) twice.triangles.push_back({0, 1 + i, 1 + (i + 1) % kAround});
  const std::size_t layered = crossing_pairs(twice);
  EXPECT_GT(layered, 0u);
  EXPECT_EQ(check_solid(twice, all).self_intersections, layered);
  EXPECT_EQ(check_solid(subdivided_cube(8)).self_intersections, 0u);
  EXPECT_TRUE(check_solid(subdivided_cube(8)).valid()) << check_solid(subdivided_cube(8)).summary();
}

// The crossing pairs by testing every pair whose boxes overlap (a tree's pairs, nothing passed over).
std::size_t crossing_pairs_in_tree(const TriangleMesh& mesh) {
  const AabbTree tree(mesh);
  return tree
      .overlapping_pairs([&](Index a, Index b) {
        const Triangle &ta = mesh.triangles[a], &tb = mesh.triangles[b];
        return mesh_triangles_intersect(ta, {mesh.positions[ta[0]], mesh.positions[ta[1]], mesh.positions[ta[2]]}, tb,
                                        {mesh.positions[tb[0]], mesh.positions[tb[1]], mesh.positions[tb[2]]});
      })
      .size();
}

// The check passes over whole patches whose faces all turn one way in an axis projection and whose
// border projects to a simple polygon (embedded_patch.h). A ramp whose every face turns the same way
// seen from above, one and a half turns around an axis, tilted one way across the first turn and the
// other way across the last half: its layers cross along a circle, and only their borders (a spiral,
// whose projection crosses itself) tell. Both exact (a regular grid, the crossing along grid lines)
// and moved at random; then real scans with crossings of their own, a slit disc, a ring cut open and
// a fine cube with corners pushed through: the same count as testing every pair of overlapping boxes.
TEST(SolidCheck, PassesOverOnlyPatchesThatCannotCrossThemselves) {
  SolidOptions all;
  all.max_reported = std::numeric_limits<std::size_t>::max();
  for (const bool jitter : {false, true}) {
    std::mt19937 rng(11);
    std::normal_distribution<double> noise(0.0, 1e-3);
    const TriangleMesh ramp =
        test::make_grid_patch(120, 0.0, 3.0 * std::numbers::pi, -1.0, 1.0, [&](double angle, double across) {
          const double r = 10.0 + across;
          const Vec3 p(r * std::cos(angle), r * std::sin(angle), std::cos(0.5 * angle) * across);
          return jitter ? Vec3(p + Vec3(noise(rng), noise(rng), noise(rng))) : p;
        });
    const std::size_t expected = crossing_pairs_in_tree(ramp);
    EXPECT_GT(expected, 0u) << "jitter " << jitter;
    EXPECT_EQ(check_solid(ramp, all).self_intersections, expected) << "jitter " << jitter;
  }
  for (const char* name : {"maxilla_dentition_ct_crop", "vertebrae_lumbar_L2-L5_ssm_mean"}) {
    const TriangleMesh scan = read_mesh(test::examples_dir() + "/meshes/" + name + ".stl.gz");
    const std::size_t expected = crossing_pairs_in_tree(scan);
    EXPECT_GT(expected, 0u) << name;
    EXPECT_EQ(check_solid(scan, all).self_intersections, expected) << name;
  }
  // A curved disc slit from its border to its centre, the slit's two sides on separate vertices at the
  // same places: its faces touch across the slit, and the border loop runs along both sides of it
  // (collinear edges that overlap, not a simple polygon).
  constexpr int kSlit = 16;
  TriangleMesh slit = test::make_grid_patch(2 * kSlit, -1.0, 1.0, -1.0, 1.0,
                                            [](double u, double v) { return Vec3(u, v, 0.2 * (u * u + v * v)); });
  std::map<Index, Index> copy; // grid vertex on the slit -> its copy below it
  for (int i = 0; i < kSlit; ++i) {
    const Index v = static_cast<Index>(kSlit * (2 * kSlit + 1) + i);
    copy[v] = slit.vertex_count();
    slit.positions.push_back(slit.positions[v]);
  }
  for (Triangle& t : slit.triangles) {
    const Vec3 centre = (slit.positions[t[0]] + slit.positions[t[1]] + slit.positions[t[2]]) / 3.0;
    if (centre.x() < 0.0 && centre.y() < 0.0)
      for (Index& v : t)
        if (const auto it = copy.find(v); it != copy.end()) v = it->second;
  }
  const std::size_t across = crossing_pairs_in_tree(slit);
  EXPECT_GT(across, 0u);
  EXPECT_EQ(check_solid(slit, all).self_intersections, across);
  // A curved ring cut open along a radius, the cut's two sides on separate vertices at the same places:
  // one border loop whose two cut sides lie on each other, apart along the loop (no fold at a corner).
  const TriangleMesh ring = test::make_grid_patch(32, 0.0, 2.0 * std::numbers::pi, 0.5, 1.0, [](double a, double r) {
    const double angle = a >= 2.0 * std::numbers::pi ? 0.0 : a; // the cut's far side exactly on the near one
    return Vec3(r * std::cos(angle), r * std::sin(angle), 0.2 * r * r);
  });
  const std::size_t along_cut = crossing_pairs_in_tree(ring);
  EXPECT_GT(along_cut, 0u);
  EXPECT_EQ(check_solid(ring, all).self_intersections, along_cut);
  TriangleMesh not_a_number = make_icosphere(10.0, 4); // a corner with no place is in no patch
  not_a_number.positions[7].y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(check_solid(not_a_number, all).valid());
  const TriangleMesh cube = subdivided_cube(40);
  EXPECT_TRUE(check_solid(cube).valid());
  std::mt19937 rng(3);
  std::uniform_int_distribution<Index> pick(0, cube.vertex_count() - 1);
  const std::vector<Vec3> normals = vertex_normals(cube);
  for (int trial = 0; trial < 4; ++trial) {
    TriangleMesh pushed = cube;
    for (int k = 0; k <= trial; ++k) {
      const Index v = pick(rng);
      pushed.positions[v] -= 0.2 * normals[v]; // through the cube's side, into its inside
    }
    const std::size_t expected = crossing_pairs_in_tree(pushed);
    EXPECT_EQ(check_solid(pushed, all).self_intersections, expected) << "trial " << trial;
  }
}

} // namespace
} // namespace st

namespace st {

// A long sliver (a side of a prism, one face from end to end, tilted) has a box that spans hundreds of
// small faces': the check pairs it only with the faces its plane can meet (AabbTree::overlapping_pairs'
// slabs). The count is that of testing every pair: the prism through a fine plate (crossings), and per
// side small faces at exact places, every coordinate a dyadic fraction: one lying in the side's plane
// over it, one with a corner on it and the others off it, ones parallel to it a 2^-40 and a 2^-10 of
// its normal off it; then all of it moved at random.
TEST(SolidCheck, PairsLongSliversAsTestingEveryPairDoes) {
  SolidOptions all;
  all.max_reported = std::numeric_limits<std::size_t>::max();
  for (const bool jitter : {false, true}) {
    TriangleMesh mesh =
        test::make_grid_patch(24, -3.0, 3.0, -3.0, 3.0, [](double u, double v) { return Vec3(u, v, 0.0); });
    const auto add = [&](const Vec3& a, const Vec3& b, const Vec3& c) {
      const Index first = mesh.vertex_count();
      mesh.positions.insert(mesh.positions.end(), {a, b, c});
      mesh.triangles.push_back({first, first + 1, first + 2});
    };
    const int ring[8][2] = {{2, 1}, {1, 2}, {-1, 2}, {-2, 1}, {-2, -1}, {-1, -2}, {1, -2}, {2, -1}};
    const auto corner = [&](int i, double z) { return Vec3(ring[i % 8][0] + 0.5 * z, ring[i % 8][1], z); };
    for (int i = 0; i < 8; ++i) {
      const Vec3 a = corner(i, -4.0), b = corner(i + 1, -4.0), c = corner(i + 1, 4.0), d = corner(i, 4.0);
      add(a, b, c);
      add(a, c, d);
      const Vec3 u = (b - a) / 4.0, v = (c - a) / 8.0, n = u.cross(v); // exact
      const Vec3 at = a + 2.0 * u + 3.0 * v;                           // inside face (a, b, c)
      add(at, at + u, at + v);
      add(at + n, at + n + u, at);
      for (const int power : {-40, -10}) {
        const Vec3 off = at + std::ldexp(1.0, power) * n;
        add(off, off + u, off + v);
      }
    }
    if (jitter) {
      std::mt19937 rng(5);
      std::normal_distribution<double> noise(0.0, 1e-3);
      for (Vec3& p : mesh.positions) p += Vec3(noise(rng), noise(rng), noise(rng));
    }
    const std::size_t expected = crossing_pairs(mesh);
    EXPECT_GE(expected, 16u) << "jitter " << jitter;
    EXPECT_EQ(check_solid(mesh, all).self_intersections, expected) << "jitter " << jitter;
  }
}

// A caller building the tree beside the check hands it over when asked: the same report as with the
// tree given or built by the check, asked for once, after the topology (not at all for a mesh whose
// faces are degenerate: the check stops before the pairs).
TEST(SolidCheck, AsksForTheTreeOnceWhenItComesFromBeside) {
  for (const TriangleMesh& mesh : {make_icosphere(10.0, 3), subdivided_cube(6)}) {
    const AabbTree tree(mesh);
    int asked = 0;
    SolidOptions beside;
    beside.tree_source = [&]() -> const AabbTree& {
      ++asked;
      return tree;
    };
    const SolidReport from_beside = check_solid(mesh, beside);
    EXPECT_EQ(asked, 1);
    EXPECT_EQ(from_beside.summary(), check_solid(mesh).summary());
    SolidOptions given;
    given.tree = &tree;
    EXPECT_EQ(from_beside.summary(), check_solid(mesh, given).summary());
  }
}

// Distances to a closed polyline read near each point only are those over all its segments: points
// on its vertices, along its segments, near it and far from it (beyond the rings read), a polyline
// with repeated points and one of a single point.
TEST(DistancesToPolyline, AreTheNearestOfAllSegments) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (const int size : {1, 2, 7, 200, 1500}) {
    std::vector<Vec3> poly;
    for (int i = 0; i < size; ++i) {
      const double a = 2.0 * std::numbers::pi * i / size;
      poly.emplace_back(20.0 * std::cos(a), 14.0 * std::sin(a), 3.0 * std::sin(5.0 * a) + 0.2 * unit(rng));
    }
    if (size > 7) poly[5] = poly[4];
    std::vector<Vec3> points;
    for (int i = 0; i < 400; ++i) {
      const Vec3& a = poly[i % size];
      const Vec3& b = poly[(i + 1) % size];
      const double t = 0.5 + 0.5 * unit(rng);
      const double off = i % 4 == 0 ? 0.0 : i % 4 == 1 ? 1e-3 : i % 4 == 2 ? 0.5 : 40.0;
      points.push_back(i % 9 == 0 ? a : Vec3(a + t * (b - a) + off * Vec3(unit(rng), unit(rng), unit(rng))));
    }
    const DistanceStats s = distances_to_polyline(points, poly);
    double min = std::numeric_limits<double>::infinity(), max = 0.0, sum = 0.0;
    for (const Vec3& p : points) {
      double best = std::numeric_limits<double>::infinity();
      for (int k = 0; k < size; ++k) {
        const Vec3 &a = poly[k], &b = poly[(k + 1) % size], ab = b - a;
        const double len2 = ab.squaredNorm();
        const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
        best = std::min(best, (p - (a + t * ab)).norm());
      }
      min = std::min(min, best);
      max = std::max(max, best);
      sum += best;
    }
    EXPECT_EQ(s.count, points.size());
    EXPECT_EQ(s.min, min) << size;
    EXPECT_EQ(s.max, max) << size;
    EXPECT_EQ(s.mean, sum / static_cast<double>(points.size())) << size;
  }
  EXPECT_EQ(distances_to_polyline({}, {Vec3::Zero()}).count, 0u);
  EXPECT_TRUE(std::isinf(distances_to_polyline({Vec3::Zero()}, {}).min));
}

} // namespace st
