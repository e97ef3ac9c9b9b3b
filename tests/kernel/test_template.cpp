// The initial template end to end: on shapes built in code and on every example case (real meshes).

#include "helpers.h"

#include "st/io/case_file.h"
#include "st/core/errors.h"
#include "st/core/tolerances.h"
#include "st/io/mesh_io.h"
#include "st/design/template_design.h"

#include <filesystem>
#include <numbers>

using namespace st;
using namespace st::test;

namespace {

TemplateOptions dome_options(double thickness) {
  TemplateOptions o;
  for (int i = 0; i < 10; ++i) {
    const double a = 2.0 * std::numbers::pi * i / 10 + 0.05;
    o.boundary_points.emplace_back(12.0 * std::cos(a), 9.0 * std::sin(a), 0.0);
  }
  o.thickness = thickness;
  return o;
}

TriangleMesh bumpy_sphere() {
  TriangleMesh s = make_icosphere(20.0, 5);
  for (Vec3& p : s.positions) {
    const Vec3 u = p.normalized();
    p = u * (20.0 + 0.6 * std::sin(5 * u.x()) * std::cos(4 * u.y()) + 0.4 * std::sin(7 * u.z()));
  }
  return s;
}

} // namespace

TEST(Template, OnABumpySphereIsAValidSolidAtTheThickness) {
  const TriangleMesh bone = bumpy_sphere();
  TemplateOptions o;
  for (int i = 0; i < 9; ++i) {
    const double a = 2.0 * std::numbers::pi * i / 9;
    const Vec3 d(std::sin(0.7) * std::cos(a), std::sin(0.7) * std::sin(a), std::cos(0.7));
    o.boundary_points.push_back(20.0 * d);
  }
  o.thickness = 2.5;
  o.resolution = 0.25;
  const TemplateResult r = design_template(bone, o);
  expect_valid_solid(r.shell);
  EXPECT_EQ(r.solid.components, 1u);
  // Inner surface on the bone, outer at the thickness within the field's resolution, rim on the curve.
  EXPECT_LT(r.fit.inner_to_bone.max, 1e-6);
  EXPECT_GT(r.fit.outer_to_inner.min, 2.5 - 0.25);
  EXPECT_LT(r.fit.outer_to_inner.max, 2.5 + 0.25);
  EXPECT_LT(r.fit.rim_to_curve.max, 1e-6);
  // Volume of a shell of thickness T over a cap of area A on a sphere of radius R:
  // A * T * (1 + T/R + T^2/(3 R^2)).
  const double cap_area = surface_area(r.inner), R = 20.0, T = 2.5;
  const double shell = cap_area * T * (1.0 + T / R + T * T / (3.0 * R * R));
  EXPECT_NEAR(r.solid.volume, shell, 0.03 * shell);
  EXPECT_EQ(r.wall_triangles, r.inner_rim_points + r.outer_rim_points);
}

TEST(Template, ClearanceMovesTheInnerSurfaceOffTheBone) {
  const TriangleMesh bone = bumpy_sphere();
  TemplateOptions o;
  for (int i = 0; i < 9; ++i) {
    const double a = 2.0 * std::numbers::pi * i / 9;
    const Vec3 d(std::sin(0.6) * std::cos(a), std::sin(0.6) * std::sin(a), std::cos(0.6));
    o.boundary_points.push_back(20.0 * d);
  }
  o.thickness = 3.0;
  o.clearance = 0.2;
  const TemplateResult r = design_template(bone, o);
  expect_valid_solid(r.shell);
  EXPECT_NEAR(r.fit.inner_to_bone.max, 0.2, 0.02);
  EXPECT_GT(r.fit.inner_to_bone.min, 0.15);
}

TEST(Template, OnAFlatPlateTheVolumeIsAreaTimesThickness) {
  const TriangleMesh plate = make_height_field(-20, 20, -20, 20, 60, [](double, double) { return 0.0; });
  const TemplateOptions o = dome_options(2.0);
  const TemplateResult r = design_template(plate, o);
  expect_valid_solid(r.shell);
  const double area = surface_area(r.inner);
  EXPECT_NEAR(area, std::numbers::pi * 12.0 * 9.0, 0.01 * std::numbers::pi * 12.0 * 9.0);
  EXPECT_NEAR(r.solid.volume, area * 2.0, 0.03 * area * 2.0);
}

TEST(Template, BadOptionsAreRefusedNamingTheOption) {
  const TriangleMesh plate = make_height_field(-20, 20, -20, 20, 20, [](double, double) { return 0.0; });
  auto refused = [&](TemplateOptions o, const std::string& key) {
    try {
      design_template(plate, o);
      ADD_FAILURE() << key << " accepted";
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  };
  TemplateOptions o = dome_options(0.0);
  refused(o, "thickness");
  o = dome_options(-1.0);
  refused(o, "thickness");
  o = dome_options(1000.0);
  refused(o, "thickness");
  o = dome_options(std::nan(""));
  refused(o, "thickness");
  o = dome_options(2.0);
  o.clearance = -0.5;
  refused(o, "clearance");
  o = dome_options(2.0);
  o.resolution = 0.0005; // would need billions of cells
  refused(o, "resolution");
  o = dome_options(2.0);
  o.boundary_points.resize(2);
  refused(o, "3 control points");
}

TEST(Template, NothingEnclosedIsAGeometryError) {
  const TriangleMesh plate = make_height_field(-20, 20, -20, 20, 20, [](double, double) { return 0.0; });
  TemplateOptions o;
  o.boundary_points = {{0.1, 0.1, 0}, {0.2, 0.1, 0}, {0.15, 0.2, 0}}; // inside one triangle
  o.thickness = 2.0;
  EXPECT_THROW(design_template(plate, o), GeometryError);
}

// Regression: displacing the cut region along per-vertex normals folded the cut's tiny triangles
// on striated cryosection bone; the clearance now follows a smooth normal field of the bone.
TEST(Template, ClearanceOnStriatedBoneStaysValid) {
  const CaseFile c = read_case(examples_dir() + "/cases/tibia-osteotomy.json");
  const TriangleMesh bone = read_mesh(c.bone);
  for (double clearance : {0.3, 0.5}) {
    TemplateOptions o;
    o.boundary_points = c.boundary_points;
    o.inside = c.inside;
    o.thickness = c.thickness;
    o.clearance = clearance;
    const TemplateResult r = design_template(bone, o);
    expect_valid_solid(r.shell);
    EXPECT_NEAR(r.fit.inner_to_bone.max, clearance, 0.05 * clearance);
    EXPECT_GT(r.fit.inner_to_bone.min, 0.8 * clearance);
  }
}

// Every example case (real anatomical meshes) gives a valid template that fits its bone.
class ExampleCase : public ::testing::TestWithParam<std::string> {};

TEST_P(ExampleCase, DesignsAValidTemplate) {
  const CaseFile c = read_case(GetParam());
  const TriangleMesh bone = read_mesh(c.bone);
  const TemplateResult r = design_template(bone, st::test::case_options(c)); // with the case's tubes
  expect_valid_solid(r.shell);
  EXPECT_EQ(r.solid.components, 1u);
  EXPECT_NEAR(r.fit.inner_to_bone.max, c.clearance, 1e-3 + 0.1 * c.clearance);
  EXPECT_GT(r.fit.outer_to_inner.min, c.thickness - r.resolution);
  EXPECT_LT(r.fit.outer_to_inner.max, c.thickness + r.resolution);
  // The rim passes through a vertex the curve crosses an edge next to (within the cut margin), and
  // rim vertices closer than kMinCutDistance_mm are merged (cut.h).
  EXPECT_LT(r.fit.rim_to_curve.max,
            c.clearance + std::max(tol::kMinCutDistance_mm, 2.0 * tol::kEdgeCutMargin) + tol::kMinCutDistance_mm);
  // A case that names its insertion direction gets a guide that comes off along it (block-out).
  if (c.insertion || c.insertion_auto) {
    EXPECT_TRUE(r.insertion.removal_checked);
    EXPECT_TRUE(r.insertion.removable)
        << "meets the bone near "
        << (r.insertion.blocking.empty() ? Vec3::Zero() : r.insertion.blocking[0]).transpose();
  }
  // Every case gets its stability: contacts about one per mm^2 of the inner surface in contact, a
  // score in [0, 1], a press point on the outer surface; a guide that comes off lifts off freely.
  ASSERT_TRUE(r.stability.analysed);
  const StabilityReport& s = r.stability.report;
  EXPECT_NEAR(static_cast<double>(s.contacts), r.insertion.contact_area_mm2, 0.05 * r.insertion.contact_area_mm2 + 5.0);
  EXPECT_GE(s.score, 0.0);
  EXPECT_LE(s.score, 1.0);
  EXPECT_LT(distances_to_surface({r.stability.press.point}, r.outer).max, 1e-9);
  if (r.insertion.removable) EXPECT_TRUE(s.lift_off_free);
  if (s.score == 0.0 && s.lift_off_free) EXPECT_FALSE(s.free_motions.size() == 1) << "nothing but the lift-off is free";
  write_stl(r.shell, output_dir() + "/" + c.name + ".stl");
}

std::vector<std::string> example_cases() {
  std::vector<std::string> out;
  const std::filesystem::path dir = std::filesystem::path(ST_EXAMPLES_DIR) / "cases";
  if (std::filesystem::exists(dir))
    for (const auto& e : std::filesystem::directory_iterator(dir))
      if (e.path().extension() == ".json") out.push_back(e.path().string());
  std::sort(out.begin(), out.end());
  return out;
}

INSTANTIATE_TEST_SUITE_P(Examples, ExampleCase, ::testing::ValuesIn(example_cases()), [](const auto& info) {
  std::string n = std::filesystem::path(info.param).stem().string();
  for (char& ch : n)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return n;
});

TEST(Template, SimplifiedOuterSurfaceKeepsTheShellValidWithFarFewerTriangles) {
  const CaseFile c = read_case(examples_dir() + "/cases/vertebra-pedicle.json");
  const TriangleMesh bone = read_mesh(c.bone);
  TemplateOptions o;
  o.boundary_points = c.boundary_points;
  o.inside = c.inside;
  o.thickness = c.thickness;
  const TemplateResult plain = design_template(bone, o);
  o.simplify_outer = true;
  const TemplateResult simple = design_template(bone, o);
  expect_valid_solid(simple.shell);
  EXPECT_LT(simple.shell.face_count(), plain.shell.face_count() / 3);
  EXPECT_NEAR(simple.solid.volume, plain.solid.volume, 0.01 * plain.solid.volume);
  EXPECT_GT(simple.fit.outer_to_inner.min, c.thickness - simple.resolution);
  EXPECT_LT(simple.fit.outer_to_inner.max, c.thickness + simple.resolution);
}

// Regression: on this loop (up to the anterior nasal spine) closest-triangle propagation reached
// crease nodes from the wrong part of the patch and the outer surface came 0.39 mm too close.
TEST(Template, OuterSurfaceStaysAtTheThicknessNearTheNasalSpine) {
  const TriangleMesh bone = read_mesh(examples_dir() + "/meshes/maxilla_dentition_ct_crop.stl.gz");
  TemplateOptions o;
  o.boundary_points = {{100.29, -183.45, 19.86}, {115.46, -199.29, 20.06}, {134.41, -199.78, 19.91},
                       {149.58, -185.76, 19.17}, {147.68, -191.59, 11.88}, {134.41, -203.97, 9.75},
                       {115.46, -202.62, 10.15}, {102.19, -187.46, 13.12}};
  o.inside = Vec3(124.93, -203.84, 12.75);
  o.thickness = 2.5;
  o.resolution = 0.25;
  const TemplateResult r = design_template(bone, o);
  expect_valid_solid(r.shell);
  EXPECT_GT(r.fit.outer_to_inner.min, 2.5 - 0.25);
  EXPECT_LT(r.fit.outer_to_inner.max, 2.5 + 0.25);
}
