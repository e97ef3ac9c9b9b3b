// The offset's two contourings (st/design/offset.h, step 4): marching cubes, the default, against
// marching tetrahedra, certified. Closed offsets (front_only false) so that check_solid decides
// exactly: closed, 2-manifold, outward, no self-intersecting pair. Patches with creases (a step, a
// V), on grid-aligned positions (CAD-like), and random bumpy ones at random resolutions.

#include "helpers.h"

#include "st/core/mesh.h"
#include "st/design/offset.h"
#include "st/validate/validate.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <random>
#include <string>

namespace {

using st::TriangleMesh;
using st::Vec3;

st::OffsetResult offset(const TriangleMesh& patch, double distance, double h, bool tetrahedra) {
  st::OffsetOptions o;
  o.distance = distance;
  o.cell_size = h;
  o.front_only = false;
  o.tetrahedra = tetrahedra;
  return st::offset_surface(patch, o);
}

/// Both contourings of the same band: valid solids, the same volume within 0.5 %, the cubes' with
/// less than half the triangles.
void expect_cubes_like_tetrahedra(const TriangleMesh& patch, double distance, double h, const std::string& what) {
  const st::OffsetResult cubes = offset(patch, distance, h, false);
  const st::OffsetResult tets = offset(patch, distance, h, true);
  const st::SolidReport c = st::check_solid(cubes.surface);
  const st::SolidReport t = st::check_solid(tets.surface);
  EXPECT_TRUE(c.valid()) << what << ", cubes: " << c.summary();
  EXPECT_TRUE(t.valid()) << what << ", tetrahedra: " << t.summary();
  EXPECT_NEAR(c.volume, t.volume, 0.005 * t.volume) << what;
  EXPECT_LT(cubes.surface.face_count(), tets.surface.face_count() / 2) << what;
}

TriangleMesh rotated(TriangleMesh mesh, double ax, double ay) {
  const Eigen::Matrix3d r =
      (Eigen::AngleAxisd(ax, Vec3::UnitX()) * Eigen::AngleAxisd(ay, Vec3::UnitY())).toRotationMatrix();
  for (Vec3& p : mesh.positions) p = r * p;
  return mesh;
}

TEST(OffsetContour, CubesGiveTheTetrahedraSolidWithFewerTriangles) {
  // A flat square on grid-aligned positions (the thickness a whole number of cells), a V and a
  // step (concave creases where the offsets of two faces meet), and a wavy patch tilted.
  const TriangleMesh square = st::test::make_height_field(-8, 8, -8, 8, 16, [](double, double) { return 0.0; });
  const TriangleMesh vee = st::test::make_height_field(-8, 8, -8, 8, 32, [](double x, double) { return std::abs(x); });
  const TriangleMesh step =
      st::test::make_height_field(-8, 8, -8, 8, 32, [](double x, double) { return x < 0.0 ? 0.0 : 2.0; });
  const TriangleMesh wavy = st::test::make_height_field(
      -8, 8, -8, 8, 32, [](double x, double y) { return 2.0 * std::sin(x / 2.0) * std::cos(y / 3.0); });
  expect_cubes_like_tetrahedra(square, 2.5, 0.25, "square");
  expect_cubes_like_tetrahedra(vee, 2.0, 0.25, "V");
  expect_cubes_like_tetrahedra(step, 2.0, 0.25, "step");
  expect_cubes_like_tetrahedra(rotated(wavy, 0.3, -0.5), 2.0, 0.3, "wavy, tilted");
}

TEST(OffsetContour, RandomBumpyPatchesGiveValidSolids) {
  // ST_PROPERTY_CASES / 50 patches (default 20): sums of three random waves, some steep enough to
  // fold the offset into creases, at random resolutions, axis-aligned or tilted.
  int cases = 20;
  if (const char* env = std::getenv("ST_PROPERTY_CASES")) cases = std::max(4, std::atoi(env) / 50);
  std::mt19937 rng(20261202);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int c = 0; c < cases; ++c) {
    double amp[3], fx[3], fy[3], ph[3];
    for (int k = 0; k < 3; ++k) {
      amp[k] = 0.3 + 1.5 * unit(rng);
      fx[k] = 0.2 + 1.2 * unit(rng);
      fy[k] = 0.2 + 1.2 * unit(rng);
      ph[k] = 6.3 * unit(rng);
    }
    const TriangleMesh bumpy = st::test::make_height_field(-6, 6, -6, 6, 36, [&](double x, double y) {
      double z = 0.0;
      for (int k = 0; k < 3; ++k) z += amp[k] * std::sin(fx[k] * x + ph[k]) * std::cos(fy[k] * y);
      return z;
    });
    const double h = 0.15 + 0.2 * unit(rng);
    const TriangleMesh patch = c % 2 ? rotated(bumpy, 2.0 * unit(rng), 2.0 * unit(rng)) : bumpy;
    const st::OffsetResult r = offset(patch, 2.0 + unit(rng), h, false);
    const st::SolidReport s = st::check_solid(r.surface);
    EXPECT_TRUE(s.valid()) << "patch " << c << " (h " << h << "): " << s.summary();
  }
}

} // namespace
