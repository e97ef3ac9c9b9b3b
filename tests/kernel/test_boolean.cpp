// Boolean operations by corefinement: closed-form shapes whose volumes are known, contacts in special
// position, and bad operands.

#include "helpers.h"

#include "st/boolean/boolean.h"
#include "st/core/errors.h"
#include "st/guide/sleeve.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

namespace st {
namespace {

TriangleMesh make_box(const Vec3& lo, const Vec3& hi) {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i)
    m.positions.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
  // Outward faces, two triangles each.
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangles.push_back({Index(q[0]), Index(q[1]), Index(q[2])});
    m.triangles.push_back({Index(q[0]), Index(q[2]), Index(q[3])});
  }
  return m;
}

void expect_valid(const TriangleMesh& mesh, std::size_t components = 1) {
  const SolidReport r = check_solid(mesh);
  EXPECT_TRUE(r.valid()) << r.summary();
  EXPECT_EQ(r.components, components) << r.summary();
}

TEST(Boolean, OverlappingSpheresKeepTheVolumeIdentity) {
  const TriangleMesh a = test::make_icosphere(10.0, 3);
  const TriangleMesh b = test::make_icosphere(7.0, 3, Vec3(8.3, 1.1, -0.7));
  const double va = signed_volume(a), vb = signed_volume(b);
  const BooleanResult u = mesh_boolean(a, b, BooleanOp::Union);
  const BooleanResult i = mesh_boolean(a, b, BooleanOp::Intersection);
  const BooleanResult d = mesh_boolean(a, b, BooleanOp::Difference);
  expect_valid(u.mesh);
  expect_valid(i.mesh);
  expect_valid(d.mesh);
  const double vu = signed_volume(u.mesh), vi = signed_volume(i.mesh), vd = signed_volume(d.mesh);
  EXPECT_GT(vi, 0.05 * vb);
  // The pieces are the operands' own faces split exactly along one curve: the identities hold up to
  // the float32 rounding of the result.
  EXPECT_NEAR(vu + vi, va + vb, 1e-4 * (va + vb));
  EXPECT_NEAR(vd, va - vi, 1e-4 * va);
  EXPECT_GT(u.curve_segments, 50u);
}

TEST(Boolean, SleeveThroughASlabLeavesABore) {
  const TriangleMesh slab = make_box(Vec3(-10, -10, 0), Vec3(10, 10, 3));
  const Cylinder bore{Vec3(0.3, -0.2, -2.0), Vec3(0.1, 0.05, 1.0).normalized(), 1.2, 8.0};
  const TriangleMesh drill = cylinder_mesh(bore, 0.005);
  const BooleanResult r = mesh_boolean(slab, drill, BooleanOp::Difference);
  expect_valid(r.mesh);
  // Genus 1 now: V - E + F = 0.
  const std::size_t f = r.mesh.face_count(), e = 3 * f / 2;
  EXPECT_EQ(static_cast<long>(r.mesh.vertex_count()) - static_cast<long>(e) + static_cast<long>(f), 0);
  // Volume: the slab minus the prism's cross-section over the slab's height / cos(tilt).
  const int n = circle_segments(1.2, 0.005);
  const double polygon = 0.5 * n * 1.2 * 1.2 * std::sin(2.0 * std::numbers::pi / n);
  const double expected = 20.0 * 20.0 * 3.0 - polygon * 3.0 / bore.axis.normalized().z();
  EXPECT_NEAR(signed_volume(r.mesh), expected, 1e-3);
}

TEST(Boolean, SleeveOnASlabJoinsIt) {
  const TriangleMesh slab = make_box(Vec3(-10, -10, 0), Vec3(10, 10, 3));
  const TriangleMesh sleeve = cylinder_mesh({Vec3(1, 2, 1.5), Vec3::UnitZ(), 2.5, 6.0}, 0.01);
  const BooleanResult r = mesh_boolean(slab, sleeve, BooleanOp::Union);
  expect_valid(r.mesh);
  const double va = signed_volume(slab), vb = signed_volume(sleeve);
  EXPECT_NEAR(signed_volume(r.mesh), va + vb - vb * 1.5 / 6.0, 1e-3);
}

TEST(Boolean, CoplanarAndTouchingContactsAreResolved) {
  // Flush faces: the box's top is the cylinder's bottom plane; an edge along an edge.
  const TriangleMesh slab = make_box(Vec3(-5, -5, 0), Vec3(5, 5, 2));
  const TriangleMesh flush = cylinder_mesh({Vec3(0, 0, 2), Vec3::UnitZ(), 1.5, 3.0}, 0.01);
  const BooleanResult u = mesh_boolean(slab, flush, BooleanOp::Union);
  EXPECT_GT(u.attempts, 1);
  const SolidReport r = check_solid(u.mesh);
  EXPECT_TRUE(r.valid()) << r.summary();
  EXPECT_NEAR(signed_volume(u.mesh), signed_volume(slab) + signed_volume(flush), 1e-2);

  const TriangleMesh same_edge = make_box(Vec3(-5, -5, 0), Vec3(0, 0, 4));
  const BooleanResult d = mesh_boolean(slab, same_edge, BooleanOp::Difference);
  const SolidReport rd = check_solid(d.mesh);
  EXPECT_TRUE(rd.valid()) << rd.summary();
  EXPECT_NEAR(signed_volume(d.mesh), 10.0 * 10.0 * 2.0 - 5.0 * 5.0 * 2.0, 1e-2);
}

TEST(Boolean, ACornerCutOffCloserThanFloatResolvesIsNotRetried) {
  // A cube 600 mm from the origin (float ulp 6.1e-5 mm) whose top carries a needle face (4, 5, q),
  // q one ulp off the front edge; the other box's side plane crosses the needle 1 mm from its
  // corner 5, where it is a fifth of an ulp wide: the two crossings round to one point, which cuts
  // corner 5 off the needle. Handled as it is, at the first attempt, with no operand moved.
  TriangleMesh cube = make_box(Vec3(600, 600, 600), Vec3(610, 610, 610));
  const Index q = cube.vertex_count();
  cube.positions.emplace_back(605.0, 600.0 + std::ldexp(1.0, -14), 610.0);
  cube.triangles.erase(cube.triangles.begin() + 2, cube.triangles.begin() + 4); // the top quad 4 5 7 6
  for (const auto& [u, v] : {std::pair<Index, Index>{4, 5}, {5, 7}, {7, 6}, {6, 4}})
    cube.triangles.push_back({u, v, q});
  expect_valid(cube);
  const TriangleMesh box = make_box(Vec3(609, 596, 605), Vec3(620, 604.5, 615));
  const double overlap = 1.0 * 4.5 * 5.0;
  const BooleanResult u = mesh_boolean(cube, box, BooleanOp::Union);
  EXPECT_EQ(u.attempts, 1);
  expect_valid(u.mesh);
  EXPECT_NEAR(signed_volume(u.mesh), 1000.0 + 11.0 * 8.5 * 10.0 - overlap, 1e-3);
  const BooleanResult d = mesh_boolean(cube, box, BooleanOp::Difference);
  EXPECT_EQ(d.attempts, 1);
  expect_valid(d.mesh);
  EXPECT_NEAR(signed_volume(d.mesh), 1000.0 - overlap, 1e-3);
}

TEST(Boolean, DisjointAndNestedOperands) {
  const TriangleMesh a = test::make_icosphere(5.0, 2);
  const TriangleMesh far = test::make_icosphere(2.0, 2, Vec3(20, 0, 0));
  const TriangleMesh inner = test::make_icosphere(2.0, 2, Vec3(0.5, 0, 0));
  expect_valid(mesh_boolean(a, far, BooleanOp::Union).mesh, 2);
  EXPECT_EQ(mesh_boolean(a, far, BooleanOp::Intersection).mesh.face_count(), 0u);
  const BooleanResult nested = mesh_boolean(a, inner, BooleanOp::Union);
  EXPECT_EQ(nested.mesh.face_count(), a.face_count());
  const BooleanResult hollow = mesh_boolean(a, inner, BooleanOp::Difference);
  EXPECT_NEAR(signed_volume(hollow.mesh), signed_volume(a) - signed_volume(inner), 1e-3);
  EXPECT_EQ(check_solid(hollow.mesh).components, 2u);
}

TEST(Boolean, BadOperandsAreRefusedByName) {
  const TriangleMesh a = test::make_icosphere(5.0, 1);
  TriangleMesh open = a;
  open.triangles.pop_back();
  EXPECT_THROW(mesh_boolean(a, open, BooleanOp::Union), InvalidInput);
  try {
    mesh_boolean(open, a, BooleanOp::Union);
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("first operand"), std::string::npos) << e.what();
  }
  TriangleMesh nan = a;
  nan.positions[3].x() = std::nan("");
  EXPECT_THROW(mesh_boolean(a, nan, BooleanOp::Difference), InvalidInput);
  EXPECT_THROW(mesh_boolean(a, TriangleMesh{}, BooleanOp::Union), InvalidInput);
}

TEST(Boolean, RandomCylindersThroughASphere) {
  const TriangleMesh ball = test::make_icosphere(8.0, 3);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 40; ++k) {
    const Vec3 dir = Vec3(u(rng), u(rng), u(rng)).normalized();
    const Vec3 at = 6.0 * Vec3(u(rng), u(rng), u(rng));
    const Cylinder c{at - 10.0 * dir, dir, 0.5 + 1.5 * (u(rng) + 1.0), 20.0 * (0.3 + 0.5 * (u(rng) + 1.0))};
    const TriangleMesh tube = cylinder_mesh(c, 0.01);
    const BooleanResult un = mesh_boolean(ball, tube, BooleanOp::Union);
    const BooleanResult in = mesh_boolean(ball, tube, BooleanOp::Intersection);
    const SolidReport r = check_solid(un.mesh);
    ASSERT_TRUE(r.valid()) << "case " << k << ": " << r.summary();
    const double vu = signed_volume(un.mesh), vi = in.mesh.empty() ? 0.0 : signed_volume(in.mesh);
    EXPECT_NEAR(vu + vi, signed_volume(ball) + signed_volume(tube), 1e-3) << "case " << k;
  }
}

TEST(Boolean, FacesPassingWithinAnUlpOfAVertex) {
  // A box tilted at random whose top face passes within half a float ulp (3e-5 mm, 600 mm from the
  // origin) of the cube's corner (610, 600, 610): the curve points around that corner round onto it,
  // onto each other or next to it. Every union and intersection is valid and the volumes add up (to
  // 0.5 mm^3 of 2000: curve edges shorter than 256 ulp, 0.019 mm here, are collapsed, moving a vertex
  // by up to that); operations that still need an operand moved are counted (printed) and bounded
  // (were 96 of 200, before a point rounding onto a vertex was taken as that vertex).
  const TriangleMesh cube = make_box(Vec3(600, 600, 600), Vec3(610, 610, 610));
  const Vec3 corner(610, 600, 610);
  std::mt19937 rng(20261203);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int retried = 0;
  constexpr int kCases = 100;
  for (int k = 0; k < kCases; ++k) {
    const Eigen::AngleAxisd turn(0.5 * u(rng), Vec3(u(rng), u(rng), u(rng)).normalized());
    const Vec3 near = corner + 3e-5 * Vec3(u(rng), u(rng), u(rng));
    TriangleMesh box = make_box(Vec3(-5, -5, -10), Vec3(5, 5, 0));
    for (Vec3& p : box.positions) p = near + turn * (p - Vec3(1.3, -2.1, 0.0)); // a point of the top face
    const BooleanResult un = mesh_boolean(cube, box, BooleanOp::Union);
    const BooleanResult in = mesh_boolean(cube, box, BooleanOp::Intersection);
    retried += (un.attempts > 1) + (in.attempts > 1);
    const SolidReport r = check_solid(un.mesh);
    ASSERT_TRUE(r.valid()) << "case " << k << ": " << r.summary();
    const double vi = in.mesh.empty() ? 0.0 : signed_volume(in.mesh);
    EXPECT_NEAR(signed_volume(un.mesh) + vi, signed_volume(cube) + signed_volume(box), 0.5) << "case " << k;
  }
  std::printf("%d of %d operations retried with an operand moved\n", retried, 2 * kCases);
  EXPECT_LE(retried, 2 * kCases * 15 / 100);
}

TEST(Boolean, ResultLeftUncheckedIsTheCheckedOneOrFailsTheSolidCheck) {
  // A caller that checks the whole result (check_solid) may leave the faces near the curve unchecked
  // (check_result false, the design's guide) and redo the operation checked when its check fails: so
  // whatever the Boolean's own check would have rejected must fail check_solid. Boxes tilted at random
  // through a cube's corner within half a float ulp (as above), where rounding the curve points
  // folds faces: each unchecked result is the checked one, face for face, or fails check_solid.
  const TriangleMesh cube = make_box(Vec3(600, 600, 600), Vec3(610, 610, 610));
  const Vec3 corner(610, 600, 610);
  std::mt19937 rng(20261207);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  BooleanOptions unchecked;
  unchecked.check_result = false;
  int same = 0, refused = 0;
  for (int k = 0; k < 100; ++k) {
    const Eigen::AngleAxisd turn(0.5 * u(rng), Vec3(u(rng), u(rng), u(rng)).normalized());
    const Vec3 near = corner + 3e-5 * Vec3(u(rng), u(rng), u(rng));
    TriangleMesh box = make_box(Vec3(-5, -5, -10), Vec3(5, 5, 0));
    for (Vec3& p : box.positions) p = near + turn * (p - Vec3(1.3, -2.1, 0.0));
    for (BooleanOp op : {BooleanOp::Union, BooleanOp::Difference}) {
      const BooleanResult checked = mesh_boolean(cube, box, op);
      const BooleanResult free = mesh_boolean(cube, box, op, unchecked);
      if (free.mesh.positions == checked.mesh.positions && free.mesh.triangles == checked.mesh.triangles) {
        ++same;
        continue;
      }
      EXPECT_GT(checked.attempts, 1) << "case " << k << ": a result the check passed at once differs unchecked";
      const SolidReport r = check_solid(free.mesh);
      EXPECT_FALSE(r.valid()) << "case " << k << ": unchecked, a result the Boolean's check refuses passes check_solid";
      ++refused;
    }
  }
  std::printf("%d unchecked results as checked, %d refused by check_solid\n", same, refused);
  EXPECT_GT(refused, 0); // the cases reach what the Boolean's check catches
}

} // namespace
} // namespace st
