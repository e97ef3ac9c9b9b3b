// Undercut block-out and the removal check (issue 12) on a tooth standing on a plate: a post with a
// bulge (the crown's height of contour) as a surface of revolution, whose undercut, best direction
// and blocked-out volume are known in closed form.

#include "helpers.h"

#include "st/core/aabb_tree.h"
#include "st/core/float32.h"
#include "st/core/predicates.h"
#include "st/boolean/triangle_intersection.h"
#include "st/design/insertion.h"
#include "st/design/template_design.h"
#include "st/io/case_file.h"
#include "st/io/mesh_io.h"
#include "st/validate/removal.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace st {
namespace {

constexpr double kPi = std::numbers::pi;

/// The tooth's profile: radius at height z on the post (0 <= z <= 8): 3 mm, with a bulge of 1 mm
/// between z = 3 and z = 7, widest (4 mm) at z = 5.
double tooth_radius(double z) { return z > 3.0 && z < 7.0 ? 3.0 + std::sin(kPi * (z - 3.0) / 4.0) : 3.0; }

/// A surface of revolution about the z axis through the profile points (r, z), from the outer rim
/// inwards (the last point on the axis), `segments` around; normals away from the solid under it.
TriangleMesh revolve(const std::vector<std::array<double, 2>>& profile, int segments) {
  TriangleMesh m;
  const int n = static_cast<int>(profile.size());
  for (int i = 0; i + 1 < n; ++i)
    for (int j = 0; j < segments; ++j) {
      const double a = 2.0 * kPi * j / segments;
      m.positions.emplace_back(profile[i][0] * std::cos(a), profile[i][0] * std::sin(a), profile[i][1]);
    }
  m.positions.emplace_back(0.0, 0.0, profile.back()[1]);
  // As a mesh file holds it (float32): a guide at zero clearance then copies the bone exactly.
  round_to_float32(m);
  auto id = [segments](int i, int j) { return static_cast<Index>(i * segments + (j % segments)); };
  const Index centre = m.vertex_count() - 1;
  for (int i = 0; i + 1 < n; ++i)
    for (int j = 0; j < segments; ++j) {
      if (i + 2 == n) {
        m.triangles.push_back({id(i, j), id(i, j + 1), centre});
        continue;
      }
      m.triangles.push_back({id(i, j), id(i, j + 1), id(i + 1, j)});
      m.triangles.push_back({id(i, j + 1), id(i + 1, j + 1), id(i + 1, j)});
    }
  return m;
}

/// The plate (z = 0, radius 15 down to the post), the post and its bulge, the flat top at z = 8.
/// `plate_step`: the plate's ring spacing (0.25 puts a ring exactly under the bulge's widest ring).
TriangleMesh tooth_on_plate(double plate_step, int segments = 256) {
  std::vector<std::array<double, 2>> profile;
  for (double r = 15.0; r > 3.0 + 1e-9; r -= plate_step) profile.push_back({r, 0.0});
  for (int k = 0; k <= 80; ++k) {
    const double z = 0.1 * k;
    profile.push_back({tooth_radius(z), z});
  }
  for (int k = 1; k <= 12; ++k) profile.push_back({3.0 - 0.25 * k, 8.0});
  return revolve(profile, segments);
}

/// Hidden area along -z, in closed form: the bulge's lower half, the post under it (a wall in its
/// shadow) and the ring of plate the bulge shades.
double tooth_undercut_area() {
  double bulge = 0.0;
  const int steps = 20000;
  for (int k = 0; k < steps; ++k) {
    const double z = 3.0 + 2.0 * (k + 0.5) / steps;
    const double slope = kPi / 4.0 * std::cos(kPi * (z - 3.0) / 4.0);
    bulge += 2.0 * kPi * tooth_radius(z) * std::sqrt(1.0 + slope * slope) * (2.0 / steps);
  }
  return bulge + 2.0 * kPi * 3.0 * 3.0 + kPi * (16.0 - 9.0);
}

/// The volume under the bulge's widest ring down to the plate, outside the tooth.
double tooth_cavity_volume() {
  double v = 0.0;
  const int steps = 20000;
  for (int k = 0; k < steps; ++k) {
    const double z = 5.0 * (k + 0.5) / steps;
    const double r = tooth_radius(z);
    v += kPi * (16.0 - r * r) * (5.0 / steps);
  }
  return v;
}

/// The faces of the tooth and plate within 10 mm of the axis (their centres).
TriangleMesh tooth_region(const TriangleMesh& bone) {
  TriangleMesh region;
  region.positions = bone.positions;
  for (const Triangle& t : bone.triangles)
    if ((bone.positions[t[0]] + bone.positions[t[1]] + bone.positions[t[2]]).head<2>().norm() / 3.0 < 10.0)
      region.triangles.push_back(t);
  return region;
}

/// The template over the tooth, its border a circle of radius 10 on the plate.
TemplateOptions tooth_template(bool block_out) {
  TemplateOptions o;
  for (int k = 0; k < 12; ++k) {
    const double a = 2.0 * kPi * (k + 0.5) / 12.0;
    o.boundary_points.emplace_back(10.0 * std::cos(a), 10.0 * std::sin(a), 0.0);
  }
  o.inside = Vec3(0.0, 0.0, 8.0);
  o.thickness = 2.0;
  o.analyse_insertion = true;
  o.insertion = Vec3(0.0, 0.0, -1.0);
  o.block_out = block_out;
  return o;
}

TEST(BlockOut, UndercutOfAToothIsItsClosedFormArea) {
  const TriangleMesh bone = tooth_on_plate(0.3);
  const AabbTree tree(bone);
  const TriangleMesh region = tooth_region(bone);
  const Undercut u = undercut(tree, region, Vec3(0, 0, -1), 0.05);
  const double expected = tooth_undercut_area();
  EXPECT_NEAR(u.hidden_mm2, expected, 0.02 * expected);
}

TEST(BlockOut, UndercutOfAFinelyTessellatedToothSamplesEveryFewFacesAndKeepsItsArea) {
  // 1024 segments round: faces far smaller than a sample's share at 0.5 mm spacing, so every
  // stride-th face is sampled and the faces between are resolved near the hidden samples. The area
  // keeps to the closed form, and away from the zones' borders every face is classed as the closed
  // form classes it (hidden: the plate ring 3 < r < 4, the post, the bulge below its widest ring).
  const TriangleMesh bone = tooth_on_plate(0.3, 1024);
  const AabbTree tree(bone);
  const TriangleMesh region = tooth_region(bone);
  const double spacing = 0.5;
  ASSERT_GT(0.5 * spacing * spacing * static_cast<double>(region.face_count()) / surface_area(region), 10.0);
  const Undercut u = undercut(tree, region, Vec3(0, 0, -1), spacing);
  const double expected = tooth_undercut_area();
  EXPECT_NEAR(u.hidden_mm2, expected, 0.02 * expected);
  double wrong = 0.0, classed = 0.0;
  for (Index f = 0; f < region.face_count(); ++f) {
    const Triangle& t = region.triangles[f];
    const Vec3 c = (region.positions[t[0]] + region.positions[t[1]] + region.positions[t[2]]) / 3.0;
    const double r = c.head<2>().norm();
    bool hidden = false;
    if (c.z() < 1e-9) { // the plate
      if (std::abs(r - 3.0) < 0.35 || std::abs(r - 4.0) < 0.35) continue;
      hidden = r > 3.0 && r < 4.0;
    } else if (c.z() < 8.0 - 1e-9) { // the post and its bulge
      if (std::abs(c.z() - 5.0) < 0.15 || c.z() < 0.15) continue;
      hidden = c.z() < 5.0;
    }
    const double area = 0.5 * triangle_normal(region, f).norm();
    classed += area;
    if ((u.hidden[f] > 0.5f) != hidden) wrong += area;
  }
  EXPECT_GT(classed, 0.8 * surface_area(region));
  EXPECT_LT(wrong, 0.002 * classed);
}

TEST(BlockOut, ToothGuideComesOffOnlyWhenBlockedOut) {
  const TriangleMesh bone = tooth_on_plate(0.3, 128);
  // As the bone gives it, the guide wraps under the bulge and cannot come off.
  const TemplateResult copy = design_template(bone, tooth_template(false));
  test::expect_valid_solid(copy.shell);
  ASSERT_TRUE(copy.insertion.removal_checked);
  EXPECT_FALSE(copy.insertion.removable);
  EXPECT_FALSE(copy.insertion.blocking.empty());
  // Blocked out, it lifts 20 mm without touching the bone, and fills the space under the bulge.
  const TemplateResult guide = design_template(bone, tooth_template(true));
  test::expect_valid_solid(guide.shell);
  const InsertionReport& ins = guide.insertion;
  EXPECT_TRUE(ins.blocked_out);
  EXPECT_TRUE(ins.removable) << ins.blocking.size() << " blocking places, first "
                             << (ins.blocking.empty() ? Vec3::Zero() : ins.blocking.front()).transpose();
  EXPECT_EQ(ins.unfilled.size(), 0u);
  EXPECT_EQ(ins.removal_distance, 20.0);
  // The fill leans from the widest ring (r = 4) to the first plate ring beyond it (r = 4.2).
  const double cavity = tooth_cavity_volume();
  EXPECT_GT(ins.blocked_out_volume_mm3, cavity);
  EXPECT_LT(ins.blocked_out_volume_mm3, cavity + kPi * (4.2 * 4.2 - 16.0) * 5.0);
  // The guide keeps the bone's own surface wherever it can reach it: all but the hidden area and the
  // plate ring the fill leans over.
  EXPECT_GT(ins.contact_area_mm2, ins.region_area_mm2 - tooth_undercut_area() - kPi * (4.2 * 4.2 - 16.0) - 0.5);
}

TEST(BlockOut, TheAnalysisBesideTheShellGivesWhatItGivesBeforeIt) {
  // Without block-out the insertion analysis, and then the stability's contacts, run beside the shell;
  // with it, before and after it. On a cap the guide reaches from above (nothing to block out) both give
  // the same guide and the same report, along a given direction and along the automatic one.
  const TriangleMesh bone = test::make_icosphere(20.0, 5);
  for (const bool given : {true, false}) {
    TemplateOptions o;
    for (int k = 0; k < 16; ++k) {
      const double a = 2.0 * kPi * k / 16.0;
      o.boundary_points.emplace_back(std::sqrt(300.0) * std::cos(a), std::sqrt(300.0) * std::sin(a), 10.0);
    }
    o.inside = Vec3(0.0, 0.0, 25.0);
    o.thickness = 2.0;
    o.analyse_insertion = true;
    if (given) o.insertion = Vec3(0.0, 0.0, -1.0);
    const TemplateResult beside = design_template(bone, o);
    o.block_out = true;
    const TemplateResult before = design_template(bone, o);
    ASSERT_TRUE(beside.insertion.analysed);
    EXPECT_FALSE(before.insertion.blocked_out);
    EXPECT_EQ(beside.insertion.undercut_area_mm2, 0.0);
    EXPECT_EQ(beside.insertion.direction, before.insertion.direction);
    EXPECT_EQ(beside.insertion.hidden, before.insertion.hidden);
    EXPECT_EQ(beside.insertion.region.triangles, before.insertion.region.triangles);
    EXPECT_EQ(beside.insertion.contact_area_mm2, before.insertion.contact_area_mm2);
    EXPECT_TRUE(beside.insertion.removable);
    EXPECT_EQ(beside.shell.positions, before.shell.positions);
    EXPECT_EQ(beside.shell.triangles, before.shell.triangles);
    // The stability's contacts, prepared beside the shell, and the fit's tree made there too.
    ASSERT_TRUE(beside.stability.analysed);
    ASSERT_FALSE(beside.stability.contacts.empty());
    ASSERT_EQ(beside.stability.contacts.size(), before.stability.contacts.size());
    for (std::size_t i = 0; i < before.stability.contacts.size(); ++i)
      EXPECT_EQ(beside.stability.contacts[i].point, before.stability.contacts[i].point);
    EXPECT_EQ(beside.stability.report.score, before.stability.report.score);
    EXPECT_EQ(beside.stability.press.point, before.stability.press.point);
    EXPECT_EQ(beside.stability.extend.found, before.stability.extend.found);
    EXPECT_EQ(beside.fit.outer_to_inner.min, before.fit.outer_to_inner.min);
    EXPECT_EQ(beside.fit.outer_to_inner.max, before.fit.outer_to_inner.max);
    EXPECT_EQ(beside.fit.outer_to_inner.mean, before.fit.outer_to_inner.mean);
    test::expect_valid_solid(beside.shell);
  }
}

TEST(BlockOut, FillIsAWallWhereThePlateRingLiesExactlyUnderTheBulge) {
  // Plate rings every 0.25 mm: one lies exactly under the widest ring (r = 4, same angles), so the
  // hole left by the hidden faces has no area seen along the axis: the fill is a wall along it.
  const TriangleMesh bone = tooth_on_plate(0.25, 128);
  const TemplateResult guide = design_template(bone, tooth_template(true));
  test::expect_valid_solid(guide.shell);
  EXPECT_TRUE(guide.insertion.removable);
  EXPECT_EQ(guide.insertion.unfilled.size(), 0u);
  EXPECT_NEAR(guide.insertion.blocked_out_volume_mm3, tooth_cavity_volume(), 0.02 * tooth_cavity_volume());
}

TEST(BlockOut, MaxillaGuideOverTheTeethComesOffAlongAuto) {
  // The labial surface of the anterior teeth and alveolar bone (a real CT scan): along the
  // least-undercut direction the hidden zones are filled, the guide comes off, and it keeps touching
  // the bone over at least 60 % of its inner surface.
  const CaseFile c = read_case(test::examples_dir() + "/cases/maxilla-labial-auto.json");
  const TriangleMesh bone = read_mesh(c.bone);
  const TemplateOptions o = st::test::case_options(c);
  ASSERT_TRUE(o.block_out);
  const TemplateResult r = design_template(bone, o);
  test::expect_valid_solid(r.shell);
  const InsertionReport& ins = r.insertion;
  EXPECT_TRUE(ins.automatic);
  EXPECT_GT(ins.undercut_area_mm2, 0.0);
  EXPECT_TRUE(ins.blocked_out);
  EXPECT_TRUE(ins.removable);
  EXPECT_GE(ins.contact_area_mm2, 0.6 * ins.inner_area_mm2);
  // Without the block-out, the same guide cannot come off.
  TemplateOptions copy = o;
  copy.block_out = false;
  copy.insertion = ins.direction;
  EXPECT_FALSE(design_template(bone, copy).insertion.removable);
}

TEST(BlockOut, AZoneAtTheRimHangsASkirtFromTheSilhouetteDownToTheDrawnBorder) {
  // The border drawn round the post at z = 2, under the bulge: the band from the widest ring (r = 4,
  // z = 5) down to the border is hidden and reaches the rim. The guide keeps it covered by a skirt along
  // the axis from the widest ring down to z = 2 (a cylinder 3 mm high, standing off the post), and still
  // comes off.
  const TriangleMesh bone = tooth_on_plate(0.3, 128);
  TemplateOptions o = tooth_template(true);
  o.boundary_points.clear();
  for (int k = 0; k < 12; ++k) {
    const double a = 2.0 * kPi * (k + 0.5) / 12.0;
    o.boundary_points.emplace_back(3.0 * std::cos(a), 3.0 * std::sin(a), 2.0);
  }
  o.clearance = 0.1;
  const TemplateResult guide = design_template(bone, o);
  test::expect_valid_solid(guide.shell);
  const InsertionReport& ins = guide.insertion;
  EXPECT_EQ(ins.trimmed_zones, 1u);
  EXPECT_NEAR(ins.skirt_depth_mm, 3.0, 0.05);
  const double cylinder = 2.0 * kPi * 4.1 * 3.0; // at the clearance off the widest ring
  EXPECT_NEAR(ins.skirt_area_mm2, cylinder, 0.02 * cylinder);
  EXPECT_TRUE(ins.removable) << ins.blocking.size() << " blocking places";
  // The inner surface reaches the drawn border's depth, and keeps clear of the bone everywhere.
  double lowest = 1e9, closest = 1e9;
  const AabbTree tree(bone);
  for (const Vec3& p : guide.inner.positions) {
    lowest = std::min(lowest, p.z());
    closest = std::min(closest, tree.closest_point(p)->distance);
  }
  EXPECT_NEAR(lowest, 2.0, 0.05);
  EXPECT_GT(closest, 0.05);
  // The skirt's faces are fills: the guide's contact is the reachable bone only.
  EXPECT_LT(ins.contact_area_mm2, ins.inner_area_mm2 - 0.5 * cylinder);
}

TEST(Removal, APlateLiftsOffAPlaneAndCatchesOnALedge) {
  // A 10 x 10 x 2 box resting on a plane comes off upwards; with a ledge 1 mm above its top, it
  // meets the ledge; moved off sideways (along -x, the ledge behind it) it comes off again.
  const TriangleMesh plane = test::make_height_field(-20, 20, -20, 20, 40, [](double, double) { return 0.0; });
  TriangleMesh box;
  for (int k = 0; k < 8; ++k) box.positions.emplace_back(k & 1 ? 5.0 : -5.0, k & 2 ? 5.0 : -5.0, k & 4 ? 2.0 : 0.0);
  box.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                   {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  test::expect_valid_solid(box);
  const AabbTree free_tree(plane);
  EXPECT_TRUE(check_removal(free_tree, box, Vec3(0, 0, -1)).removable);
  TriangleMesh with_ledge = plane;
  const TriangleMesh ledge = test::make_height_field(2, 12, -3, 3, 4, [](double, double) { return 3.0; });
  const Index n = with_ledge.vertex_count();
  with_ledge.positions.insert(with_ledge.positions.end(), ledge.positions.begin(), ledge.positions.end());
  for (const Triangle& t : ledge.triangles) with_ledge.triangles.push_back({t[0] + n, t[2] + n, t[1] + n});
  const AabbTree ledge_tree(with_ledge);
  const RemovalReport up = check_removal(ledge_tree, box, Vec3(0, 0, -1));
  EXPECT_FALSE(up.removable);
  ASSERT_FALSE(up.blocking.empty());
  EXPECT_GT(up.blocking.front().x(), 1.9);
  // Sideways the box's bottom slides on the plane (touching, not crossing): along -x it leaves the
  // ledge, along +x it passes under it (the ledge is 1 mm above the box's top).
  EXPECT_TRUE(check_removal(ledge_tree, box, Vec3(1, 0, 0)).removable);
  EXPECT_TRUE(check_removal(ledge_tree, box, Vec3(-1, 0, 0)).removable);
}

TEST(Removal, ABonePreparedOnceAnswersLikeAFreshOneInAnyOrder) {
  // The shrunk bone is made vertex by vertex as the sweeps reach it: a SweepTest asked about several
  // guides and directions answers each as a fresh check would. The plates rest on grid vertices of the
  // plane (zero clearance: corners the guide copies) under a ledge, so every family has work.
  TriangleMesh bone = test::make_height_field(-20, 20, -20, 20, 40, [](double, double) { return 0.0; });
  const TriangleMesh ledge = test::make_height_field(2, 12, -3, 3, 4, [](double, double) { return 3.0; });
  const Index n = bone.vertex_count();
  bone.positions.insert(bone.positions.end(), ledge.positions.begin(), ledge.positions.end());
  for (const Triangle& t : ledge.triangles) bone.triangles.push_back({t[0] + n, t[2] + n, t[1] + n});
  auto plate = [](double x0, double y0) {
    TriangleMesh box;
    for (int k = 0; k < 8; ++k)
      box.positions.emplace_back(x0 + (k & 1 ? 5.0 : -5.0), y0 + (k & 2 ? 5.0 : -5.0), k & 4 ? 2.0 : 0.0);
    box.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                     {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
    return box;
  };
  const AabbTree tree(bone);
  const MeshTopology topology(bone);
  const SweepTest sweep(tree, &topology);
  int blocked = 0;
  for (const Vec3 at : {Vec3(0, 0, 0), Vec3(-12, 8, 0), Vec3(7, 0, 0)})
    for (const Vec3 d : {Vec3(0, 0, -1), Vec3(1, 0, 0), Vec3(-1, 0, -1), Vec3(0.3, -0.2, -1)}) {
      const TriangleMesh guide = plate(at.x(), at.y());
      const RemovalReport prepared = sweep(guide, d, 20.0);
      const RemovalReport fresh = check_removal(tree, guide, d, 20.0);
      EXPECT_EQ(prepared.removable, fresh.removable) << at.transpose() << " / " << d.transpose();
      EXPECT_EQ(prepared.blocked_features, fresh.blocked_features);
      EXPECT_EQ(prepared.blocked_faces, fresh.blocked_faces);
      EXPECT_EQ(prepared.blocking, fresh.blocking);
      blocked += prepared.removable ? 0 : 1;
    }
  EXPECT_GT(blocked, 0); // the ledge holds some of them
  EXPECT_LT(blocked, 12);
  // A topology of another mesh is refused, and so is a tree over another guide.
  const MeshTopology other(ledge);
  EXPECT_THROW(static_cast<void>(SweepTest(tree, &other)), InvalidInput);
  const TriangleMesh guide = plate(0.0, 0.0), copy = guide;
  const AabbTree copy_tree(copy);
  EXPECT_THROW(static_cast<void>(sweep(guide, Vec3(0, 0, -1), 20.0, SweepStart::shrunk, &copy_tree)), InvalidInput);
  EXPECT_EQ(sweep(copy, Vec3(0, 0, -1), 20.0, SweepStart::shrunk, &copy_tree).blocking,
            check_removal(tree, copy, Vec3(0, 0, -1), 20.0).blocking); // blocked by the ledge
}

/// A closed octahedron of radius 5 about the origin.
TriangleMesh octahedron() {
  TriangleMesh m;
  m.positions = {{5, 0, 0}, {0, 5, 0}, {-5, 0, 0}, {0, -5, 0}, {0, 0, 5}, {0, 0, -5}};
  for (Index k = 0; k < 4; ++k) {
    m.triangles.push_back({k, (k + 1) % 4, 4});
    m.triangles.push_back({(k + 1) % 4, k, 5});
  }
  return m;
}

/// A thin closed rod along x from -50 to 50, its cross-section a triangle about (y, z).
TriangleMesh rod(double y, double z) {
  TriangleMesh m;
  for (double x : {-50.0, 50.0}) {
    m.positions.emplace_back(x, y - 0.2, z - 0.2);
    m.positions.emplace_back(x, y + 0.2, z - 0.2);
    m.positions.emplace_back(x, y, z + 0.2);
  }
  m.triangles = {{0, 2, 1}, {3, 4, 5}, {0, 1, 4}, {0, 4, 3}, {1, 2, 5}, {1, 5, 4}, {2, 0, 3}, {2, 3, 5}};
  return m;
}

TEST(Removal, AGuideMeetsABarItsEdgesPassWithNoCornerOnIt) {
  // An octahedron lifted by 20 mm along +z past a thin bar at y = 2: no corner's path meets the bar
  // and the bar's corners lie far off to the sides, so only an edge sweeping over it (the equator, where
  // the faces turn from facing up to facing down) or the octahedron at the end of the way finds it.
  const TriangleMesh guide = octahedron();
  test::expect_valid_solid(guide);
  for (const TriangleMesh& bar : {rod(2.0, 10.0), rod(2.0, 22.0)}) {
    test::expect_valid_solid(bar);
    const AabbTree tree(bar);
    const RemovalReport r = check_removal(tree, guide, Vec3(0, 0, -1));
    EXPECT_FALSE(r.removable) << "bar at z " << bar.positions[2].z();
    ASSERT_FALSE(r.blocking.empty());
  }
  // Off to the side (y = 6, outside the octahedron's outline) and beyond the way (z = 27): free.
  for (const TriangleMesh& bar : {rod(6.0, 10.0), rod(2.0, 27.0)}) {
    const AabbTree tree(bar);
    EXPECT_TRUE(check_removal(tree, guide, Vec3(0, 0, -1)).removable) << "bar at y " << bar.positions[2].y();
  }
}

/// Whether the segment [p, q] crosses the closed triangle (a, b, c), its ends strictly on either side.
bool segment_crosses(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  const int sp = orient3d(a, b, c, p), sq = orient3d(a, b, c, q);
  if (sp == 0 || sq == 0 || sp == sq) return false;
  const int s1 = orient3d(p, q, a, b), s2 = orient3d(p, q, b, c), s3 = orient3d(p, q, c, a);
  return (s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0);
}

/// What a guide moved by t * w, t in (0, L], meets of a piece, by every feature pair (no cull, no
/// boundary argument): each guide vertex's path against the piece's faces, each piece vertex's path
/// back against the guide's faces, each guide edge's parallelogram against the piece's edges. Counts
/// the guide vertices whose path meets the piece where the guide's surface faces one way all round
/// (`one_way`: no part of the boundary of the solid it sweeps).
struct Swept {
  bool meets = false;
  int one_way_paths = 0;
};
Swept sweep_by_every_pair(const TriangleMesh& guide, const std::vector<bool>& one_way, const TriangleMesh& piece,
                          const Vec3& w, double L) {
  Swept r;
  for (Index v = 0; v < guide.vertex_count(); ++v) {
    const Vec3 &p = guide.positions[v], q = p + L * w;
    for (const Triangle& t : piece.triangles)
      if (segment_crosses(p, q, piece.positions[t[0]], piece.positions[t[1]], piece.positions[t[2]])) {
        r.meets = true;
        r.one_way_paths += one_way[v] ? 1 : 0;
        break;
      }
  }
  for (const Vec3& b : piece.positions)
    for (const Triangle& t : guide.triangles)
      r.meets =
          r.meets || segment_crosses(b, b - L * w, guide.positions[t[0]], guide.positions[t[1]], guide.positions[t[2]]);
  for (const Triangle& g : guide.triangles)
    for (int k = 0; k < 3 && !r.meets; ++k) {
      const Vec3 &g0 = guide.positions[g[k]], &g1 = guide.positions[g[(k + 1) % 3]];
      for (const Triangle& t : piece.triangles)
        for (int e = 0; e < 3; ++e) {
          const Vec3 &b0 = piece.positions[t[e]], &b1 = piece.positions[t[(e + 1) % 3]];
          r.meets = r.meets || segment_crosses(b0, b1, g0, g1, g1 + L * w) ||
                    segment_crosses(b0, b1, g0, g1 + L * w, g0 + L * w);
        }
    }
  return r;
}

TEST(Removal, ABumpyBallIsBlockedByExactlyThePiecesSomePairOfFeaturesMeets) {
  // A closed bumpy ball (its surface turns from facing the way off to facing back along a wavy
  // silhouette and around its bumps) moved off along a slanted way past small tetrahedra strewn
  // around and above it: the check, which follows only the paths of the vertices where the surface
  // turns, blocks on exactly the pieces that some pair of features meets. Pieces that meet the ball
  // at rest are left out (the guide rests on the bone, never in it).
  TriangleMesh guide = test::make_icosphere(1.0, 3);
  for (Vec3& p : guide.positions)
    p *= 5.0 + 0.5 * std::sin(3.0 * p.x() + 1.0) * std::cos(2.0 * p.y()) + 0.3 * std::sin(4.0 * p.z());
  test::expect_valid_solid(guide);
  const Vec3 d = Vec3(0.3, -0.2, -1.0).normalized(), w = -d;
  const double L = 20.0;
  std::vector<bool> one_way(guide.vertex_count(), true); // every face around it on one side of w
  {
    std::vector<int> sides(guide.vertex_count(), 0);
    for (Index f = 0; f < guide.face_count(); ++f)
      for (Index v : guide.triangles[f]) sides[v] |= triangle_normal(guide, f).dot(w) > 0.0 ? 1 : 2;
    for (Index v = 0; v < guide.vertex_count(); ++v) one_way[v] = sides[v] != 3;
  }
  Vec3 highest = guide.positions[0];
  for (const Vec3& p : guide.positions)
    if (p.dot(w) > highest.dot(w)) highest = p;
  std::mt19937_64 rng(20261207);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int blocked = 0, free = 0, behind_one_way = 0;
  for (int trial = 0; trial < 160; ++trial) {
    // About the column the ball sweeps, from below its start to beyond its end.
    const Vec3 centre = 7.0 * Vec3(unit(rng), unit(rng), unit(rng)) + (10.5 + 13.5 * unit(rng)) * w;
    TriangleMesh piece;
    const double size = 0.6 + 0.5 * unit(rng);
    // Every other piece a sliver 6 times as long as it is wide, which passes between the corners.
    const Vec3 along = Vec3(unit(rng), unit(rng), unit(rng)).normalized();
    for (int k = 0; k < 4; ++k) {
      const Vec3 x = size * Vec3(unit(rng), unit(rng), unit(rng));
      piece.positions.push_back(centre + x + (trial % 2 ? 5.0 * x.dot(along) : 0.0) * along);
    }
    piece.triangles = {{0, 1, 2}, {0, 3, 1}, {1, 3, 2}, {2, 3, 0}};
    if (trial % 16 == 0) { // a sliver through the ball's top at the end of the way, its corners outside
      const Vec3 across = w.cross(along).normalized(), top = highest + (L - 0.05) * w;
      piece.positions = {top - 1.6 * across, top + 1.6 * across + 0.02 * along, top + 1.6 * across - 0.02 * along,
                         top + 0.15 * w};
    }
    if (orient3d(piece.positions[0], piece.positions[1], piece.positions[2], piece.positions[3]) == 0) continue;
    if (orient3d(piece.positions[0], piece.positions[1], piece.positions[2], piece.positions[3]) > 0)
      for (Triangle& t : piece.triangles) std::swap(t[1], t[2]);
    bool at_rest = false;
    for (const Triangle& g : guide.triangles)
      for (const Triangle& t : piece.triangles)
        at_rest = at_rest || triangles_intersect(guide.positions[g[0]], guide.positions[g[1]], guide.positions[g[2]],
                                                 piece.positions[t[0]], piece.positions[t[1]], piece.positions[t[2]]);
    const Vec3 middle = 0.25 * (piece.positions[0] + piece.positions[1] + piece.positions[2] + piece.positions[3]);
    if (at_rest || test::winding_number(guide, middle) > 0.5) continue; // in the ball, meeting none of it
    const Swept expected = sweep_by_every_pair(guide, one_way, piece, w, L);
    const RemovalReport r = check_removal(AabbTree(piece), guide, d, L);
    EXPECT_EQ(r.removable, !expected.meets) << "piece " << trial << " about " << centre.transpose();
    (expected.meets ? blocked : free) += 1;
    behind_one_way += expected.one_way_paths > 0 ? 1 : 0;
  }
  // Both verdicts, and paths the check does not follow that meet a piece, come up often.
  EXPECT_GT(blocked, 20);
  EXPECT_GT(free, 20);
  EXPECT_GT(behind_one_way, 10);
}

} // namespace
} // namespace st
