// Boundary curve and cut: smooth cut through triangles, sides decided by topology, clear errors.

#include "helpers.h"

#include "st/design/cut.h"
#include "st/core/errors.h"
#include "st/design/surface_curve.h"
#include "st/core/topology.h"

#include <numbers>
#include <optional>

using namespace st;
using namespace st::test;

namespace {

std::vector<Vec3> circle_on_sphere(double radius, double polar, int n, double phase = 0.1) {
  std::vector<Vec3> pts;
  for (int i = 0; i < n; ++i) {
    const double a = phase + 2.0 * std::numbers::pi * i / n;
    pts.emplace_back(radius * std::sin(polar) * std::cos(a), radius * std::sin(polar) * std::sin(a),
                     radius * std::cos(polar));
  }
  return pts;
}

} // namespace

TEST(Cut, SphereCapAreaMatchesAnalyticValue) {
  const double r = 10.0, polar = std::numbers::pi / 3.0;
  const TriangleMesh sphere = make_icosphere(r, 5);
  const MeshTopology topology(sphere);
  const SurfaceCurve curve = trace_surface_curve(topology, circle_on_sphere(r, polar, 12));
  const CutResult cap = cut_region(topology, curve);
  const double expected = 2.0 * std::numbers::pi * r * r * (1.0 - std::cos(polar));
  EXPECT_NEAR(cap.area, expected, 0.01 * expected);
  // The rim runs along the circle: every rim vertex at the circle's height.
  for (Index v : cap.rim) EXPECT_NEAR(cap.region.positions[v].z(), r * std::cos(polar), 0.02 * r);
  // One disc: a single border loop, no holes.
  const MeshTopology cap_topology(cap.region);
  EXPECT_EQ(border_loops(cap.region, cap_topology.all_opposites()).size(), 1u);
}

TEST(Cut, KeepsTheSideHoldingTheInsidePoint) {
  const double r = 10.0, polar = std::numbers::pi / 3.0;
  const TriangleMesh sphere = make_icosphere(r, 4);
  const MeshTopology topology(sphere);
  const SurfaceCurve curve = trace_surface_curve(topology, circle_on_sphere(r, polar, 8));
  CutOptions o;
  o.inside = Vec3(0, 0, -r); // the big side
  const CutResult big = cut_region(topology, curve, o);
  const double expected = 2.0 * std::numbers::pi * r * r * (1.0 + std::cos(polar));
  EXPECT_NEAR(big.area, expected, 0.01 * expected);
}

// With an inside point only its side is flooded (after a walk to the curve finds which); the region
// must be the one the two sides' race gives: the same faces in the same order, the same rim.
TEST(Cut, InsidePointGivesTheRegionOfTheRace) {
  const double r = 10.0, polar = std::numbers::pi / 3.0;
  const TriangleMesh sphere = make_icosphere(r, 5);
  const TriangleMesh grid = make_height_field(-10, 10, -10, 10, 40, [](double x, double y) { return 0.02 * x * y; });
  for (const TriangleMesh* mesh : {&sphere, &grid}) {
    const MeshTopology topology(*mesh);
    const bool on_sphere = mesh == &sphere;
    std::vector<Vec3> pts = circle_on_sphere(r, polar, 12);
    if (!on_sphere)
      for (Vec3& p : pts) p = Vec3(0.6 * p.x(), 0.6 * p.y(), 0.02 * 0.36 * p.x() * p.y());
    // Inside points: off the surface over the middle, and exactly on a vertex of the mesh; the curve
    // indexes the faces around them too, as the design's does, so that the walk starts from their own.
    const Vec3 middle = on_sphere ? Vec3(0.0, 0.0, r + 0.3) : Vec3(0.1, -0.05, 0.4);
    Index vertex = 0;
    for (Index v = 0; v < mesh->vertex_count(); ++v)
      if ((mesh->positions[v] - middle).norm() < (mesh->positions[vertex] - middle).norm()) vertex = v;
    CutResult raced;
    for (const Vec3& inside : {middle, mesh->positions[vertex]}) {
      CurveOptions curve_options;
      curve_options.also_index = inside;
      const SurfaceCurve curve = trace_surface_curve(topology, pts, curve_options);
      raced = cut_region(topology, curve); // the smaller side, the two sides taking turns
      CutOptions o;
      o.inside = inside;
      const CutResult walked = cut_region(topology, curve, o);
      EXPECT_EQ(walked.region.triangles, raced.region.triangles);
      EXPECT_EQ(walked.region.positions, raced.region.positions);
      EXPECT_EQ(walked.rim, raced.rim);
    }
    // The other side: the two regions make up the surface.
    const SurfaceCurve curve = trace_surface_curve(topology, pts);
    CutOptions o;
    o.inside = on_sphere ? Vec3(0.0, 0.0, -r) : Vec3(-9.5, 9.5, 0.02 * -9.5 * 9.5);
    o.require_closed_region = on_sphere; // the grid's other side holds its open border
    const CutResult other = cut_region(topology, curve, o);
    EXPECT_NEAR(other.area + raced.area, surface_area(*mesh), 1e-9 * surface_area(*mesh));
  }
}

TEST(Cut, BorderIsSmoothNotAlongMeshEdges) {
  // A coarse plane: the rim of a circle cut must lie on the circle, not zig-zag along edges.
  const TriangleMesh plane = make_height_field(-10, 10, -10, 10, 20, [](double, double) { return 0.0; });
  const MeshTopology topology(plane);
  std::vector<Vec3> pts;
  for (int i = 0; i < 24; ++i) {
    const double a = 2.0 * std::numbers::pi * i / 24 + 0.05;
    pts.emplace_back(5.0 * std::cos(a), 5.0 * std::sin(a), 0.0);
  }
  const SurfaceCurve curve = trace_surface_curve(topology, pts);
  const CutResult disc = cut_region(topology, curve);
  double max_dev = 0.0;
  for (Index v : disc.rim) max_dev = std::max(max_dev, std::abs(disc.region.positions[v].head<2>().norm() - 5.0));
  EXPECT_LT(max_dev, 0.01); // a path along mesh edges would deviate by up to half an edge (0.5 mm)
  EXPECT_NEAR(disc.area, std::numbers::pi * 25.0, 0.01 * std::numbers::pi * 25.0);
  EXPECT_GT(disc.rim.size(), 30u);
}

TEST(Cut, LoopAroundAHandleDoesNotSeparate) {
  // A torus: a loop around the tube does not enclose a region.
  TriangleMesh torus;
  const int nu = 48, nv = 24;
  const double big = 10.0, small = 3.0;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * std::numbers::pi * i / nu, v = 2 * std::numbers::pi * j / nv;
      torus.positions.emplace_back((big + small * std::cos(v)) * std::cos(u), (big + small * std::cos(v)) * std::sin(u),
                                   small * std::sin(v));
    }
  auto id = [&](int i, int j) { return static_cast<Index>(((i + nu) % nu) * nv + (j + nv) % nv); };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      torus.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      torus.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  const MeshTopology topology(torus);
  std::vector<Vec3> pts;
  const double u = 0.13;
  for (int k = 0; k < 8; ++k) {
    const double v = 2 * std::numbers::pi * k / 8 + 0.05;
    pts.emplace_back((big + small * std::cos(v)) * std::cos(u), (big + small * std::cos(v)) * std::sin(u),
                     small * std::sin(v));
  }
  const SurfaceCurve curve = trace_surface_curve(topology, pts);
  // Without an inside point, and with one (whose side alone is flooded then).
  for (const std::optional<Vec3>& inside : {std::optional<Vec3>{}, std::optional<Vec3>{Vec3(-big, 0.0, small)}}) {
    CutOptions o;
    o.inside = inside;
    try {
      cut_region(topology, curve, o);
      FAIL() << "a loop around the torus tube must be refused";
    } catch (const GeometryError& e) {
      EXPECT_NE(std::string(e.what()).find("does not separate"), std::string::npos) << e.what();
    }
  }
}

TEST(Cut, LoopRunningIntoAnOpenBorderIsRefused) {
  // An open plane patch: a loop that leaves the patch runs into its border.
  const TriangleMesh plane = make_height_field(-5, 5, -5, 5, 10, [](double, double) { return 0.0; });
  const MeshTopology topology(plane);
  CurveOptions o;
  EXPECT_THROW(
      {
        const SurfaceCurve curve = trace_surface_curve(topology, {{-4, -4, 0}, {6, -4, 0}, {6, 4, 0}, {-4, 4, 0}}, o);
        cut_region(topology, curve);
      },
      GeometryError);
}

TEST(Cut, RegionWithAHoleIsRefused) {
  TriangleMesh plane = make_height_field(-10, 10, -10, 10, 20, [](double, double) { return 0.0; });
  // Punch a hole in the middle: drop the two triangles of the centre quad.
  std::vector<Triangle> kept;
  for (const Triangle& t : plane.triangles) {
    Vec3 c = (plane.positions[t[0]] + plane.positions[t[1]] + plane.positions[t[2]]) / 3.0;
    if (c.head<2>().norm() > 0.8) kept.push_back(t);
  }
  plane.triangles = kept;
  const MeshTopology topology(plane);
  std::vector<Vec3> pts;
  for (int i = 0; i < 8; ++i) {
    const double a = 2.0 * std::numbers::pi * i / 8 + 0.05;
    pts.emplace_back(6.0 * std::cos(a), 6.0 * std::sin(a), 0.0);
  }
  const SurfaceCurve curve = trace_surface_curve(topology, pts);
  CutOptions o;
  o.inside = Vec3(3, 0, 0);
  try {
    cut_region(topology, curve, o);
    FAIL() << "a region containing a hole must be refused";
  } catch (const GeometryError& e) {
    EXPECT_NE(std::string(e.what()).find("hole"), std::string::npos) << e.what();
  }
}

TEST(Curve, BadControlPointsAreRefused) {
  const TriangleMesh sphere = make_icosphere(10.0, 3);
  const MeshTopology topology(sphere);
  EXPECT_THROW(trace_surface_curve(topology, {{10, 0, 0}, {0, 10, 0}}), InvalidInput);
  EXPECT_THROW(trace_surface_curve(topology, {{10, 0, 0}, {0, 10, 0}, {0, 0, std::nan("")}}), InvalidInput);
  EXPECT_THROW(trace_surface_curve(topology, {{10, 0, 0}, {0, 10, 0}, {0, 0, 30}}), InvalidInput); // 20 mm off
  EXPECT_THROW(trace_surface_curve(topology, {{10, 0, 0}, {10, 0, 0}, {0, 0, 10}}), InvalidInput);
}

TEST(Curve, SelfCrossingLoopIsRefused) {
  const TriangleMesh plane = make_height_field(-10, 10, -10, 10, 30, [](double, double) { return 0.0; });
  const MeshTopology topology(plane);
  // A bow tie: 0 -> 1 -> 2 -> 3 crosses itself in the middle.
  const std::vector<Vec3> bow{{-6, -6, 0}, {6, 6, 0}, {6, -6, 0}, {-6, 6, 0}};
  EXPECT_THROW(
      {
        const SurfaceCurve curve = trace_surface_curve(topology, bow);
        cut_region(topology, curve);
      },
      GeometryError);
}

TEST(Curve, SplinePassesThroughControlPoints) {
  const std::vector<Vec3> pts{{0, 0, 0}, {10, 0, 0}, {10, 10, 0}, {0, 10, 0}};
  const auto s = closed_catmull_rom(pts, 0.5);
  for (const Vec3& p : pts) {
    double best = 1e9;
    for (const Vec3& q : s) best = std::min(best, (p - q).norm());
    EXPECT_LT(best, 1e-12);
  }
  EXPECT_GT(s.size(), 70u);
}

TEST(Curve, NoiseIslandNearAControlPointIsIgnored) {
  // A small loose piece (as CT noise leaves) sits right where the user clicked, 1 mm off the bone:
  // the point must still snap onto the bone, and the cut be the same as without the piece.
  const double r = 10.0, polar = std::numbers::pi / 3.0;
  TriangleMesh mesh = make_icosphere(r, 5);
  auto pts = circle_on_sphere(r, polar, 12);
  const Vec3 at = pts[0] * (r + 1.0) / r;
  const TriangleMesh island = make_icosphere(0.4, 1, at);
  const Index offset = mesh.vertex_count();
  mesh.positions.insert(mesh.positions.end(), island.positions.begin(), island.positions.end());
  for (const Triangle& t : island.triangles) mesh.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  pts[0] = at;
  const MeshTopology topology(mesh);
  const SurfaceCurve curve = trace_surface_curve(topology, pts);
  EXPECT_LT(curve.control_faces[0], make_icosphere(r, 5).face_count()); // on the sphere
  const CutResult cap = cut_region(topology, curve);
  const double expected = 2.0 * std::numbers::pi * r * r * (1.0 - std::cos(polar));
  EXPECT_NEAR(cap.area, expected, 0.015 * expected);
}
