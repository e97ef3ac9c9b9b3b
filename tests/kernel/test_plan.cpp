// Plans from planning software: 3D Slicer markups in LPS and RAS, CSV tables of axes, case files
// naming markups, the sleeve catalogue; malformed plans refused naming the file and the entry.

#include "helpers.h"

#include "st/io/case_file.h"
#include "st/core/errors.h"
#include "st/io/mesh_io.h"
#include "st/io/plan.h"
#include "st/design/template_design.h"
#include "st/validate/validate.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

using namespace st;
namespace fs = std::filesystem;

namespace {

const std::string kSchema =
    R"("@schema": "https://raw.githubusercontent.com/slicer/slicer/master/Modules/Loadable/Markups/Resources/Schema/markups-schema-v1.0.3.json#")";

/// A folder of its own for a test's files.
fs::path scratch(const std::string& name) { return st::test::scratch_dir("plan", name); }

std::string write(const fs::path& path, const std::string& text) { return st::test::write_text(path, text); }

template <class F> std::string error_of(F&& f) { return st::test::invalid_input_of(std::forward<F>(f)); }

void expect_near(const Vec3& a, const Vec3& b, double tol = 1e-12) {
  EXPECT_LE((a - b).norm(), tol) << a.transpose() << " vs " << b.transpose();
}

const std::string kMarkups = "{" + kSchema + R"(, "markups": [
  {"type": "ClosedCurve", "coordinateSystem": "RAS", "coordinateUnits": "mm", "name": "CC",
   "controlPoints": [
     {"id": "1", "label": "CC-1", "position": [-10.0, -20.0, 5.0], "positionStatus": "defined"},
     {"id": "2", "label": "CC-2", "position": [-12.0, -25.0, 6.0], "positionStatus": "defined"},
     {"id": "3", "label": "CC-3", "position": [-8.0, -26.0, 7.0], "positionStatus": "undefined"},
     {"id": "4", "label": "CC-4", "position": [-7.0, -22.0, 5.5]}],
   "display": {"visibility": true, "color": [0.4, 1.0, 1.0]}},
  {"type": "Line", "coordinateSystem": "LPS", "name": "16",
   "controlPoints": [{"label": "16-1", "position": [1.0, 2.0, 3.0]}, {"label": "16-2", "position": [1.0, 2.0, -9.0]}]},
  {"type": "Line", "controlPoints": [{"label": "L-1", "position": [0, 0, 0]}, {"label": "L-2", "position": [3, 4, 0]}]},
  {"type": "Fiducial", "coordinateSystem": "RAS", "controlPoints": [{"label": "inside", "position": [-9.0, -23.0, 6.0]}]},
  {"type": "Angle", "controlPoints": []}
]})";

} // namespace

TEST(Plan, MeshSpaceComesFromTheHeader) {
  EXPECT_EQ(mesh_space("solid bone SPACE=RAS"), Space::RAS);
  EXPECT_EQ(mesh_space("3D Slicer output. space = ras"), Space::RAS);
  EXPECT_EQ(mesh_space("3D Slicer output. SPACE=LPS"), Space::LPS);
  EXPECT_EQ(mesh_space(""), Space::LPS);
  expect_near(convert_space({1, 2, 3}, Space::LPS, Space::RAS), {-1, -2, 3});
  expect_near(convert_space({1, 2, 3}, Space::RAS, Space::RAS), {1, 2, 3});
}

// The frame from a mesh file's start agrees with the header the full reader reports, for every format
// and compressed, and for the example meshes.
TEST(Plan, MeshFileSpaceFromTheFilesStart) {
  const fs::path dir = scratch("mesh-space");
  const TriangleMesh tet = st::test::make_icosphere(1.0, 0);
  struct File {
    std::string name, text;
    Space expect;
  } files[] = {
      {"a.ply",
       "ply\nformat ascii 1.0\ncomment made by Slicer SPACE=RAS\nelement vertex 3\nproperty float x\n"
       "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n"
       "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
       Space::RAS},
      {"b.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
       "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"
       "comment SPACE=RAS after the header is data, not a header\n",
       Space::LPS},
      {"c.obj", "# SPACE=RAS\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", Space::RAS},
      {"d.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", Space::LPS},
      {"e.stl",
       "solid bone SPACE=RAS\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
       "endloop\nendfacet\nendsolid bone\n",
       Space::RAS},
  };
  for (const File& f : files) {
    const std::string path = write(dir / f.name, f.text);
    EXPECT_EQ(mesh_file_space(path), f.expect) << f.name;
    ReadReport report;
    if (f.name != "b.ply") {
      read_mesh(path, &report);
      EXPECT_EQ(mesh_space(report.header), f.expect) << f.name;
    }
  }
  write_stl(tet, (dir / "f.stl").string(), "3D Slicer output. SPACE=RAS");
  EXPECT_EQ(mesh_file_space((dir / "f.stl").string()), Space::RAS);
  write_stl(tet, (dir / "g.stl").string(), "3D Slicer output. SPACE=LPS");
  EXPECT_EQ(mesh_file_space((dir / "g.stl").string()), Space::LPS);
  for (const auto& entry : fs::directory_iterator(st::test::examples_dir() + "/meshes")) {
    if (entry.path().extension() != ".gz") continue;
    ReadReport report;
    read_mesh(entry.path().string(), &report);
    EXPECT_EQ(mesh_file_space(entry.path().string()), mesh_space(report.header)) << entry.path();
  }
  EXPECT_NE(error_of([&] { mesh_file_space((dir / "missing.stl").string()); }).find("cannot open"), std::string::npos);
}

TEST(Plan, SlicerMarkupsIntoAnLpsBone) {
  const Plan p = parse_markups(kMarkups, "plan.mrk.json", Space::LPS);
  // The curve was in RAS: x and y change sign; the undefined point is skipped and reported.
  ASSERT_EQ(p.boundary_points.size(), 3u);
  expect_near(p.boundary_points[0], {10, 20, 5});
  expect_near(p.boundary_points[2], {7, 22, 5.5});
  ASSERT_TRUE(p.inside);
  expect_near(*p.inside, {9, 23, 6});
  ASSERT_EQ(p.axes.size(), 2u);
  EXPECT_EQ(p.axes[0].name, "16");
  expect_near(p.axes[0].entry, {1, 2, 3});
  expect_near(p.axes[0].direction, {0, 0, -1});
  EXPECT_DOUBLE_EQ(*p.axes[0].depth, 12.0);
  EXPECT_FALSE(p.axes[0].inner_radius);
  EXPECT_EQ(p.axes[1].name, "L-1"); // no markup name: its first point's label
  expect_near(p.axes[1].direction, {0.6, 0.8, 0});
  EXPECT_DOUBLE_EQ(*p.axes[1].depth, 5.0);
  bool skipped = false, ignored = false;
  for (const std::string& w : p.warnings) {
    skipped |= w.find("controlPoints[2]") != std::string::npos && w.find("undefined") != std::string::npos;
    ignored |= w.find("Angle") != std::string::npos;
  }
  EXPECT_TRUE(skipped && ignored);
}

TEST(Plan, SlicerMarkupsIntoARasBone) {
  const Plan lps = parse_markups(kMarkups, "plan.mrk.json", Space::LPS);
  const Plan ras = parse_markups(kMarkups, "plan.mrk.json", Space::RAS);
  for (std::size_t i = 0; i < lps.boundary_points.size(); ++i)
    expect_near(ras.boundary_points[i], convert_space(lps.boundary_points[i], Space::LPS, Space::RAS));
  expect_near(ras.boundary_points[0], {-10, -20, 5}); // RAS curve into a RAS bone: unchanged
  expect_near(ras.axes[0].entry, {-1, -2, 3});
  expect_near(ras.axes[1].direction, {-0.6, -0.8, 0});
}

TEST(Plan, CoordinateUnitsAsSlicersCodedEntry) {
  const std::string text =
      "{" + kSchema + R"(, "markups": [{"type": "Line", "coordinateUnits": ["um", "UCUM", "micrometer"],
    "controlPoints": [{"position": [0, 0, 0]}, {"position": [0, 0, -4000]}]}]})";
  EXPECT_DOUBLE_EQ(*parse_markups(text, "coded.mrk.json", Space::LPS).axes[0].depth, 4.0);
}

TEST(Plan, MicrometreMarkupsAreScaledAndPointListsMakeBoundaries) {
  const std::string text = "{" + kSchema + R"(, "markups": [
    {"type": "Fiducial", "coordinateUnits": {"CodeValue": "um", "CodingSchemeDesignator": "UCUM", "CodeMeaning": "micrometer"},
     "controlPoints": [{"position": [1000, 0, 0]}, {"position": [0, 2000, 0]}, {"position": [0, 0, 3000]}]}]})";
  const Plan p = parse_markups(text, "um.mrk.json", Space::LPS);
  ASSERT_EQ(p.boundary_points.size(), 3u);
  expect_near(p.boundary_points[1], {0, 2, 0});
  EXPECT_TRUE(p.axes.empty());
}

TEST(Plan, MalformedMarkupsNameTheFileAndTheEntry) {
  const auto markups = [](const std::string& body) { return "{" + kSchema + R"(, "markups": [)" + body + "]}"; };
  struct Bad {
    std::string text, expect;
  } bad[] = {
      {"{\"markups\": [", "not valid JSON"},
      {"[1, 2]", "(top level)"},
      {"{\"controlPoints\": []}", "markups: is required"},
      {markups(R"({"type": "Line", "controlPoints": [{"position": [0,0,0]}]})"), "markups[0] (Line)"},
      {markups(R"({"type": "Line", "controlPoints": [{"position": [1,1,1]}, {"position": [1,1,1]}]})"), "coincide"},
      {markups(R"({"type": "Line", "coordinateSystem": "XYZ", "controlPoints": []})"), "markups[0].coordinateSystem"},
      {markups(R"({"type": "Line", "coordinateUnits": "inch", "controlPoints": []})"), "coordinateUnits"},
      {markups(R"({"type": "ClosedCurve", "controlPoints": [{"position": [0,0,"a"]}]})"),
       "markups[0].controlPoints[0].position[2]"},
      {markups(R"({"type": "ClosedCurve", "controlPoints": [{"position": [0,0,1e999]}]})"), "not valid JSON"},
      {markups(R"({"type": "ClosedCurve", "controlPoints": [{"position": [0,0,0]}, {"position": [1,0,0]}]})"),
       "at least 3"},
      {markups(R"({"type": "ClosedCurve", "controlPoints": [{"label": "x"}]})"),
       "controlPoints[0].position: is required"},
      {markups(R"({"controlPoints": []})"), "markups[0].type: is required"},
      {markups(R"({"type": "Angle"})"), "nothing to plan with"},
  };
  for (const Bad& b : bad) {
    const std::string message = error_of([&] { parse_markups(b.text, "bad.mrk.json", Space::LPS); });
    EXPECT_NE(message.find("bad.mrk.json"), std::string::npos) << message;
    EXPECT_NE(message.find(b.expect), std::string::npos) << "expected '" << b.expect << "' in: " << message;
  }
}

TEST(Plan, CsvOfAxesWithDirectionsOrTargets) {
  const Plan p = parse_plan_csv(
      "\xEF\xBB\xBF# implant axes\r\n"
      "Name;Entry X "
      "(mm);entry_y;entry_z;target_x;target_y;target_z;inner_diameter;outer_diameter;length;offset;comment\r\n"
      "\"16; upper right\";1;2;3;1;2;-7;2.2;4.4;5;3;first\r\n"
      "\r\n"
      "13;0;0;0;0;4;3;2.2;4.4;6;;\r\n",
      "axes.csv", Space::LPS);
  ASSERT_EQ(p.axes.size(), 2u);
  EXPECT_EQ(p.axes[0].name, "16; upper right");
  EXPECT_EQ(p.axes[0].source, "axes.csv:3");
  expect_near(p.axes[0].entry, {1, 2, 3});
  expect_near(p.axes[0].direction, {0, 0, -1});
  EXPECT_DOUBLE_EQ(*p.axes[0].depth, 10.0);
  EXPECT_DOUBLE_EQ(*p.axes[0].inner_radius, 1.1);
  EXPECT_DOUBLE_EQ(*p.axes[0].outer_radius, 2.2);
  EXPECT_DOUBLE_EQ(*p.axes[0].offset, 3.0);
  expect_near(p.axes[1].direction, {0, 0.8, 0.6});
  EXPECT_DOUBLE_EQ(*p.axes[1].length, 6.0);
  EXPECT_FALSE(p.axes[1].offset); // empty field: not given
  ASSERT_FALSE(p.warnings.empty());
  EXPECT_NE(p.warnings[0].find("comment"), std::string::npos);

  const Plan d = parse_plan_csv("name,entry_x,entry_y,entry_z,direction_x,direction_y,direction_z,length [mm]\n"
                                "A,1,2,3,0,0,+2,5\n#B,1,2,3,0,0,1,5\n",
                                "d.csv", Space::LPS);
  ASSERT_EQ(d.axes.size(), 1u);
  expect_near(d.axes[0].direction, {0, 0, 1});
  EXPECT_FALSE(d.axes[0].depth);
  EXPECT_DOUBLE_EQ(*d.axes[0].length, 5.0);
  ASSERT_EQ(d.warnings.size(), 1u); // the '#B' row is a comment, and said to be one
  EXPECT_NE(d.warnings[0].find("d.csv:3: starts with '#'"), std::string::npos);
  // A file that names its frame is converted into the bone's; without, it is taken in the bone's frame.
  const std::string ras = "# space=RAS\nname\tentry_x\tentry_y\tentry_z\tdirection_x\tdirection_y\tdirection_z\n"
                          "A\t1\t2\t3\t1\t0\t0\n";
  const Plan to_lps = parse_plan_csv(ras, "ras.csv", Space::LPS);
  expect_near(to_lps.axes[0].entry, {-1, -2, 3});
  expect_near(to_lps.axes[0].direction, {-1, 0, 0});
  expect_near(parse_plan_csv(ras, "ras.csv", Space::RAS).axes[0].entry, {1, 2, 3});
}

TEST(Plan, MalformedCsvNamesTheLineAndTheColumn) {
  const std::string head = "name,entry_x,entry_y,entry_z,direction_x,direction_y,direction_z\n";
  struct Bad {
    std::string text, expect;
  } bad[] = {
      {"", "empty"},
      {"# only a comment\n", "empty"},
      {"name entry_x\n", "bad.csv:1: the first line must name the columns"},
      {"name,entry_x,entry_y\nA,1,2\n", "bad.csv:1: no column \"entry_z\""},
      {"name,entry_x,entry_y,entry_z\nA,1,2,3\n", "either direction"},
      {"name,entry_x,entry_y,entry_z,direction_x,direction_y,direction_z,target_x,target_y,target_z\n",
       "either direction"},
      {"name,entry_x,entry_y,entry_z,direction_x\n", "no column \"direction_y\""},
      {"entry_x,entry_x,entry_y,entry_z,direction_x,direction_y,direction_z\n", "appears twice"},
      {head, "holds no axes"},
      {head + "A,1,2,3,0,0\n", "bad.csv:2: has 6 fields, the header names 7"},
      {head + "A,1,2,3,0,0,1\nB,1,x,3,0,0,1\n", "bad.csv:3: entry_y: \"x\" is not a number"},
      {head + "A,1,,3,0,0,1\n", "bad.csv:2: entry_y: is empty"},
      {head + "A,1,2,3,0,0,1e999\n", "bad.csv:2: direction_z: \"1e999\" is out of range"},
      {head + "A,1,2,3,0,0,nan\n", "\"nan\" is not a finite number"},
      {head + "A,1,2,3,0,0,0x10\n", "\"0x10\" is not a number"},
      {head + "A,1,2,3,0,0,1,2\n", "has 8 fields"},
      {"name,entry_x,entry_y,entry_z,direction_x,direction_y,direction_z,length (cm)\n", "lengths must be in mm"},
      {head + "# space=RAS\nA,1,2,3,0,0,1\n", "bad.csv:2: the space line must come before the column names"},
      {head + "A,1,2,3,0,0,0\n", "non-zero"},
      {head + "\"A,1,2,3,0,0,1\n", "not closed"},
      {"# space=XYZ\n" + head, "space must be LPS or RAS"},
      {"name,entry_x,entry_y,entry_z,target_x,target_y,target_z\nA,1,2,3,1,2,3\n", "must differ from the entry"},
      {"name,entry_x,entry_y,entry_z,direction_x,direction_y,direction_z,inner_radius,inner_diameter\n", "not both"},
      {std::string("name,entry_x\0,y", 15) + "\n", "binary"},
  };
  for (const Bad& b : bad) {
    const std::string message = error_of([&] { parse_plan_csv(b.text, "bad.csv", Space::LPS); });
    EXPECT_NE(message.find(b.expect), std::string::npos) << "expected '" << b.expect << "' in: " << message;
  }
}

TEST(Plan, SleeveCatalogue) {
  const std::vector<SleevePreset>& presets = default_sleeve_presets();
  ASSERT_GE(presets.size(), 5u);
  for (const SleevePreset& p : presets) {
    EXPECT_GT(p.inner_radius, 0.0);
    EXPECT_GT(p.outer_radius, p.inner_radius);
    EXPECT_GT(p.length, 0.0);
  }
  EXPECT_EQ(&find_sleeve_preset(presets, "PILOT-2.0"), &find_sleeve_preset(presets, "pilot-2.0"));
  EXPECT_NE(error_of([&] { find_sleeve_preset(presets, "nope"); }).find("\"pilot-2.0\""), std::string::npos);

  const auto catalogue = [](const std::string& sleeves) {
    return R"({"format": "surgical-template-sleeves/1", "sleeves": [)" + sleeves + "]}";
  };
  const std::vector<SleevePreset> mine = parse_sleeve_presets(
      catalogue(R"({"name": "M", "inner_diameter": 3, "outer_diameter": 5, "length": 8, "offset": 1})"), "my.json");
  ASSERT_EQ(mine.size(), 1u);
  EXPECT_DOUBLE_EQ(mine[0].inner_radius, 1.5);
  EXPECT_DOUBLE_EQ(mine[0].outer_radius, 2.5);
  EXPECT_NE(error_of([&] {
              parse_sleeve_presets(catalogue(R"({"name": "M", "inner_diameter": 5, "outer_diameter": 3, "length": 8})"),
                                   "my.json");
            }).find("my.json: sleeves[0].outer_diameter: must be > inner_radius"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              parse_sleeve_presets(catalogue(R"({"name": "M", "inner_diameter": 1, "outer_diameter": 3, "length": 8},
                                                {"name": "M", "inner_diameter": 1, "outer_diameter": 3, "length": 8})"),
                                   "my.json");
            }).find("appears twice"),
            std::string::npos);
  EXPECT_NE(error_of([&] { parse_sleeve_presets(R"({"format": "x", "sleeves": []})", "my.json"); }).find("format"),
            std::string::npos);
}

TEST(Plan, PinPresetsMakePinsWithTheirCounterbores) {
  // The catalogue's pin presets: a K-wire, and screws whose heads sink into a counterbore.
  const std::vector<SleevePreset>& presets = default_sleeve_presets();
  const SleevePreset& screw = find_sleeve_preset(presets, "pin-screw-2.7");
  EXPECT_EQ(screw.kind, TubeKind::pin);
  ASSERT_TRUE(screw.counterbore.has_value());
  EXPECT_DOUBLE_EQ(screw.counterbore->radius, 2.6);
  EXPECT_EQ(find_sleeve_preset(presets, "pin-kwire-1.6").kind, TubeKind::pin);
  EXPECT_FALSE(find_sleeve_preset(presets, "pin-kwire-1.6").counterbore.has_value());
  PlanAxis axis;
  axis.name = "p1";
  axis.source = "plan.csv";
  axis.entry = {0, 0, 0};
  axis.direction = {0, 0, -1};
  const TubeSpec t = tube_from_axis(axis, screw);
  EXPECT_EQ(t.kind, TubeKind::pin);
  ASSERT_TRUE(t.counterbore.has_value());
  EXPECT_DOUBLE_EQ(t.counterbore->depth, 3.0);
  const auto catalogue = [](const std::string& sleeves) {
    return R"({"format": "surgical-template-sleeves/1", "sleeves": [)" + sleeves + "]}";
  };
  const std::string sizes = R"("name": "P", "inner_diameter": 2, "outer_diameter": 5, "length": 8)";
  EXPECT_NE(error_of([&] {
              parse_sleeve_presets(catalogue("{" + sizes + R"(, "kind": "nail"})"), "my.json");
            }).find("my.json: sleeves[0].kind"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              parse_sleeve_presets(catalogue("{" + sizes + R"(, "counterbore_diameter": 4})"), "my.json");
            }).find("together"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              parse_sleeve_presets(catalogue("{" + sizes + R"(, "counterbore_diameter": 1, "counterbore_depth": 2})"),
                                   "my.json");
            }).find("sleeves[0].counterbore_diameter: must be > inner_radius"),
            std::string::npos);
}

TEST(Plan, AxesBecomeTubesWithSizesFromThePlanOrAPreset) {
  const Plan p = parse_markups(kMarkups, "plan.mrk.json", Space::LPS);
  EXPECT_NE(
      error_of([&] { tube_from_axis(p.axes[0], std::nullopt); }).find("axis \"16\": the plan gives no inner_radius"),
      std::string::npos);
  const SleevePreset& preset = find_sleeve_preset(default_sleeve_presets(), "kwire-2.0");
  const TubeSpec t = tube_from_axis(p.axes[0], preset);
  EXPECT_DOUBLE_EQ(t.inner_radius, preset.inner_radius);
  EXPECT_DOUBLE_EQ(t.length, preset.length);
  EXPECT_DOUBLE_EQ(t.depth, 12.0);
  PlanAxis sized = p.axes[0];
  sized.inner_radius = 3.0; // wider than the preset's outer radius: impossible
  EXPECT_NE(error_of([&] { tube_from_axis(sized, preset); }).find("outer_radius must be > inner_radius"),
            std::string::npos);
}

// A case whose boundary and tubes are Slicer markups (RAS curve, LPS and RAS lines) reads exactly as
// the case with the same plan as points; on a bone saved in RAS the same markups land mirrored.
TEST(Plan, CaseWithMarkupsEqualsCaseWithPoints) {
  const std::string cases = st::test::examples_dir() + "/cases/";
  const CaseFile points = read_case(cases + "vertebra-pedicle.json");
  const CaseFile markups = read_case(cases + "vertebra-pedicle-slicer.json");
  ASSERT_EQ(markups.boundary_points.size(), points.boundary_points.size());
  for (std::size_t i = 0; i < points.boundary_points.size(); ++i)
    expect_near(markups.boundary_points[i], points.boundary_points[i], 1e-9);
  ASSERT_EQ(markups.tubes.size(), points.tubes.size());
  for (std::size_t i = 0; i < points.tubes.size(); ++i) {
    EXPECT_EQ(markups.tubes[i].name, points.tubes[i].name);
    expect_near(markups.tubes[i].entry, points.tubes[i].entry, 1e-9);
    expect_near(markups.tubes[i].direction, points.tubes[i].direction, 1e-5); // targets written to 4 decimals
    EXPECT_NEAR(markups.tubes[i].depth, 35.0, 1e-3);
  }

  // The bone saved by Slicer in RAS: the mesh mirrored (x, y negated) with "SPACE=RAS" in its header.
  const fs::path dir = scratch("ras-bone");
  TriangleMesh bone = read_mesh(points.bone);
  for (Vec3& v : bone.positions) v = convert_space(v, Space::LPS, Space::RAS);
  write_stl(bone, (dir / "bone.stl").string(), "3D Slicer output. SPACE=RAS");
  fs::create_directories(dir / "cases");
  fs::copy(st::test::examples_dir() + "/plans", dir / "plans");
  std::ifstream in(cases + "vertebra-pedicle-slicer.json");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text.replace(text.find("../meshes/vertebrae_lumbar_L2-L5_ssm_mean.stl.gz"),
               std::string("../meshes/vertebrae_lumbar_L2-L5_ssm_mean.stl.gz").size(), "../bone.stl");
  const CaseFile mirrored = read_case(write(dir / "cases" / "case.json", text));
  for (std::size_t i = 0; i < points.boundary_points.size(); ++i)
    expect_near(mirrored.boundary_points[i], convert_space(points.boundary_points[i], Space::LPS, Space::RAS), 1e-9);
  expect_near(mirrored.tubes[0].entry, convert_space(points.tubes[0].entry, Space::LPS, Space::RAS), 1e-9);
}

TEST(Plan, CaseMarkupsErrorsNameTheKey) {
  const fs::path dir = scratch("case-errors");
  const std::string bone = (fs::path(st::test::examples_dir()) / "meshes" / "sacrum.stl.gz").string();
  write(dir / "line.mrk.json", "{" + kSchema + R"(, "markups": [{"type": "Line", "controlPoints": [
      {"position": [0,0,0]}, {"position": [0,0,-5]}]}]})");
  const auto case_text = [&](const std::string& boundary, const std::string& tube) {
    return R"({"format": "surgical-template-case/1", "bone": ")" + bone + R"(", "boundary": )" + boundary +
           R"(, "template": {"thickness": 2}, "tubes": [)" + tube + "]}";
  };
  const std::string tube_ok = R"({"markups": "line.mrk.json", "inner_radius": 1, "outer_radius": 2, "length": 5})";
  struct Bad {
    std::string text, expect;
  } bad[] = {
      {case_text(R"({"markups": "missing.mrk.json"})", tube_ok), "missing.mrk.json: cannot open the markups file"},
      {case_text(R"({"markups": "line.mrk.json"})", tube_ok), "boundary.markups"},
      {case_text(R"({"points": [[0,0,0],[1,0,0],[0,1,0]], "markups": "line.mrk.json"})", tube_ok), "not both"},
      {case_text(
           R"({"points": [[0,0,0],[1,0,0],[0,1,0]]})",
           R"({"markups": "line.mrk.json", "entry": [0,0,0], "inner_radius": 1, "outer_radius": 2, "length": 5})"),
       "tubes[0]: give either markups"},
      {case_text(R"({"points": [[0,0,0],[1,0,0],[0,1,0]]})",
                 R"({"markups": "line.mrk.json", "inner_radius": 1, "outer_radius": 2, "length": 5, "depth": -1})"),
       "tubes[0].depth"},
  };
  for (const Bad& b : bad) {
    const std::string message = error_of([&] { read_case(write(dir / "case.json", b.text)); });
    EXPECT_NE(message.find(b.expect), std::string::npos) << "expected '" << b.expect << "' in: " << message;
  }
  const CaseFile ok =
      read_case(write(dir / "case.json", case_text(R"({"points": [[0,0,0],[1,0,0],[0,1,0]]})", tube_ok)));
  ASSERT_EQ(ok.tubes.size(), 1u);
  EXPECT_DOUBLE_EQ(ok.tubes[0].depth, 5.0);
  expect_near(ok.tubes[0].direction, {0, 0, -1});
}

TEST(Plan, ReadPlanRecognisesEachFormat) {
  const std::string plans = st::test::examples_dir() + "/plans/";
  const Plan csv = read_plan(plans + "maxilla-implants.csv", Space::LPS);
  const CaseFile maxilla = read_case(st::test::examples_dir() + "/cases/maxilla-implants.json");
  ASSERT_EQ(csv.axes.size(), maxilla.tubes.size());
  for (std::size_t i = 0; i < csv.axes.size(); ++i) {
    const TubeSpec t = tube_from_axis(csv.axes[i], std::nullopt);
    EXPECT_EQ(t.name, maxilla.tubes[i].name);
    expect_near(t.entry, maxilla.tubes[i].entry, 1e-9);
    expect_near(t.direction, maxilla.tubes[i].direction, 1e-5);
    EXPECT_DOUBLE_EQ(t.inner_radius, maxilla.tubes[i].inner_radius);
    EXPECT_DOUBLE_EQ(t.offset, maxilla.tubes[i].offset);
  }
  const Plan whole = read_plan(plans + "vertebra-plan.mrk.json", Space::LPS);
  EXPECT_EQ(whole.boundary_points.size(), 9u);
  EXPECT_TRUE(whole.inside);
  EXPECT_EQ(whole.axes.size(), 2u);
  const Plan from_case = read_plan(st::test::examples_dir() + "/cases/maxilla-implants.json", Space::RAS);
  EXPECT_EQ(from_case.axes.size(), 5u);
  EXPECT_EQ(from_case.boundary_points.size(), maxilla.boundary_points.size());
  const fs::path dir = scratch("read-plan");
  EXPECT_NE(error_of([&] { read_plan(write(dir / "x.json", R"({"points": []})"), Space::LPS); }).find("case file"),
            std::string::npos);
  EXPECT_NE(error_of([&] { read_plan((dir / "none.csv").string(), Space::LPS); }).find("cannot open"),
            std::string::npos);
}

// The plan of a Slicer session in one markups file designs a valid template with both pedicle tubes.
TEST(Plan, SlicerPlanDesignsAValidGuide) {
  CaseFile c = read_case(st::test::examples_dir() + "/cases/vertebra-pedicle.json");
  const Plan plan = read_plan(st::test::examples_dir() + "/plans/vertebra-plan.mrk.json", mesh_file_space(c.bone));
  c.boundary_points = plan.boundary_points;
  c.inside = plan.inside;
  const SleevePreset& preset = find_sleeve_preset(default_sleeve_presets(), "drill-2.5");
  c.tubes.clear();
  for (const PlanAxis& a : plan.axes) c.tubes.push_back(tube_from_axis(a, preset));
  const TemplateResult r = design_template(read_mesh(c.bone), st::test::case_options(c));
  st::test::expect_valid_solid(r.shell);
  EXPECT_EQ(r.tubes.size(), 2u);
}

// Saw blades in the catalogue's own section: the built-in ones found by name; a user's file checked by
// key; a catalogue without blades has none.
TEST(Plan, BladePresetsAreInTheCatalogueAndCheckedByKey) {
  const std::vector<BladePreset>& blades = default_blade_presets();
  ASSERT_GE(blades.size(), 5u);
  const BladePreset& b = find_blade_preset(blades, "SAGITTAL-0.89");
  EXPECT_EQ(b.name, "sagittal-0.89");
  EXPECT_DOUBLE_EQ(b.thickness, 0.89);
  EXPECT_DOUBLE_EQ(b.clearance, 0.1);
  EXPECT_THROW(find_blade_preset(blades, "chainsaw"), InvalidInput);
  auto refused = [](const std::string& list, const std::string& words) {
    try {
      parse_blade_presets(R"({"format": "surgical-template-sleeves/1", "sleeves": [], "blades": )" + list + "}",
                          "mine.json");
      ADD_FAILURE() << "accepted: " << list;
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  refused(R"([{"name": "x"}])", "mine.json: blades[0].thickness: is required");
  refused(R"([{"name": "x", "thickness": -1}])", "blades[0].thickness: must be > 0");
  refused(R"([{"name": "x", "thickness": 1, "clearance": -0.1}])", "blades[0].clearance: must be >= 0");
  refused(R"([{"name": "x", "thickness": 1}, {"name": "x", "thickness": 2}])", "blades[1].name");
  refused(R"({"name": "x"})", "blades: must be an array");
  EXPECT_TRUE(parse_blade_presets(R"({"format": "surgical-template-sleeves/1", "sleeves": []})", "s.json").empty());
}
