// Fixation pins (tubes of kind "pin", tube.h): the direction into the bone when none is planned, the
// counterbore for a screw's head as planned (radius and depth), bores open, paths that come within
// 1 mm of another bore reported, and the case keys; on a synthetic plate and on the tibia example.

#include "helpers.h"

#include "st/core/aabb_tree.h"
#include "st/core/errors.h"
#include "st/design/template_design.h"
#include "st/guide/inspect.h"
#include "st/guide/sleeve.h"
#include "st/io/case_file.h"
#include "st/io/mesh_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace st {
namespace {

using test::winding_number;

/// The least distance from the tube's axis, between heights z0 and z1, to the guide's surface.
double clear_radius(const TriangleMesh& guide, const AabbTree& tree, const TubeSpec& t, double z0, double z1) {
  const Vec3 a = tube_point(t, z0), b = tube_point(t, z1);
  BoundingBox box;
  box.extend(a);
  box.extend(b);
  double nearest = 1e300;
  tree.for_each_in_box(box.inflated(t.outer_radius + 5.0), [&](Index f) {
    const Triangle& q = guide.triangles[f];
    nearest = std::min(
        nearest, segment_triangle_distance(a, b, guide.positions[q[0]], guide.positions[q[1]], guide.positions[q[2]]));
  });
  return nearest;
}

/// Bore open along the whole axis, the counterbore as planned: clear to its radius over its depth
/// (rays out from the axis), with the sleeve's shoulder (material between bore and counterbore
/// radius) just below it. `slack`: what the Boolean operations report they may have moved.
void expect_pin_as_planned(const TriangleMesh& guide, const TubeSpec& t, const TubePlacement& p, double slack) {
  SCOPED_TRACE("tube " + t.name);
  const AabbTree tree(guide);
  EXPECT_GE(clear_radius(guide, tree, t, std::min(0.0, p.template_bottom), p.bore_top), t.inner_radius - 1e-5 - slack)
      << "the bore is not open";
  if (!t.counterbore) return;
  ASSERT_TRUE(p.counterbore_bottom.has_value());
  EXPECT_NEAR(*p.counterbore_bottom, p.sleeve_top - t.counterbore->depth, 1e-12);
  Vec3 u, v;
  orthonormal_frame(tube_axis(t), u, v);
  double narrowest = 1e300;
  for (int h = 0; h <= 10; ++h)
    for (int k = 0; k < 16; ++k) {
      const double z = *p.counterbore_bottom + 0.05 + (p.sleeve_top - 0.1 - *p.counterbore_bottom) * h / 10.0;
      const double a = 2.0 * std::numbers::pi * k / 16.0;
      if (const auto hit = tree.first_hit(tube_point(t, z), std::cos(a) * u + std::sin(a) * v, 0.0, 50.0))
        narrowest = std::min(narrowest, hit->t);
    }
  // The counterbore is circumscribed (its polygon's sides touch the circle): its corners lie beyond.
  EXPECT_GE(narrowest, t.counterbore->radius - 1e-5 - slack) << "the counterbore is narrower than planned";
  EXPECT_LT(narrowest, t.counterbore->radius + 0.02) << "the counterbore is wider than planned";
  const double shoulder = 0.5 * (t.inner_radius + t.counterbore->radius);
  const double wall = 0.5 * (t.counterbore->radius + t.outer_radius);
  for (int k = 0; k < 6; ++k) {
    const double a = 2.0 * std::numbers::pi * (k + 0.5) / 6.0;
    const Vec3 around = std::cos(a) * u + std::sin(a) * v;
    EXPECT_GT(winding_number(guide, tube_point(t, *p.counterbore_bottom - 0.2) + shoulder * around), 0.5)
        << "no shoulder under the counterbore";
    EXPECT_LT(winding_number(guide, tube_point(t, *p.counterbore_bottom + 0.2) + shoulder * around), 0.5)
        << "material in the counterbore";
    if (wall < t.outer_radius)
      EXPECT_GT(winding_number(guide, tube_point(t, p.sleeve_top - 0.2) + wall * around), 0.5)
          << "no sleeve wall around the counterbore";
  }
}

TubeSpec pin(const std::string& name, const Vec3& entry, double inner, double outer) {
  TubeSpec t;
  t.name = name;
  t.kind = TubeKind::pin;
  t.entry = entry;
  t.auto_direction = true;
  t.inner_radius = inner;
  t.outer_radius = outer;
  t.length = 8.0;
  t.offset = 2.0;
  return t;
}

TEST(Pins, PinsWithoutADirectionGoIntoTheBoneAndCounterboresAreAsPlanned) {
  auto height = [](double x, double y) { return 0.2 * x + 0.005 * y * y; };
  const TriangleMesh bone = test::make_height_field(-30, 30, -30, 30, 60, height);
  TemplateOptions o;
  o.boundary_points = {{-15, -15, 0}, {15, -15, 0}, {15, 15, 0}, {-15, 15, 0}};
  for (Vec3& q : o.boundary_points) q.z() = height(q.x(), q.y());
  o.thickness = 3.0;
  o.clearance = 0.1;
  TubeSpec wire = pin("wire", {-6, 0, height(-6, 0)}, 1.05, 2.25);
  TubeSpec screw = pin("screw", {6, 4, height(6, 4)}, 1.3, 3.0);
  screw.counterbore = Counterbore{2.2, 3.0};
  o.tubes = {wire, screw};
  const TemplateResult r = design_template(bone, o);
  test::expect_valid_solid(r.shell);
  EXPECT_EQ(r.solid.components, 1u);
  ASSERT_EQ(r.tubes.size(), 2u);
  // Into the bone: against the surface's normal there (the plane z = 0.2 x + 0.005 y^2).
  for (std::size_t i = 0; i < 2; ++i) {
    const Vec3 at = o.tubes[i].entry;
    const Vec3 normal = Vec3(-0.2, -0.01 * at.y(), 1.0).normalized();
    EXPECT_GT(r.tubes[i].direction.dot(-normal), std::cos(2.0 * std::numbers::pi / 180.0)) << o.tubes[i].name;
    EXPECT_EQ(r.tubes[i].kind, TubeKind::pin);
    EXPECT_TRUE(r.tubes[i].near.empty()) << r.tubes[i].near.front();
    TubeSpec built = o.tubes[i];
    built.direction = r.tubes[i].direction;
    expect_pin_as_planned(r.shell, built, r.tubes[i], r.max_perturbation + r.curve_tolerance);
  }
  write_stl(r.shell, test::output_dir() + "/pins-plate.stl");
}

TEST(Pins, TheTibiaExamplePinsItsWedgeWithPathsClearOfEachOther) {
  const CaseFile c = read_case(test::examples_dir() + "/cases/tibia-osteotomy.json");
  ASSERT_EQ(c.tubes.size(), 2u) << "a pin pair";
  const TriangleMesh bone = read_mesh(c.bone);
  const TemplateResult r = design_template(bone, st::test::case_options(c));
  test::expect_valid_solid(r.shell);
  for (std::size_t i = 0; i < c.tubes.size(); ++i) {
    EXPECT_EQ(c.tubes[i].kind, TubeKind::pin);
    EXPECT_TRUE(r.tubes[i].near.empty());
    expect_pin_as_planned(r.shell, c.tubes[i], r.tubes[i], r.max_perturbation + r.curve_tolerance);
  }
  // Paths at least 1 mm from the other bore, measured on the plan's axes to their planned depth.
  const TubeSpec &a = c.tubes[0], &b = c.tubes[1];
  EXPECT_GE(segment_segment_distance(tube_point(a, r.tubes[0].bore_top), tube_point(a, -a.depth),
                                     tube_point(b, r.tubes[1].bore_top), tube_point(b, -b.depth)) -
                a.inner_radius - b.inner_radius,
            1.0);
}

TEST(Pins, PathsWithinAMillimetreOfAnotherBoreAreReported) {
  const TriangleMesh bone = test::make_height_field(-30, 30, -30, 30, 30, [](double, double) { return 0.0; });
  TemplateOptions o;
  o.boundary_points = {{-15, -15, 0}, {15, -15, 0}, {15, 15, 0}, {-15, 15, 0}};
  o.thickness = 3.0;
  TubeSpec a = pin("a", {-5, 0, 0}, 1.0, 2.0);
  a.auto_direction = false;
  a.direction = Vec3(0.3, 0, -1).normalized(); // leans towards b: their paths meet 10 mm into the bone
  TubeSpec b = pin("b", {5, 0, 0}, 1.0, 2.0);
  b.auto_direction = false;
  b.direction = Vec3(-0.3, 0, -1).normalized();
  o.tubes = {a, b};
  const TemplateResult r = design_template(bone, o);
  ASSERT_EQ(r.tubes[0].near.size(), 1u);
  EXPECT_NE(r.tubes[0].near[0].find("tube 'b'"), std::string::npos);
  EXPECT_NE(r.tubes[1].near[0].find("tube 'a'"), std::string::npos);
}

TEST(Pins, CaseKeysForPinsReadWriteAndRefuse) {
  const std::string path = test::output_dir() + "/pins-case.json";
  auto text = [](const std::string& tube) {
    return std::string(R"({"format": "surgical-template-case/1", "bone": "b.stl",
      "boundary": {"points": [[0,0,0],[1,0,0],[0,1,0]]}, "template": {"thickness": 2}, "tubes": [)") +
           tube + "]}";
  };
  const CaseFile c = parse_case(text(R"({"name": "k", "kind": "pin", "entry": [1, 2, 3], "inner_radius": 1,
      "outer_radius": 2.5, "length": 8, "counterbore": {"radius": 1.8, "depth": 2}})"),
                                path);
  ASSERT_EQ(c.tubes.size(), 1u);
  EXPECT_EQ(c.tubes[0].kind, TubeKind::pin);
  EXPECT_TRUE(c.tubes[0].auto_direction) << "a pin without a direction goes into the bone where it is";
  ASSERT_TRUE(c.tubes[0].counterbore.has_value());
  EXPECT_DOUBLE_EQ(c.tubes[0].counterbore->radius, 1.8);
  const CaseFile back = parse_case(case_json(c, path), path);
  EXPECT_TRUE(back.tubes[0].auto_direction);
  EXPECT_EQ(back.tubes[0].kind, TubeKind::pin);
  EXPECT_DOUBLE_EQ(back.tubes[0].counterbore->depth, 2.0);
  auto refused = [&](const std::string& tube, const std::string& words) {
    try {
      parse_case(text(tube), path);
      ADD_FAILURE() << "accepted: " << tube;
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  const std::string sizes = R"("entry": [0,0,0], "inner_radius": 1, "outer_radius": 2, "length": 5)";
  refused("{" + sizes + "}", "tubes[0].direction: is required"); // a sleeve needs its direction
  refused("{" + sizes + R"(, "kind": "nail"})", "tubes[0].kind: must be \"sleeve\" or \"pin\"");
  refused("{" + sizes + R"(, "kind": "pin", "counterbore": {"radius": 0.5, "depth": 1}})",
          "tubes[0].counterbore.radius: must be > inner_radius");
  refused("{" + sizes + R"(, "kind": "pin", "counterbore": {"radius": 1.5}})",
          "tubes[0].counterbore.depth: is required");
}

TEST(Pins, APinWithoutDirectionOnAnEdgeIsRefusedByName) {
  // A knife edge: the faces around the entry face opposite ways.
  const TriangleMesh bone =
      test::make_height_field(-20, 20, -20, 20, 40, [](double x, double) { return -std::abs(x) * 5; });
  const AabbTree tree(bone);
  TubeSpec t = pin("edge", {0, 0, 0}, 1.0, 2.0);
  try {
    pin_direction(t, tree, 3.0);
    ADD_FAILURE() << "an edge gave a direction";
  } catch (const GeometryError& e) {
    EXPECT_NE(std::string(e.what()).find("tube 'edge'"), std::string::npos) << e.what();
  }
  t.entry = {0, 0, 50};
  EXPECT_THROW(pin_direction(t, tree, 3.0), GeometryError); // no bone near
}

} // namespace
} // namespace st
