// Cut planes from planning software: 3D Slicer Plane markups (Slicer 5's centre and normal, 4.11's
// three points, a point with an orientation) and CSV tables of planes, made into saw slots by
// apply_plan with the chosen blade and length; malformed planes refused naming the file and the plane.

#include "helpers.h"

#include "st/core/errors.h"
#include "st/io/case_file.h"
#include "st/io/plan.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

using namespace st;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) { return st::test::scratch_dir("plan-planes", name); }

std::string write(const fs::path& path, const std::string& text) { return st::test::write_text(path, text); }

template <class F> std::string error_of(F&& f) { return st::test::invalid_input_of(std::forward<F>(f)); }

void expect_near(const Vec3& a, const Vec3& b, double tol = 1e-12) {
  EXPECT_LE((a - b).norm(), tol) << a.transpose() << " vs " << b.transpose();
}

std::string markups(const std::string& list) { return R"({"markups": [)" + list + "]}"; }

} // namespace

TEST(PlanPlanes, SlicerPlanesAreReadInEachOfTheirFormsIntoTheBonesFrame) {
  // Slicer 5: centre and normal, here in RAS for an LPS bone (x and y change sign; the normal is a direction).
  const Plan five = parse_markups(markups(R"({"type": "Plane", "name": "osteotomy", "coordinateSystem": "RAS",
      "planeType": "pointNormal", "center": [10, 20, 30], "normal": [0, 0, 2],
      "controlPoints": [{"position": [10, 20, 30]}]})"),
                                  "five.mrk.json", Space::LPS);
  ASSERT_EQ(five.planes.size(), 1u);
  EXPECT_EQ(five.planes[0].name, "osteotomy");
  expect_near(five.planes[0].origin, {-10, -20, 30});
  expect_near(five.planes[0].normal, {0, 0, 1});
  EXPECT_FALSE(five.planes[0].direction) << "the travel is left to slot_direction";
  EXPECT_FALSE(five.planes[0].blade);

  // Slicer 4.11: three control points (origin first), no name; micrometres scaled to mm.
  const Plan three = parse_markups(markups(R"({"type": "Plane", "coordinateUnits": "um", "controlPoints": [
      {"position": [1000, 0, 0]}, {"position": [2000, 0, 0]}, {"position": [1000, 1000, 0]}]})"),
                                   "three.mrk.json", Space::LPS);
  ASSERT_EQ(three.planes.size(), 1u);
  EXPECT_EQ(three.planes[0].name, "Plane 1");
  expect_near(three.planes[0].origin, {1, 0, 0});
  expect_near(three.planes[0].normal, {0, 0, 1});

  // A point with an orientation whose third column is the normal (here x).
  const Plan oriented = parse_markups(markups(R"({"type": "Plane", "orientation": [0, 0, 1, 0, 1, 0, -1, 0, 0],
      "controlPoints": [{"position": [5, 6, 7]}]})"),
                                      "o.mrk.json", Space::LPS);
  ASSERT_EQ(oriented.planes.size(), 1u);
  expect_near(oriented.planes[0].origin, {5, 6, 7});
  expect_near(oriented.planes[0].normal, {1, 0, 0});

  // A plan of planes only is a plan; a plane without a normal is refused by its markup.
  const auto refused = [](const std::string& plane, const std::string& words) {
    const std::string e = error_of([&] { parse_markups(markups(plane), "bad.mrk.json", Space::LPS); });
    EXPECT_NE(e.find("bad.mrk.json"), std::string::npos) << e;
    EXPECT_NE(e.find("markups[0]"), std::string::npos) << e;
    EXPECT_NE(e.find(words), std::string::npos) << e;
  };
  refused(R"({"type": "Plane", "controlPoints": [{"position": [0, 0, 0]}]})", "3 control points");
  refused(R"({"type": "Plane", "center": [0, 0, 0], "normal": [0, 0, 0]})", "normal is zero");
  refused(R"({"type": "Plane", "controlPoints": [{"position": [0, 0, 0]}, {"position": [1, 0, 0]},
      {"position": [2, 0, 0]}]})",
          "normal is zero");
  refused(R"({"type": "Plane", "orientation": [1, 2], "controlPoints": [{"position": [0, 0, 0]}]})", "9 numbers");
}

TEST(PlanPlanes, CsvTablesOfPlanesGiveSlotsWithTheirSizesAndEnds) {
  const fs::path dir = scratch("csv");
  const std::string path = write(dir / "cuts.csv", "# space=RAS\n"
                                                   "name;origin_x;origin_y;origin_z;normal_x;normal_y;normal_z;"
                                                   "direction_x;direction_y;direction_z;blade;length;closed\n"
                                                   "proximal;1;2;3;0;0;1;;;;0.89;14;end\n"
                                                   "distal;4;5;6;0;0;-1;0;1;0;;;start end\n");
  const Plan plan = read_plan(path, Space::LPS);
  ASSERT_EQ(plan.planes.size(), 2u);
  EXPECT_TRUE(plan.axes.empty());
  expect_near(plan.planes[0].origin, {-1, -2, 3});
  EXPECT_FALSE(plan.planes[0].direction);
  EXPECT_DOUBLE_EQ(*plan.planes[0].blade, 0.89);
  ASSERT_TRUE(plan.planes[0].closed);
  EXPECT_FALSE((*plan.planes[0].closed)[0]);
  EXPECT_TRUE((*plan.planes[0].closed)[1]);
  expect_near(*plan.planes[1].direction, {0, -1, 0});
  EXPECT_TRUE((*plan.planes[1].closed)[0] && (*plan.planes[1].closed)[1]);

  // Into a case: the blade and length the plan lacks from the chosen ones, else refused by the plane.
  CaseFile c = read_case(st::test::examples_dir() + "/cases/tibia-segment-flap.json");
  c.slots.clear();
  const auto missing = error_of([&] { apply_plan(c, plan, std::nullopt); });
  EXPECT_NE(missing.find("\"distal\""), std::string::npos) << missing;
  EXPECT_NE(missing.find("blade"), std::string::npos) << missing;
  EXPECT_TRUE(c.slots.empty()) << "nothing changes before the plan is whole";
  SlotSizes sizes;
  sizes.blade = find_blade_preset(default_blade_presets(), "sagittal-1.27");
  EXPECT_NE(error_of([&] { apply_plan(c, plan, std::nullopt, PlanTubes::Replace, sizes); }).find("length"),
            std::string::npos);
  sizes.length = 20.0;
  apply_plan(c, plan, std::nullopt, PlanTubes::Replace, sizes);
  ASSERT_EQ(c.slots.size(), 2u);
  EXPECT_DOUBLE_EQ(c.slots[0].blade, 0.89) << "the plan's own blade";
  EXPECT_DOUBLE_EQ(c.slots[0].clearance, 0.1);
  EXPECT_DOUBLE_EQ(c.slots[0].length, 14.0);
  EXPECT_TRUE(c.slots[0].auto_direction);
  EXPECT_DOUBLE_EQ(c.slots[1].blade, 1.27) << "the chosen blade";
  EXPECT_DOUBLE_EQ(c.slots[1].length, 20.0);
  EXPECT_FALSE(c.slots[1].auto_direction);
  // Added a second time, the names are taken.
  EXPECT_NE(error_of([&] { apply_plan(c, plan, std::nullopt, PlanTubes::Add, sizes); }).find("planned already"),
            std::string::npos);
  // A case written back keeps a slot without a travel as one.
  const CaseFile again = parse_case(case_json(c, c.path), c.path);
  EXPECT_TRUE(again.slots[0].auto_direction);
  EXPECT_FALSE(again.slots[1].auto_direction);

  const auto refused = [&](const std::string& text, const std::string& words) {
    const std::string e = error_of([&] { read_plan(write(dir / "bad.csv", text), Space::LPS); });
    EXPECT_NE(e.find(words), std::string::npos) << e;
  };
  refused("name,origin_x,origin_y,origin_z,normal_x,normal_y\n", "no column \"normal_z\"");
  refused("name,origin_x,origin_y,origin_z,normal_x,normal_y,normal_z\na,0,0,0,0,0,0\n", "bad.csv:2");
  refused("name,origin_x,origin_y,origin_z,normal_x,normal_y,normal_z,closed\na,0,0,0,0,0,1,sides\n", "closed");
  refused("name,origin_x,origin_y,origin_z,normal_x,normal_y,normal_z\n", "holds no planes");
}

TEST(PlanPlanes, TheExamplePlanesAreTheFlapCasesSlots) {
  // The Slicer file of the free-flap example holds its two planes, in the bone's frame.
  const CaseFile flap = read_case(st::test::examples_dir() + "/cases/tibia-segment-flap.json");
  const Plan plan =
      read_plan(st::test::examples_dir() + "/plans/tibia-flap-planes.mrk.json", mesh_file_space(flap.bone));
  ASSERT_EQ(plan.planes.size(), flap.slots.size());
  for (std::size_t i = 0; i < plan.planes.size(); ++i) {
    EXPECT_EQ(plan.planes[i].name, flap.slots[i].name);
    expect_near(plan.planes[i].origin, flap.slots[i].origin, 1e-9);
    expect_near(plan.planes[i].normal, flap.slots[i].normal, 1e-5);
  }
  const Plan csv = read_plan(st::test::examples_dir() + "/plans/tibia-flap-planes.csv", mesh_file_space(flap.bone));
  ASSERT_EQ(csv.planes.size(), flap.slots.size());
  for (std::size_t i = 0; i < csv.planes.size(); ++i) {
    expect_near(csv.planes[i].origin, flap.slots[i].origin, 1e-9);
    expect_near(csv.planes[i].normal, flap.slots[i].normal, 1e-5);
  }
}
