// The guide inspection behind the Validate panel: a designed guide passes; a guide pushed into the
// bone, and a body whose bores were never cut, fail by name.

#include "helpers.h"

#include "st/io/case_file.h"
#include "st/guide/inspect.h"
#include "st/io/mesh_io.h"
#include "st/design/template_design.h"

#include <gtest/gtest.h>

#include <algorithm>

using namespace st;

namespace {

struct Designed {
  CaseFile c;
  TriangleMesh bone;
  TemplateResult r;
};

const Designed& maxilla() {
  static const Designed d = [] {
    Designed x;
    x.c = read_case(st::test::examples_dir() + "/cases/maxilla-implants.json");
    x.bone = read_mesh(x.c.bone);
    x.r = design_template(x.bone, st::test::case_options(x.c));
    return x;
  }();
  return d;
}

} // namespace

TEST(Inspect, DesignedGuidePasses) {
  const Designed& d = maxilla();
  const GuideInspection g = inspect_guide(d.r.shell, d.bone, d.c.tubes, d.c.clearance);
  EXPECT_TRUE(g.passed()) << g.summary();
  ASSERT_EQ(g.vertex_distance.size(), d.r.shell.positions.size());
  ASSERT_EQ(g.bores.size(), 5u);
  for (const BoreCheck& b : g.bores) {
    EXPECT_TRUE(b.open) << b.name << " " << b.margin;
    EXPECT_LT(b.margin, 0.05) << b.name << ": the bore's wall is where the plan puts it";
  }
  // The inner surface lies on the bone, the outer at the thickness (within the field's resolution).
  EXPECT_GT(g.seated_vertices, 500u);
  const double far = *std::max_element(g.vertex_distance.begin(), g.vertex_distance.end());
  EXPECT_GT(far, d.c.thickness * 0.9);
  EXPECT_EQ(g.vertices_in_bone, 0u);
}

TEST(Inspect, GuideInTheBoneAndBlockedBoresAreNamed) {
  const Designed& d = maxilla();
  // The body before the tubes: the bores were never cut.
  const GuideInspection body = inspect_guide(d.r.body, d.bone, d.c.tubes, d.c.clearance);
  ASSERT_EQ(body.bores.size(), 5u);
  std::size_t blocked = 0;
  for (const BoreCheck& b : body.bores) blocked += !b.open;
  EXPECT_EQ(blocked, 5u) << body.summary();
  EXPECT_FALSE(body.passed());
  EXPECT_NE(body.summary().find("blocked"), std::string::npos);
  // The guide pushed 0.5 mm into the bone along the first tube's axis.
  TriangleMesh pushed = d.r.shell;
  for (Vec3& p : pushed.positions) p += 0.5 * d.c.tubes[0].direction;
  const GuideInspection in_bone = inspect_guide(pushed, d.bone, d.c.tubes, d.c.clearance);
  EXPECT_GT(in_bone.vertices_in_bone, 100u);
  EXPECT_GT(in_bone.deepest_in_bone, 0.2);
  EXPECT_LT(in_bone.deepest_in_bone, 0.5 + 1e-4); // the guide is stored in float
  EXPECT_NEAR(*std::min_element(in_bone.vertex_distance.begin(), in_bone.vertex_distance.end()),
              -in_bone.deepest_in_bone, 1e-12);
  EXPECT_FALSE(in_bone.passed());
}

// A point just outside a sharp crest, whose closest bone point is the crest's edge: outside on both
// sides (one face's normal alone calls one side inside).
TEST(Inspect, OutsideASharpCrestOnBothSides) {
  TriangleMesh ridge; // a thin triangular prism along y, its crest at z = 1
  for (double y : {0.0, 1.0})
    for (const Vec3& p : {Vec3(-0.1, y, 0.0), Vec3(0.1, y, 0.0), Vec3(0.0, y, 1.0)}) ridge.positions.push_back(p);
  ridge.triangles = {{0, 1, 2}, {3, 5, 4}, {0, 4, 1}, {0, 3, 4}, {1, 5, 2}, {1, 4, 5}, {2, 3, 0}, {2, 5, 3}};
  ASSERT_GT(check_solid(ridge).volume, 0.0);
  for (double side : {-1.0, 1.0}) {
    TriangleMesh probe = st::test::make_icosphere(0.02, 1, Vec3(0.15 * side, 0.5, 1.3));
    const GuideInspection g = inspect_guide(probe, ridge, {}, 0.0);
    EXPECT_EQ(g.vertices_in_bone, 0u) << "side " << side;
    EXPECT_GT(*std::min_element(g.vertex_distance.begin(), g.vertex_distance.end()), 0.0);
  }
  // And a point really inside, near the crest, is inside.
  const GuideInspection inside = inspect_guide(st::test::make_icosphere(0.005, 1, Vec3(0.0, 0.5, 0.9)), ridge, {}, 0.0);
  EXPECT_GT(inside.vertices_in_bone, 0u);
}

TEST(Inspect, SegmentTriangleDistance) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_DOUBLE_EQ(segment_triangle_distance({0.2, 0.2, -1}, {0.2, 0.2, 1}, a, b, c), 0.0);
  EXPECT_NEAR(segment_triangle_distance({0.2, 0.2, 1}, {0.2, 0.2, 2}, a, b, c), 1.0, 1e-15);
  EXPECT_NEAR(segment_triangle_distance({2, -1, 0.5}, {2, 1, 0.5}, a, b, c), std::hypot(1.0, 0.5), 1e-12);
  EXPECT_NEAR(segment_triangle_distance({3, 0, 0}, {3, 0, 0}, a, b, c), 2.0, 1e-15); // a point
}
