// Saw slots of cutting guides (slot.h, guide.h): the slot as planned on the output (its walls within
// 0.01 mm of blade / 2 + clearance from the plane, its mid-plane within 0.02 mm and its walls within 0.05 degrees of
// the plan), the blade's path free of guide material, housing material on both sides and at the closed
// ends, the guide one valid solid; on a synthetic plate and on the real tibia, with random slots; bad
// slots refused by name.

#include "helpers.h"

#include "st/core/errors.h"
#include "st/design/template_design.h"
#include "st/guide/slot.h"
#include "st/io/case_file.h"
#include "st/io/mesh_io.h"
#include "st/io/plan.h"
#include "st/guide/blade_path.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <random>

namespace st {
namespace {

using test::winding_number;

/// Random slots tried per bone (ST_PROPERTY_CASES / 25, default 20).
int random_slots() {
  const char* env = std::getenv("ST_PROPERTY_CASES");
  return env ? std::max(4, std::atoi(env) / 25) : 20;
}

/// The slot on the finished guide, measured as a caliper would: rays from the planned mid-plane along
/// +n and -n over the slot's extent meet its walls (housing and template) at half the width (within
/// 0.01 mm); the walls fitted to those hits lie within 0.05
/// degrees of the plane and their middle within 0.02 mm of it. Then the blade path, and housing
/// material on both sides and at the closed ends.
void expect_slot_as_planned(const TriangleMesh& guide, const SlotSpec& slot, const SlotPlacement& p) {
  SCOPED_TRACE("slot " + slot.name);
  const SlotFrame f = slot_frame(slot);
  const double half = 0.5 * p.width;
  const AabbTree tree(guide);
  std::array<std::vector<Vec3>, 2> hits; // on the -n and the +n wall
  double worst = 0.0;
  for (int j = 0; j <= 20; ++j)
    for (int k = 0; k <= 20; ++k) {
      const double b = (-0.5 + 0.05 * j) * (slot.length - 0.4);
      const double z = p.cut_bottom + 1.0 + (p.housing_top - 0.05 - p.cut_bottom - 1.0) * k / 20.0;
      const Vec3 from = f.at(0.0, b, z);
      for (int side = 0; side < 2; ++side) {
        const Vec3 towards = side ? f.n : Vec3(-f.n);
        const auto hit = tree.first_hit(from, towards, 0.0, half + slot.wall);
        // Only the walls (faces turned within 5 degrees of the plane's normal, in the band of 0.05 mm
        // about the wall's plane): elsewhere the ray runs under or over the template beside the slot,
        // or meets the template's rim.
        if (!hit || std::abs(triangle_normal(guide, hit->face).dot(f.n)) < std::cos(5.0 * std::numbers::pi / 180.0))
          continue;
        bool in_band = true;
        for (const Index w : guide.triangles[hit->face])
          in_band &= std::abs((side ? 1.0 : -1.0) * (guide.positions[w] - f.origin).dot(f.n) - half) < 0.05;
        if (!in_band) continue;
        if (std::abs(hit->t - half) > worst && std::getenv("ST_DEBUG_SLOTS"))
          std::fprintf(stderr, "wall hit %.4f off at along %.3f height %.3f (face %u)\n", hit->t - half, b, z,
                       static_cast<unsigned>(hit->face));
        worst = std::max(worst, std::abs(hit->t - half));
        hits[static_cast<std::size_t>(side)].push_back(from + hit->t * towards);
      }
    }
  ASSERT_GT(hits[0].size(), 20u) << "no wall on the -n side";
  ASSERT_GT(hits[1].size(), 20u) << "no wall on the +n side";
  // Within 0.01 mm (the issue's number; measured 0.002 on the tibia 600 mm from the origin, where the
  // Boolean operation collapses curve edges under 0.016 mm: the template moves, not the slot's walls).
  EXPECT_LT(worst, 0.01) << "a wall off its planned plane (slot width blade + 2 x clearance)";
  // Least-squares planes through each wall's hits.
  std::array<Vec3, 2> normal;
  std::array<double, 2> offset{};
  for (int side = 0; side < 2; ++side) {
    const std::vector<Vec3>& h = hits[static_cast<std::size_t>(side)];
    Vec3 mean = Vec3::Zero();
    for (const Vec3& x : h) mean += x / static_cast<double>(h.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const Vec3& x : h) cov += (x - mean) * (x - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
    normal[static_cast<std::size_t>(side)] = eig.eigenvectors().col(0);
    offset[static_cast<std::size_t>(side)] = (mean - f.origin).dot(f.n);
    const double angle =
        std::acos(std::min(1.0, std::abs(eig.eigenvectors().col(0).dot(f.n)))) * 180.0 / std::numbers::pi;
    EXPECT_LT(angle, 0.05) << "degrees between the " << (side ? "+n" : "-n") << " wall and the planned plane";
  }
  EXPECT_LT(std::abs(0.5 * (offset[0] + offset[1])), 0.02) << "mid-plane off the plan";
  const BladePathReport path = check_blade_path(guide, slot, p);
  EXPECT_TRUE(path.free) << "guide material in the blade's path near "
                         << (path.blocked ? *path.blocked : Vec3::Zero()).transpose();
  // Housing on both sides over the slot's length, at the closed ends, and nothing in the slot.
  const double z = 0.5 * (p.template_top + p.housing_top);
  for (const double b : {-0.4 * slot.length, 0.0, 0.4 * slot.length}) {
    EXPECT_GT(winding_number(guide, f.at(-half - 0.5 * slot.wall, b, z)), 0.5) << "no housing at -n, " << b;
    EXPECT_GT(winding_number(guide, f.at(half + 0.5 * slot.wall, b, z)), 0.5) << "no housing at +n, " << b;
    EXPECT_LT(winding_number(guide, f.at(0.0, b, z)), 0.5) << "material in the slot at " << b;
  }
  const double end = 0.5 * slot.length + 0.5 * slot.wall;
  EXPECT_EQ(winding_number(guide, f.at(0.0, -end, z)) > 0.5, slot.closed_start) << "start end";
  EXPECT_EQ(winding_number(guide, f.at(0.0, end, z)) > 0.5, slot.closed_end) << "end end";
}

SlotSpec make_slot(const std::string& name, const Vec3& origin, const Vec3& normal, const Vec3& direction, double blade,
                   double length) {
  SlotSpec s;
  s.name = name;
  s.origin = origin;
  s.normal = normal;
  s.direction = direction;
  s.blade = blade;
  s.length = length;
  return s;
}

TemplateOptions plate_template() {
  TemplateOptions o;
  o.boundary_points = {{-15, -15, 0}, {15, -15, 0}, {15, 15, 0}, {-15, 15, 0}};
  o.thickness = 2.5;
  o.clearance = 0.1;
  return o;
}

TEST(Slots, APlateGuideCarriesSlotsAsPlannedWithOpenAndClosedEnds) {
  const TriangleMesh bone = test::make_height_field(-30, 30, -30, 30, 60, [](double x, double y) {
    return 0.02 * x * x - 0.01 * y * y + 0.1 * x; // a gently curved, tilted surface
  });
  TemplateOptions o = plate_template();
  for (Vec3& p : o.boundary_points) p.z() = 0.02 * p.x() * p.x() - 0.01 * p.y() * p.y() + 0.1 * p.x();
  o.slots.push_back(make_slot("across", {0, 0, 0}, {1, 0, 0}, {0, 0, -1}, 1.27, 16));
  SlotSpec tilted = make_slot("tilted", {-8, 2, 0}, {1, 0.3, 0.2}, {0.1, 0, -1}, 0.6, 12);
  tilted.origin.z() = 0.02 * 64 - 0.01 * 4 - 0.8;
  tilted.closed_start = false;
  tilted.clearance = 0.15;
  tilted.wall = 2.0;
  o.slots.push_back(tilted);
  const TemplateResult r = design_template(bone, o);
  test::expect_valid_solid(r.shell);
  EXPECT_EQ(r.solid.components, 1u);
  ASSERT_EQ(r.slots.size(), 2u);
  ASSERT_EQ(r.blade_paths.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_TRUE(r.blade_paths[i].free);
    EXPECT_NEAR(r.slots[i].housing_top - r.slots[i].template_top, o.slots[i].height, 1e-9);
    expect_slot_as_planned(r.shell, o.slots[i], r.slots[i]);
  }
  write_stl(r.shell, test::output_dir() + "/slots-plate.stl");
}

TEST(Slots, TheTibiaWedgeOsteotomyGuideHasBothSlotsAsPlanned) {
  const CaseFile c = read_case(test::examples_dir() + "/cases/tibia-osteotomy.json");
  ASSERT_EQ(c.slots.size(), 2u) << "the example plans its wedge as two slots";
  const TriangleMesh bone = read_mesh(c.bone);
  const TemplateResult r = design_template(bone, st::test::case_options(c));
  test::expect_valid_solid(r.shell);
  EXPECT_EQ(r.solid.components, 1u);
  for (std::size_t i = 0; i < c.slots.size(); ++i) {
    EXPECT_TRUE(r.slots[i].meets.empty()) << c.slots[i].name << " meets " << r.slots[i].meets.front();
    expect_slot_as_planned(r.shell, c.slots[i], r.slots[i]);
  }
}

TEST(Slots, TheFlapHarvestGuideHasOneSlotPerPlaneEachClosedOnOneSide) {
  const CaseFile c = read_case(test::examples_dir() + "/cases/tibia-segment-flap.json");
  ASSERT_EQ(c.slots.size(), 2u);
  for (const SlotSpec& s : c.slots) EXPECT_NE(s.closed_start, s.closed_end) << s.name << ": closed on one side";
  const double apart = std::abs((c.slots[1].origin - c.slots[0].origin).dot(c.slots[0].normal));
  EXPECT_GE(apart, 20.0);
  EXPECT_LE(apart, 40.0);
  const TriangleMesh bone = read_mesh(c.bone);
  const TemplateResult r = design_template(bone, st::test::case_options(c));
  test::expect_valid_solid(r.shell);
  EXPECT_EQ(r.solid.components, 1u);
  for (std::size_t i = 0; i < c.slots.size(); ++i) {
    EXPECT_TRUE(r.blade_paths[i].free) << c.slots[i].name;
    expect_slot_as_planned(r.shell, c.slots[i], r.slots[i]);
  }
}

TEST(Slots, PlanesFromASlicerPlanGiveSlotsWhoseSawTravelsIntoTheBone) {
  // The flap example's planes as 3D Slicer saves them: no travel, blade and length chosen by the user.
  CaseFile c = read_case(test::examples_dir() + "/cases/tibia-segment-flap.json");
  const std::vector<SlotSpec> planned = c.slots;
  SlotSizes sizes;
  sizes.blade = find_blade_preset(default_blade_presets(), "sagittal-0.89");
  sizes.length = 14.0;
  apply_plan(c, read_plan(test::examples_dir() + "/plans/tibia-flap-planes.mrk.json", mesh_file_space(c.bone)),
             std::nullopt, PlanTubes::Replace, sizes);
  ASSERT_EQ(c.slots.size(), 2u);
  const TriangleMesh bone = read_mesh(c.bone);
  const TemplateResult r = design_template(bone, st::test::case_options(c));
  test::expect_valid_solid(r.shell);
  EXPECT_EQ(r.solid.components, 1u);
  for (std::size_t i = 0; i < c.slots.size(); ++i) {
    ASSERT_TRUE(c.slots[i].auto_direction);
    const Vec3 d = r.slots[i].direction;
    EXPECT_NEAR(d.norm(), 1.0, 1e-12);
    EXPECT_LT(std::abs(d.dot(c.slots[i].normal)), 1e-12) << "the saw travels in the cut plane";
    // Into the bone: within 30 degrees of the travel the example plans by hand, and the bone lies
    // ahead of the origin along it.
    EXPECT_GT(d.dot(planned[i].direction), std::cos(30.0 * std::numbers::pi / 180.0)) << c.slots[i].name;
    EXPECT_TRUE(AabbTree(bone).first_hit(c.slots[i].origin - 5.0 * d, d, 0.0, 10.0)) << c.slots[i].name;
    EXPECT_TRUE(r.blade_paths[i].free) << c.slots[i].name;
    SlotSpec as_built = c.slots[i];
    as_built.direction = d;
    as_built.auto_direction = false;
    expect_slot_as_planned(r.shell, as_built, r.slots[i]);
  }
}

TEST(Slots, ASlotWithoutTravelIsRefusedByNameWhereTheBoneGivesNone) {
  const TriangleMesh plate = test::make_height_field(-30, 30, -30, 30, 30, [](double, double) { return 0.0; });
  const AabbTree tree(plate);
  SlotSpec s = make_slot("flat", {0, 0, 0}, {0, 0, 1}, {1, 0, 0}, 0.89, 10);
  s.auto_direction = true;
  // The plane lies along the surface: no way into the bone within it.
  try {
    slot_direction(s, tree);
    ADD_FAILURE() << "a plane along the surface was given a travel";
  } catch (const GeometryError& e) {
    EXPECT_NE(std::string(e.what()).find("slot 'flat'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("along the surface"), std::string::npos) << e.what();
  }
  // No bone near the origin.
  s.origin = {0, 0, 50};
  s.normal = {1, 0, 0};
  EXPECT_THROW(slot_direction(s, tree), GeometryError);
  // Across the plate: straight down into it.
  s.origin = {0, 0, 0};
  EXPECT_LT((slot_direction(s, tree) - Vec3(0, 0, -1)).norm(), 1e-9);
}

TEST(Slots, RandomSlotsOnRealTemplatesAreAsPlannedOrRefusedByName) {
  // Slots anywhere over the template (origins on its covered bone, planes through random directions
  // around the surface normal, random sizes and ends): each guide is valid with its slot as planned,
  // or the slot is refused with a message naming it.
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), blade(0.4, 1.5), length(8.0, 25.0);
  for (const char* name : {"tibia-osteotomy", "sacrum-iliosacral"}) {
    CaseFile c = read_case(test::examples_dir() + "/cases/" + std::string(name) + ".json");
    c.slots.clear();
    c.labels.clear(); // a random slot may cross the planned label
    c.tubes.clear();
    const TriangleMesh bone = read_mesh(c.bone);
    TemplateOptions base = st::test::case_options(c);
    base.analyse_insertion = false;
    const TemplateResult plain = design_template(bone, base);
    const std::vector<Vec3> normals = vertex_normals(plain.inner); // away from the bone
    int built = 0, refused = 0;
    for (int trial = 0; trial < random_slots(); ++trial) {
      SCOPED_TRACE(std::string(name) + " slot " + std::to_string(trial));
      const Index v = std::uniform_int_distribution<Index>(0, plain.inner.vertex_count() - 1)(rng);
      const Vec3 origin = plain.inner.positions[v];
      const Vec3 normal = normals[v];
      Vec3 across = Vec3(unit(rng), unit(rng), unit(rng)).cross(normal);
      if (across.norm() < 1e-3) continue;
      SlotSpec s = make_slot("s" + std::to_string(trial), origin, across.normalized(),
                             -normal + 0.3 * Vec3(unit(rng), unit(rng), unit(rng)), blade(rng), length(rng));
      s.closed_start = unit(rng) > -0.5;
      s.closed_end = unit(rng) > -0.5;
      TemplateOptions o = base;
      o.slots = {s};
      try {
        const TemplateResult r = design_template(bone, o);
        test::expect_valid_solid(r.shell);
        expect_slot_as_planned(r.shell, s, r.slots[0]);
        ++built;
      } catch (const GeometryError& e) {
        EXPECT_NE(std::string(e.what()).find("slot '" + s.name + "'"), std::string::npos) << e.what();
        ++refused;
      }
    }
    std::printf("%s: %d random slots built as planned, %d refused by name\n", name, built, refused);
    EXPECT_GT(built, refused) << name;
  }
}

TEST(Slots, BadSlotsAreRefusedNamingTheSlotAndTheKey) {
  const TriangleMesh bone = test::make_height_field(-30, 30, -30, 30, 30, [](double, double) { return 0.0; });
  TemplateOptions o = plate_template();
  auto refused = [&](SlotSpec s, const std::string& words) {
    o.slots = {std::move(s)};
    try {
      design_template(bone, o);
      ADD_FAILURE() << "accepted; expected: " << words;
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  const SlotSpec good = make_slot("a", {0, 0, 0}, {1, 0, 0}, {0, 0, -1}, 1.0, 10);
  SlotSpec s = good;
  s.blade = 0.0;
  refused(s, "slot 'a': blade must be > 0");
  s = good;
  s.direction = {2, 0, 0};
  refused(s, "slot 'a': direction must not be parallel to normal");
  s = good;
  s.clearance = -0.1;
  refused(s, "slot 'a': clearance must be >= 0");
  s = good;
  s.length = std::nan("");
  refused(s, "slot 'a': length must be > 0");
  s = good;
  s.origin = {100, 100, 0}; // beside the template
  refused(s, "slot 'a' misses the template");
}

TEST(Slots, ACaseFileWithSlotsReadsWritesAndRefusesBadKeys) {
  const std::string dir = test::output_dir();
  const std::string path = dir + "/slots-case.json";
  auto text = [](const std::string& slot) {
    return std::string(R"({"format": "surgical-template-case/1", "bone": "b.stl",
      "boundary": {"points": [[0,0,0],[1,0,0],[0,1,0]]}, "template": {"thickness": 2},
      "slots": [)") +
           slot + "]}";
  };
  const CaseFile c = parse_case(text(R"({"name": "cut 1", "origin": [1, 2, 3], "normal": [0, 0, 2],
      "direction": [0, 1, 1], "blade": 1.27, "length": 20, "closed": ["end"], "wall": 2.5})"),
                                path);
  ASSERT_EQ(c.slots.size(), 1u);
  const SlotSpec& s = c.slots[0];
  EXPECT_EQ(s.name, "cut 1");
  EXPECT_NEAR((s.normal - Vec3(0, 0, 1)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((s.direction - Vec3(0, 1, 0)).norm(), 0.0, 1e-12) << "the normal's component is removed";
  EXPECT_FALSE(s.closed_start);
  EXPECT_TRUE(s.closed_end);
  EXPECT_DOUBLE_EQ(s.clearance, 0.1);
  EXPECT_DOUBLE_EQ(s.height, 5.0);
  EXPECT_DOUBLE_EQ(s.wall, 2.5);
  const CaseFile back = parse_case(case_json(c, path), path);
  ASSERT_EQ(back.slots.size(), 1u);
  EXPECT_EQ(back.slots[0].name, s.name);
  EXPECT_EQ(back.slots[0].closed_start, s.closed_start);
  EXPECT_EQ(back.slots[0].closed_end, s.closed_end);
  EXPECT_DOUBLE_EQ(back.slots[0].blade, s.blade);
  auto refused = [&](const std::string& slot, const std::string& words) {
    try {
      parse_case(text(slot), path);
      ADD_FAILURE() << "accepted: " << slot;
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  const std::string base = R"("name": "x", "origin": [0,0,0], "normal": [1,0,0], "direction": [0,0,-1], "length": 5)";
  refused("{" + base + "}", "slots[0].blade: is required");
  refused("{" + base + R"(, "blade": -1})", "slots[0].blade: must be > 0");
  refused("{" + base + R"(, "blade": 1, "closed": ["middle"]})", "slots[0].closed");
  refused("{" + base + R"(, "blade": 1, "wall": "thick"})", "slots[0].wall: must be a number");
  refused(R"({"origin": [0,0,0], "normal": [1,0,0], "direction": [0,0,-1], "length": 5, "blade": 1})",
          "slots[0].name: is required");
  refused("{" + base + R"(, "blade": 1}, {)" + base + R"(, "blade": 1})", "slots[1].name");
}

} // namespace
} // namespace st
