// Case files written back (write_case) and plans applied to cases (apply_plan): the one way the
// tool, the Python module and the workbench do both.

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

fs::path scratch(const std::string& name) { return st::test::scratch_dir("case_file", name); }

std::string example_case(const std::string& name) {
  return (fs::path(st::test::examples_dir()) / "cases" / (name + ".json")).string();
}

void expect_same_case(const CaseFile& a, const CaseFile& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(fs::weakly_canonical(a.bone), fs::weakly_canonical(b.bone));
  ASSERT_EQ(a.boundary_points.size(), b.boundary_points.size());
  for (std::size_t i = 0; i < a.boundary_points.size(); ++i) EXPECT_EQ(a.boundary_points[i], b.boundary_points[i]);
  EXPECT_EQ(a.inside.has_value(), b.inside.has_value());
  if (a.inside && b.inside) EXPECT_EQ(*a.inside, *b.inside);
  EXPECT_EQ(a.thickness, b.thickness);
  EXPECT_EQ(a.clearance, b.clearance);
  EXPECT_EQ(a.resolution, b.resolution);
  EXPECT_EQ(a.sampling_step, b.sampling_step);
  EXPECT_EQ(a.insertion_auto, b.insertion_auto);
  EXPECT_EQ(a.insertion.has_value(), b.insertion.has_value());
  if (a.insertion && b.insertion) EXPECT_LT((*a.insertion - *b.insertion).norm(), 1e-15);
  ASSERT_EQ(a.tubes.size(), b.tubes.size());
  for (std::size_t i = 0; i < a.tubes.size(); ++i) {
    EXPECT_EQ(a.tubes[i].name, b.tubes[i].name);
    EXPECT_EQ(a.tubes[i].entry, b.tubes[i].entry);
    EXPECT_LT((a.tubes[i].direction - b.tubes[i].direction).norm(), 1e-15);
    EXPECT_EQ(a.tubes[i].outer_radius, b.tubes[i].outer_radius);
    EXPECT_EQ(a.tubes[i].depth, b.tubes[i].depth);
  }
}

} // namespace

TEST(CaseFile, WrittenCaseReadsBackTheSame) {
  // Every example case, written into another folder (the bone path made relative to it) and read.
  for (const char* name : {"maxilla-implants", "vertebra-pedicle", "sacrum-iliosacral", "tibia-osteotomy"}) {
    const CaseFile c = read_case(example_case(name));
    const fs::path path = scratch(name) / "deeper" / "case.json";
    fs::create_directories(path.parent_path());
    write_case(c, path.string());
    expect_same_case(c, read_case(path.string()));
  }
}

TEST(CaseFile, AnInvalidCaseIsRefusedAndNothingIsWritten) {
  CaseFile c = read_case(example_case("vertebra-pedicle"));
  c.thickness = -1.0;
  const fs::path path = scratch("invalid") / "case.json";
  try {
    write_case(c, path.string());
    FAIL() << "a negative thickness was written";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("template.thickness"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path.string() + ".tmp"));
}

TEST(CaseFile, PlanReplacesOrAddsTubesAndWarnsWhenTheInsidePointGoes) {
  const CaseFile base = read_case(example_case("vertebra-pedicle"));
  ASSERT_TRUE(base.inside.has_value());
  Plan plan;
  plan.path = "plan.mrk.json";
  plan.boundary_points = {Vec3(0, 0, 0), Vec3(10, 0, 0), Vec3(0, 10, 0)};
  PlanAxis axis;
  axis.name = "new";
  axis.entry = Vec3(1, 2, 3);
  axis.direction = Vec3(0, 0, -1);
  plan.axes = {axis};
  const SleevePreset& sizes = find_sleeve_preset(default_sleeve_presets(), "drill-2.5");

  CaseFile replaced = base;
  const auto warnings = apply_plan(replaced, plan, sizes);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("inside point is dropped"), std::string::npos);
  EXPECT_FALSE(replaced.inside.has_value());
  EXPECT_EQ(replaced.boundary_points, plan.boundary_points);
  ASSERT_EQ(replaced.tubes.size(), 1u);
  EXPECT_EQ(replaced.tubes[0].name, "new");
  EXPECT_DOUBLE_EQ(replaced.tubes[0].outer_radius, sizes.outer_radius);

  CaseFile added = base;
  apply_plan(added, plan, sizes, PlanTubes::Add);
  EXPECT_EQ(added.tubes.size(), base.tubes.size() + 1);

  // An axis without sizes and no preset: refused before anything changes.
  CaseFile untouched = base;
  EXPECT_THROW(apply_plan(untouched, plan, std::nullopt), InvalidInput);
  expect_same_case(untouched, base);
}

TEST(CaseFile, InsertionIsADirectionOrAutoAndReadsBack) {
  const CaseFile base = read_case(example_case("vertebra-pedicle"));
  const fs::path dir = scratch("insertion");
  CaseFile along = base;
  along.insertion = Vec3(0, 0, -2).normalized();
  write_case(along, (dir / "along.json").string());
  const CaseFile read_along = read_case((dir / "along.json").string());
  expect_same_case(along, read_along);
  EXPECT_EQ(template_options(read_along).insertion, Vec3(0, 0, -1));
  EXPECT_TRUE(template_options(read_along).analyse_insertion);
  CaseFile automatic = base;
  automatic.insertion_auto = true;
  write_case(automatic, (dir / "auto.json").string());
  const CaseFile read_auto = read_case((dir / "auto.json").string());
  expect_same_case(automatic, read_auto);
  EXPECT_FALSE(template_options(read_auto).insertion.has_value());
  // A case that names an insertion direction gets its undercuts blocked out; one without keeps the
  // guide it always had (analysed, not changed).
  EXPECT_TRUE(read_auto.warnings.empty());
  EXPECT_TRUE(template_options(read_auto).block_out);
  EXPECT_TRUE(template_options(read_along).block_out);
  EXPECT_FALSE(template_options(base).block_out);
  EXPECT_TRUE(template_options(base).analyse_insertion);

  const std::string text = "{\"format\": \"surgical-template-case/1\", \"bone\": \"b.stl\", \"boundary\": "
                           "{\"points\": [[0,0,0],[1,0,0],[0,1,0]]}, \"template\": {\"thickness\": 2, "
                           "\"insertion\": ";
  for (const char* bad : {"\"down\"", "[0, 0, 0]", "[1, 2]", "7"}) {
    try {
      parse_case(text + bad + "}}", "case.json");
      FAIL() << "accepted template.insertion " << bad;
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find("template.insertion"), std::string::npos) << e.what();
    }
  }
}

TEST(CaseFile, LabelsReadWriteAndRefuseBadKeysByName) {
  const std::string path = test::output_dir() + "/labels-case.json";
  auto text = [](const std::string& labels) {
    return std::string(R"({"format": "surgical-template-case/1", "bone": "b.stl",
      "boundary": {"points": [[0,0,0],[1,0,0],[0,1,0]]}, "template": {"thickness": 2},
      "labels": [)") +
           labels + "]}";
  };
  const CaseFile c = parse_case(text(R"({"text": "CASE 7 L", "at": [1, 2, 3], "up": [0, 0, 1]},
              {"name": "version", "text": "v2 \u00e9", "at": [4, 5, 6], "up": [0, 1, 0], "height": 3, "depth": 0.8,
               "mode": "emboss"})"),
                                path);
  ASSERT_EQ(c.labels.size(), 2u);
  EXPECT_EQ(c.labels[0].name, "label 1") << "a label without a name is named by its place";
  EXPECT_EQ(c.labels[0].text, "CASE 7 L");
  EXPECT_DOUBLE_EQ(c.labels[0].height, 4.0);
  EXPECT_DOUBLE_EQ(c.labels[0].depth, 0.6);
  EXPECT_EQ(c.labels[0].mode, LabelMode::engrave);
  EXPECT_EQ(c.labels[1].text, "v2 \xc3\xa9");
  EXPECT_EQ(c.labels[1].mode, LabelMode::emboss);
  EXPECT_EQ(template_options(c).labels.size(), 2u);
  const CaseFile back = parse_case(case_json(c, path), path);
  ASSERT_EQ(back.labels.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(back.labels[i].name, c.labels[i].name);
    EXPECT_EQ(back.labels[i].text, c.labels[i].text);
    EXPECT_EQ(back.labels[i].at, c.labels[i].at);
    EXPECT_EQ(back.labels[i].up, c.labels[i].up);
    EXPECT_EQ(back.labels[i].height, c.labels[i].height);
    EXPECT_EQ(back.labels[i].depth, c.labels[i].depth);
    EXPECT_EQ(back.labels[i].mode, c.labels[i].mode);
  }
  auto refused = [&](const std::string& labels, const std::string& words) {
    try {
      parse_case(text(labels), path);
      ADD_FAILURE() << "accepted: " << labels;
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  refused(R"({"at": [0,0,0], "up": [0,0,1]})", "labels[0].text: is required");
  refused(R"({"text": "", "at": [0,0,0], "up": [0,0,1]})", "labels[0].text: must not be empty");
  refused(R"({"text": "A", "up": [0,0,1]})", "labels[0].at: is required");
  refused(R"({"text": "A", "at": [0,0,0], "up": [0,0,0]})", "labels[0].up: must be a finite, non-zero vector");
  refused(R"({"text": "A", "at": [0,0,0], "up": [0,0,1], "depth": 0.4})", "labels[0].depth: must be at least 0.5");
  refused(R"({"text": "A", "at": [0,0,0], "up": [0,0,1], "height": 0.2})", "labels[0].height: must be at least 1");
  refused(R"({"text": "A", "at": [0,0,0], "up": [0,0,1], "mode": "burn"})", "labels[0].mode");
  refused(
      R"({"text": "A", "at": [0,0,0], "up": [0,0,1]}, {"name": "label 1", "text": "B", "at": [0,0,0], "up": [0,0,1]})",
      "labels[1].name");
  refused(std::string(R"({"text": ")") + std::string(65, 'A') + R"(", "at": [0,0,0], "up": [0,0,1]})",
          "labels[0].text: is too long");
}
