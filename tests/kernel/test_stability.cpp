// Seating stability: the free motions and the score of contacts on shapes whose answer is known (a
// plate on a plane, a half cylinder with and without a cap, a box corner), monotone under removing
// contacts, and exact positions (contacts on a regular grid's vertices and edges).

#include "helpers.h"

#include "st/core/aabb_tree.h"
#include "st/core/errors.h"
#include "st/core/topology.h"
#include "st/design/template_design.h"
#include "st/io/case_file.h"
#include "st/io/mesh_io.h"
#include "st/validate/stability.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <functional>
#include <numbers>
#include <random>
#include <chrono>

namespace st {
namespace {

constexpr double kPi = std::numbers::pi;

/// Random subsets tried by the monotone tests (ST_PROPERTY_CASES, default 500).
int subsets() {
  const char* env = std::getenv("ST_PROPERTY_CASES");
  return env ? std::max(10, std::atoi(env)) : 500;
}

TriangleMesh joined(std::initializer_list<TriangleMesh> parts) {
  TriangleMesh out;
  for (const TriangleMesh& m : parts) {
    const Index n = out.vertex_count();
    out.positions.insert(out.positions.end(), m.positions.begin(), m.positions.end());
    for (const Triangle& t : m.triangles) out.triangles.push_back({t[0] + n, t[1] + n, t[2] + n});
  }
  return out;
}

/// Contacts of a guide whose inner surface is `surface` (zero clearance) on `bone` (by default the
/// surface itself).
std::vector<Contact> contacts_on(const TriangleMesh& surface, const TriangleMesh* bone = nullptr) {
  const AabbTree tree(bone ? *bone : surface);
  return sample_contacts(surface, tree, 1e-6);
}

std::vector<const FreeMotion*> keeping(const StabilityReport& r) {
  std::vector<const FreeMotion*> out;
  for (const FreeMotion& m : r.free_motions)
    if (m.keeps_contact) out.push_back(&m);
  return out;
}

/// A guide covering the upper half (z >= 0) of a cylinder of radius 10 along x, x in [0, 40]: the
/// bone reaches 45 degrees further on either side (its normals there are the cylinder's).
struct HalfCylinder {
  TriangleMesh bone = test::make_grid_patch(72, -0.25 * kPi, 1.25 * kPi, 0.0, 40.0, [](double t, double x) {
    return Vec3(x, 10.0 * std::cos(t), 10.0 * std::sin(t));
  });
  TriangleMesh guide = test::faces_where(bone, [](const Vec3& c) { return c.z() > 0.0; });
};

TEST(Stability, AFlatPlateSlidesInThePlaneAndTurnsAboutItsNormal) {
  const TriangleMesh plane = test::make_height_field(0, 40, 0, 30, 40, [](double, double) { return 0.0; });
  const std::vector<Contact> contacts = contacts_on(plane);
  EXPECT_NEAR(static_cast<double>(contacts.size()), 1200.0, 2.0); // one per mm^2
  const StabilityReport r = analyse_stability(contacts, Vec3(0, 0, -1));
  EXPECT_EQ(r.score, 0.0);
  const auto keep = keeping(r);
  ASSERT_EQ(keep.size(), 3U);
  int slides = 0, turns = 0;
  for (const FreeMotion* m : keep) {
    if (m->kind == FreeMotion::Kind::slide) {
      ++slides;
      EXPECT_NEAR(m->direction.z(), 0.0, 1e-9);
    } else {
      ASSERT_EQ(m->kind, FreeMotion::Kind::turn);
      ++turns;
      EXPECT_NEAR(std::abs(m->direction.z()), 1.0, 1e-9);
    }
  }
  EXPECT_EQ(slides, 2);
  EXPECT_EQ(turns, 1);
  EXPECT_TRUE(r.lift_off_free);
  EXPECT_EQ(r.free_motions.back().kind, FreeMotion::Kind::lift_off);
  EXPECT_TRUE(r.worst_motion.keeps_contact);
}

TEST(Stability, AHalfCylinderSlidesAlongAndTurnsAboutItsAxis) {
  const HalfCylinder half;
  const std::vector<Contact> contacts = contacts_on(half.guide, &half.bone);
  const StabilityReport r = analyse_stability(contacts, Vec3(0, 0, -1));
  EXPECT_EQ(r.score, 0.0);
  const auto keep = keeping(r);
  ASSERT_EQ(keep.size(), 2U);
  EXPECT_EQ(keep[0]->kind, FreeMotion::Kind::slide);
  EXPECT_NEAR(std::abs(keep[0]->direction.x()), 1.0, 1e-6);
  EXPECT_EQ(keep[1]->kind, FreeMotion::Kind::turn);
  EXPECT_NEAR(std::abs(keep[1]->direction.x()), 1.0, 1e-6);
  // The turn's axis is the cylinder's (through y = z = 0), not one through the contacts' centroid.
  EXPECT_NEAR(keep[1]->point.y(), 0.0, 1e-6);
  EXPECT_NEAR(keep[1]->point.z(), 0.0, 1e-6);
  // Nothing else is free without rising: a sideways slide pushes into one flank.
  for (const FreeMotion& m : r.free_motions)
    if (!m.keeps_contact) EXPECT_EQ(m.kind, FreeMotion::Kind::lift_off) << m.describe();

  // A cap over the end x = 0 (its outward normal -x): the slide towards it is blocked, the one away
  // from it lifts off the cap, and the turn stays.
  const TriangleMesh cap = test::make_grid_patch(
      24, 0.0, kPi, 0.0, 10.0, [](double t, double s) { return Vec3(0.0, s * std::cos(t), s * std::sin(t)); });
  const TriangleMesh bone = joined({half.bone, cap}), guide = joined({half.guide, cap});
  const StabilityReport capped = analyse_stability(contacts_on(guide, &bone), Vec3(0, 0, -1));
  EXPECT_EQ(capped.score, 0.0);
  const auto still = keeping(capped);
  ASSERT_EQ(still.size(), 1U);
  EXPECT_EQ(still[0]->kind, FreeMotion::Kind::turn);
  EXPECT_NEAR(std::abs(still[0]->direction.x()), 1.0, 1e-6);
  int away = 0;
  for (const FreeMotion& m : capped.free_motions) {
    if (m.keeps_contact || m.kind == FreeMotion::Kind::lift_off) continue;
    EXPECT_EQ(m.kind, FreeMotion::Kind::slide) << m.describe();
    EXPECT_GT(m.direction.dot(Vec3(-1, 0, 0)), 0.999) << m.describe();
    EXPECT_EQ(m.lift, 0.0);
    ++away;
  }
  EXPECT_EQ(away, 1);
}

TEST(Stability, TheHintForASlideNamesTheBoneThatFacesIt) {
  // The half cylinder's guide slides along the axis; the bone has a cap over the end x = 0 that the
  // guide does not cover. Extending the guide there would stop the slide: the hint names the cap,
  // facing the motion, and the guide's rim at that end; bone the guide covers is not named.
  const HalfCylinder half;
  const TriangleMesh cap = test::make_grid_patch(
      24, 0.0, kPi, 0.0, 10.0, [](double t, double s) { return Vec3(0.0, s * std::cos(t), s * std::sin(t)); });
  const TriangleMesh bone = joined({half.bone, cap});
  const StabilityReport r = analyse_stability(contacts_on(half.guide, &half.bone), Vec3(0, 0, -1));
  const auto keep = keeping(r);
  ASSERT_FALSE(keep.empty());
  ASSERT_EQ(keep[0]->kind, FreeMotion::Kind::slide);
  std::vector<Vec3> rim;
  const MeshTopology topology(half.guide);
  for (const auto& loop : border_loops(half.guide, topology.all_opposites()))
    for (Index v : loop) rim.push_back(half.guide.positions[v]);
  const AabbTree covered(half.guide);
  const ExtensionHint hint = where_to_extend(r, *keep[0], rim, bone, covered, 15.0, 0.05);
  ASSERT_TRUE(hint.found);
  EXPECT_GT(hint.facing, 0.99);
  EXPECT_EQ(hint.bone_point.x(), 0.0) << "not on the cap";
  EXPECT_GT(covered.closest_point(hint.bone_point, 15.0)->distance, 0.05) << "named covered bone";
  EXPECT_EQ(hint.rim_point.x(), 0.0) << "not the rim at the capped end";
}

TEST(Stability, TheBoneNormalsMadeOnDemandAndTheTwoPartsGiveTheSameAnswer) {
  // With the bone's topology the whole analysis makes only the vertex normals it reads (the hint's, near
  // the rim, in one pass over the faces): the contacts, the score, the press point and the hint (the cap
  // the guide does not cover, and how squarely it faces the motion) are the same, bit for bit, as with
  // all normals made up front; a topology of another mesh is refused.
  const HalfCylinder half;
  // A cap over the end that bulges out of it (normals turning by up to 31 degrees from the axis): the
  // hint's facing reads the normal of a vertex where the faces around it turn.
  const TriangleMesh cap = test::make_grid_patch(24, 0.0, kPi, 0.0, 10.0, [](double t, double s) {
    return Vec3(-0.03 * s * s, s * std::cos(t), s * std::sin(t));
  });
  const TriangleMesh bone = joined({half.bone, cap});
  const AabbTree tree(bone), covered(half.guide);
  const MeshTopology topology(bone), guide_topology(half.guide);
  std::vector<Vec3> rim;
  for (const auto& loop : border_loops(half.guide, guide_topology.all_opposites()))
    for (Index v : loop) rim.push_back(half.guide.positions[v]);
  const Vec3 down(0, 0, -1);
  const StabilityResult all = guide_stability(half.guide, tree, down, 0.05, half.guide.positions, rim, covered);
  const StabilityResult lazy =
      guide_stability(half.guide, tree, down, 0.05, half.guide.positions, rim, covered, 0.05, {}, false, &topology);
  ASSERT_FALSE(all.contacts.empty());
  ASSERT_EQ(lazy.contacts.size(), all.contacts.size());
  for (std::size_t i = 0; i < all.contacts.size(); ++i) {
    EXPECT_EQ(lazy.contacts[i].point, all.contacts[i].point);
    EXPECT_EQ(lazy.contacts[i].normal, all.contacts[i].normal);
  }
  EXPECT_EQ(lazy.report.score, all.report.score);
  EXPECT_EQ(lazy.press.point, all.press.point);
  ASSERT_TRUE(all.extend.found);
  EXPECT_EQ(lazy.extend.bone_point, all.extend.bone_point);
  EXPECT_EQ(lazy.extend.rim_point, all.extend.rim_point);
  EXPECT_EQ(lazy.extend.facing, all.extend.facing); // the normal there, made in one pass over the faces
  EXPECT_THROW(static_cast<void>(guide_stability(half.guide, tree, down, 0.05, half.guide.positions, rim, covered, 0.05,
                                                 {}, false, &guide_topology)),
               InvalidInput);
  // In two parts (the design makes the first beside the shell, before the outer surface exists): the
  // first has the contacts and the report only, and the two together give the same answer.
  StabilityResult parts = stability_of_contacts(half.guide, tree, down, 0.05, {}, false, &topology);
  EXPECT_FALSE(parts.extend.found);
  ASSERT_EQ(parts.contacts.size(), all.contacts.size());
  finish_stability(parts, tree, half.guide.positions, rim, covered, 0.05, &topology);
  for (std::size_t i = 0; i < all.contacts.size(); ++i) EXPECT_EQ(parts.contacts[i].point, all.contacts[i].point);
  EXPECT_EQ(parts.report.score, all.report.score);
  EXPECT_EQ(parts.press.point, all.press.point);
  ASSERT_TRUE(parts.extend.found);
  EXPECT_EQ(parts.extend.bone_point, all.extend.bone_point);
  EXPECT_EQ(parts.extend.rim_point, all.extend.rim_point);
  EXPECT_EQ(parts.extend.facing, all.extend.facing);
  EXPECT_THROW(static_cast<void>(stability_of_contacts(half.guide, tree, down, 0.05, {}, false, &guide_topology)),
               InvalidInput);
}

/// Three faces of the box [-20, 0]^3 around its corner at the origin, `s` mm wide, normals outward.
TriangleMesh box_corner(double s, int n) {
  return joined({test::make_grid_patch(n, -s, 0, -s, 0, [](double u, double v) { return Vec3(0, u, v); }),
                 test::make_grid_patch(n, -s, 0, -s, 0, [](double u, double v) { return Vec3(v, 0, u); }),
                 test::make_grid_patch(n, -s, 0, -s, 0, [](double u, double v) { return Vec3(u, v, 0); })});
}

TEST(Stability, ABoxCornerHoldsEveryMotionButLiftingOff) {
  const std::vector<Contact> contacts = contacts_on(box_corner(10.0, 20));
  const StabilityReport r = analyse_stability(contacts, -Vec3(1, 1, 1));
  EXPECT_TRUE(r.bounded);
  EXPECT_GT(r.score, 0.5);
  for (const FreeMotion& m : r.free_motions) {
    EXPECT_FALSE(m.keeps_contact) << m.describe();
    EXPECT_GT(m.lift, 0.0) << m.describe();
  }
  ASSERT_FALSE(r.extreme_motions.empty());
  // Every extreme free motion rises against the press by at least the score, and the slide away from
  // one face along another (free) rises by 1 / sqrt(3).
  for (const Twist& x : r.extreme_motions) EXPECT_GE(-r.direction.dot(x.head<3>()), r.score - 1e-9);
  EXPECT_LE(r.score, 1.0 / std::sqrt(3.0) + 1e-9);
  // Pressing at the centroid is the score; the best press point holds at least as well.
  EXPECT_NEAR(press_score(r, r.centroid), r.score, 1e-9);
  const PressPoint press = best_press_point(r, {Vec3(1, 1, 1), Vec3(-5, 1, 1), r.centroid});
  EXPECT_GE(press.score, r.score - 1e-12);
}

TEST(Stability, AGuideAroundAWholeBoxCannotMoveAtAll) {
  // Contacts on all six faces of the box [-10, 0]^3: no motion is free, not even the lift-off; the
  // score is the top of its scale (nothing moves it) and the report says the bone holds the guide.
  const TriangleMesh box =
      joined({box_corner(10.0, 10),
              test::make_grid_patch(10, -10, 0, -10, 0, [](double u, double v) { return Vec3(-10, v, u); }),
              test::make_grid_patch(10, -10, 0, -10, 0, [](double u, double v) { return Vec3(u, -10, v); }),
              test::make_grid_patch(10, -10, 0, -10, 0, [](double u, double v) { return Vec3(v, u, -10); })});
  const StabilityReport r = analyse_stability(contacts_on(box), -Vec3(1, 1, 1));
  EXPECT_EQ(r.score, 1.0);
  EXPECT_FALSE(r.lift_off_free);
  EXPECT_TRUE(r.free_motions.empty());
  EXPECT_TRUE(r.worst_motion.blocked) << r.worst_motion.describe();
}

TEST(Stability, RemovingContactsNeverRaisesTheScore) {
  // A corner with a bulge on one face (so contacts differ in their normals), 500 random subsets.
  const TriangleMesh bump = test::make_grid_patch(20, -10, 0, -10, 0, [](double u, double v) {
    return Vec3(u, v, 1.5 * std::exp(-((u + 5) * (u + 5) + (v + 5) * (v + 5)) / 8.0));
  });
  const TriangleMesh surface =
      joined({test::make_grid_patch(20, -10, 0, -10, 0, [](double u, double v) { return Vec3(0, u, v); }),
              test::make_grid_patch(20, -10, 0, -10, 0, [](double u, double v) { return Vec3(v, 0, u); }), bump});
  const std::vector<Contact> all = contacts_on(surface);
  const Vec3 d = -Vec3(1, 1, 1);
  const StabilityReport full = analyse_stability(all, d);
  StabilityOptions frame; // the guide's frame, kept for its subsets
  frame.centroid = full.centroid;
  frame.scale = full.scale;
  EXPECT_GT(full.score, 0.2);
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> keep_fraction(0.05, 0.95);
  double lowest = 1.0;
  for (int trial = 0; trial < subsets(); ++trial) {
    const double f = keep_fraction(rng);
    std::bernoulli_distribution keep(f);
    std::vector<Contact> subset, smaller;
    for (const Contact& c : all)
      if (keep(rng)) subset.push_back(c);
    for (const Contact& c : subset)
      if (keep(rng)) smaller.push_back(c);
    const double s = analyse_stability(subset, d, frame).score, t = analyse_stability(smaller, d, frame).score;
    ASSERT_LE(s, full.score + 1e-6) << "trial " << trial << " kept " << subset.size();
    ASSERT_LE(t, s + 1e-6) << "trial " << trial << " kept " << smaller.size() << " of " << subset.size();
    lowest = std::min(lowest, t);
  }
  EXPECT_LT(lowest, full.score); // the test can fail: some subsets hold less
}

TEST(Stability, RemovingContactsOfARealGuideNeverRaisesItsScore) {
  // The labial maxilla guide (blocked out along its automatic direction), its contacts in random
  // subsets, each nested in the one before: the score falls or stays, never rises.
  const CaseFile c = read_case(test::examples_dir() + "/cases/maxilla-labial-auto.json");
  const TemplateResult r = design_template(read_mesh(c.bone), st::test::case_options(c));
  ASSERT_TRUE(r.stability.analysed);
  const StabilityReport& full = r.stability.report;
  EXPECT_GT(full.score, 0.0);
  EXPECT_TRUE(full.lift_off_free);
  StabilityOptions frame;
  frame.centroid = full.centroid;
  frame.scale = full.scale;
  EXPECT_NEAR(analyse_stability(r.stability.contacts, full.direction, frame).score, full.score, 1e-12);
  std::mt19937 rng(7);
  std::bernoulli_distribution keep(0.8);
  std::vector<Contact> current = r.stability.contacts;
  double previous = full.score;
  for (int trial = 0; trial < subsets() / 5 && current.size() > 10; ++trial) {
    std::vector<Contact> next;
    for (const Contact& k : current)
      if (keep(rng)) next.push_back(k);
    const double score = analyse_stability(next, full.direction, frame).score;
    ASSERT_LE(score, previous + 1e-6) << "trial " << trial << ", " << next.size() << " contacts";
    previous = score;
    current = std::move(next);
    if (trial % 10 == 9) current = r.stability.contacts, previous = full.score; // start a new chain
  }
}

TEST(Stability, BadInputIsRefusedAndNoContactsLeaveEverythingFree) {
  EXPECT_THROW(analyse_stability({}, Vec3::Zero()), InvalidInput);
  EXPECT_THROW(analyse_stability({}, Vec3(std::nan(""), 0, 1)), InvalidInput);
  const StabilityReport none = analyse_stability({}, Vec3(0, 0, -1));
  EXPECT_EQ(none.score, 0.0);
  EXPECT_EQ(keeping(none).size(), 6U);
}

} // namespace
} // namespace st
