// Tests of the OpenCASCADE sleeves (st_occt): the sleeve is one valid solid with the seam in the
// kernel's frame; its tessellation is a closed, manifold, outward solid whose vertices lie on the
// exact surface and whose volume is within the chordal error the deflection allows, converging as
// the deflection shrinks; the BREP text reads back as the same solid; invalid input throws.

#include "helpers.h"

#include "st/core/errors.h"
#include "st/core/mesh.h"
#include "st/occt/occt_sleeve.h"
#include "st/guide/sleeve.h"

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <BRepGProp.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <GProp_GProps.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Vertex.hxx>
#include <gp_Ax1.hxx>
#include <gp_Pln.hxx>
#include <gp_Trsf.hxx>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

namespace {

using st::TriangleMesh;
using st::TubeSpec;
using st::Vec3;

constexpr double kPi = std::numbers::pi;
/// Vertices sit on the exact surface up to floating-point rounding of coordinates below 100 mm.
constexpr double kOnSurface = 1e-9;

// ---- fixtures --------------------------------------------------------------------------------------

TubeSpec make_tube(const Vec3& direction, double inner = 2.0, double outer = 3.0, double length = 20.0,
                   double offset = 1.5, const Vec3& entry = Vec3(12.5, -40.0, 7.25)) {
  TubeSpec t;
  t.name = "test-tube";
  t.entry = entry;
  t.direction = direction;
  t.inner_radius = inner;
  t.outer_radius = outer;
  t.length = length;
  t.offset = offset;
  return t;
}

/// Axis-aligned both ways, one nearly axis-aligned, and oblique drilling directions (not unit).
std::vector<Vec3> directions() {
  return {Vec3(0, 0, 1),    Vec3(0, 0, -1), Vec3(1, 0, 0),         Vec3(0, -2, 0),
          Vec3(1e-3, 0, 1), Vec3(1, 2, -3), Vec3(-0.3, 0.5, 0.81), Vec3(0.7, -0.7, 0.1)};
}

double exact_sleeve_volume(const TubeSpec& t) {
  return kPi * (t.outer_radius * t.outer_radius - t.inner_radius * t.inner_radius) * t.length;
}

/// The range a tessellation's volume must fall in when every triangle is within `d` of the exact
/// surface and its vertices lie on it: each cross-section of the outer wall is a closed polygon
/// between the circles of radius R - d and R (material lost, up to pi (R^2 - (R - d)^2) per unit of
/// length), of the inner wall one between r - d and r (the hole shrinks, material gained, up to
/// pi (r^2 - (r - d)^2)). The caps are planar and exact.
std::pair<double, double> chordal_volume_range(const TubeSpec& t, double d) {
  const double R = t.outer_radius, r = t.inner_radius, L = t.length;
  const double exact = exact_sleeve_volume(t);
  const double slack = 1e-9 * exact; // rounding of the signed-volume sum
  return {exact - kPi * L * (R * R - (R - d) * (R - d)) - slack, exact + kPi * L * (r * r - (r - d) * (r - d)) + slack};
}

double gprop_volume(const TopoDS_Shape& shape) {
  GProp_GProps props;
  BRepGProp::VolumeProperties(shape, props);
  return props.Mass();
}

/// Height along the tube's axis from the entry, and distance from the axis.
struct Cyl {
  double z, rho;
};
Cyl cylindrical(const TubeSpec& t, const Vec3& p) {
  const Vec3 axis = st::tube_axis(t);
  const Vec3 d = p - t.entry;
  const double z = d.dot(axis);
  return {z, (d - z * axis).norm()};
}

/// Distance from the tube's axis to the segment ab, both ends at the same distance from the axis
/// (a chord of the cylinder, or a diagonal of its side): the closest point is the projection's.
double axis_distance_of_segment(const TubeSpec& t, const Vec3& a, const Vec3& b) {
  const Vec3 axis = st::tube_axis(t);
  auto flat = [&](const Vec3& p) {
    const Vec3 d = p - t.entry;
    return Vec3(d - d.dot(axis) * axis);
  };
  const Vec3 pa = flat(a), pb = flat(b), ab = pb - pa;
  const double len2 = ab.squaredNorm();
  const double s = len2 > 0 ? std::clamp(-pa.dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (pa + s * ab).norm();
}

/// Largest distance of a side triangle of the sleeve from its cylinder: side triangles have all
/// corners on one cylinder and not all at one height; the convex distance-to-axis reaches its
/// minimum over such a triangle on an edge.
double max_side_deviation(const TubeSpec& t, const TriangleMesh& mesh) {
  double worst = 0.0;
  for (const st::Triangle& f : mesh.triangles) {
    Cyl c[3];
    for (std::size_t k = 0; k < 3; ++k) c[k] = cylindrical(t, mesh.positions[f[k]]);
    for (double radius : {t.inner_radius, t.outer_radius}) {
      const bool on_cylinder =
          std::all_of(c, c + 3, [&](const Cyl& q) { return std::abs(q.rho - radius) < kOnSurface; });
      const bool flat = std::abs(c[0].z - c[1].z) < kOnSurface && std::abs(c[1].z - c[2].z) < kOnSurface;
      if (!on_cylinder || flat) continue;
      for (std::size_t k = 0; k < 3; ++k)
        worst =
            std::max(worst, radius - axis_distance_of_segment(t, mesh.positions[f[k]], mesh.positions[f[(k + 1) % 3]]));
    }
  }
  return worst;
}

/// The points of the edges that are seams (closed on their face) of `shape`.
std::vector<Vec3> seam_points(const TopoDS_Shape& shape) {
  std::vector<Vec3> out;
  for (TopExp_Explorer f(shape, TopAbs_FACE); f.More(); f.Next())
    for (TopExp_Explorer e(f.Current(), TopAbs_EDGE); e.More(); e.Next()) {
      const TopoDS_Edge& edge = TopoDS::Edge(e.Current());
      if (!BRep_Tool::IsClosed(edge, TopoDS::Face(f.Current()))) continue;
      TopoDS_Vertex v0, v1;
      TopExp::Vertices(edge, v0, v1);
      for (const TopoDS_Vertex& v : {v0, v1}) {
        const gp_Pnt p = BRep_Tool::Pnt(v);
        out.emplace_back(p.X(), p.Y(), p.Z());
      }
    }
  return out;
}

bool contains_point(const std::vector<Vec3>& points, const Vec3& p, double tol) {
  return std::any_of(points.begin(), points.end(), [&](const Vec3& q) { return (q - p).norm() < tol; });
}

TopoDS_Shape read_brep(const std::string& text) {
  std::istringstream in(text);
  TopoDS_Shape shape;
  BRep_Builder builder;
  BRepTools::Read(shape, in, builder);
  return shape;
}

int face_count(const TopoDS_Shape& shape) {
  int n = 0;
  for (TopExp_Explorer e(shape, TopAbs_FACE); e.More(); e.Next()) ++n;
  return n;
}

// ---- the B-rep solids ------------------------------------------------------------------------------

TEST(OcctSleeve, SleeveIsOneValidSolidWithTheExactVolume) {
  for (const Vec3& dir : directions()) {
    SCOPED_TRACE(testing::Message() << "direction " << dir.transpose());
    const TubeSpec t = make_tube(dir);
    const TopoDS_Shape s = st::make_sleeve_shape(t);
    ASSERT_FALSE(s.IsNull());
    EXPECT_EQ(s.ShapeType(), TopAbs_SOLID);
    EXPECT_TRUE(BRepCheck_Analyzer(s).IsValid());
    EXPECT_EQ(face_count(s), 4); // outer and inner wall, two annular caps
    EXPECT_NEAR(gprop_volume(s), exact_sleeve_volume(t), 1e-9 * exact_sleeve_volume(t));
  }
}

TEST(OcctSleeve, SeamsLieAtAngleZeroOfTheKernelFrame) {
  const TubeSpec t = make_tube(Vec3(1, 2, -3));
  Vec3 u, v;
  st::orthonormal_frame(st::tube_axis(t), u, v);
  const std::vector<Vec3> seams = seam_points(st::make_sleeve_shape(t));
  ASSERT_FALSE(seams.empty());
  for (double z : {t.offset, t.offset + t.length})
    for (double radius : {t.inner_radius, t.outer_radius})
      EXPECT_TRUE(contains_point(seams, st::tube_point(t, z) + radius * u, 1e-9)) << "z " << z << " r " << radius;

  // The cylinder's seam is where cylinder_mesh puts its first vertex.
  const st::Cylinder c = st::tube_cylinder(t, t.outer_radius, t.offset, t.offset + t.length);
  const TopoDS_Shape cyl = st::make_cylinder_shape(c);
  EXPECT_EQ(cyl.ShapeType(), TopAbs_SOLID);
  EXPECT_TRUE(BRepCheck_Analyzer(cyl).IsValid());
  const TriangleMesh kernel_mesh = st::cylinder_mesh(c, 0.01);
  EXPECT_TRUE(contains_point(seam_points(cyl), kernel_mesh.positions[0], 1e-9));
  EXPECT_NEAR(gprop_volume(cyl), kPi * c.radius * c.radius * c.height, 1e-9 * c.height * c.radius * c.radius);
}

// ---- tessellation ----------------------------------------------------------------------------------

TEST(OcctSleeve, TessellationIsAClosedOutwardSolidOnTheSurface) {
  const double d = 0.01;
  for (const Vec3& dir : directions()) {
    SCOPED_TRACE(testing::Message() << "direction " << dir.transpose());
    const TubeSpec t = make_tube(dir);
    const TriangleMesh mesh = st::tessellate_shape(st::make_sleeve_shape(t), d);
    const st::SolidReport report = st::check_solid(mesh);
    EXPECT_TRUE(report.valid()) << report.summary();
    EXPECT_EQ(report.components, 1u) << report.summary();
    st::test::expect_valid_solid(mesh);

    for (const Vec3& p : mesh.positions) {
      const Cyl c = cylindrical(t, p);
      ASSERT_GE(c.rho, t.inner_radius - kOnSurface) << p.transpose();
      ASSERT_LE(c.rho, t.outer_radius + kOnSurface) << p.transpose();
      ASSERT_GE(c.z, t.offset - kOnSurface) << p.transpose();
      ASSERT_LE(c.z, t.offset + t.length + kOnSurface) << p.transpose();
      // On the surface: on a wall or on a cap.
      const bool on_wall =
          std::abs(c.rho - t.inner_radius) < kOnSurface || std::abs(c.rho - t.outer_radius) < kOnSurface;
      const bool on_cap = std::abs(c.z - t.offset) < kOnSurface || std::abs(c.z - t.offset - t.length) < kOnSurface;
      ASSERT_TRUE(on_wall || on_cap) << p.transpose();
    }

    // The chordal premise of the volume bound, then the bound itself.
    EXPECT_LE(max_side_deviation(t, mesh), d * (1 + 1e-9));
    const auto [lo, hi] = chordal_volume_range(t, d);
    EXPECT_GE(report.volume, lo);
    EXPECT_LE(report.volume, hi);
  }
}

TEST(OcctSleeve, VolumeConvergesAsTheDeflectionShrinks) {
  const TubeSpec t = make_tube(Vec3(-0.3, 0.5, 0.81), 1.6, 2.5, 30.0, 0.0);
  const TopoDS_Shape s = st::make_sleeve_shape(t);
  const double exact = exact_sleeve_volume(t);
  // An angular deflection that never binds, so the linear one alone sets the segments.
  const double angular = 1.0;
  // A fine run first: the triangulation it could leave on the shape must not be reused below.
  st::tessellate_shape(s, 0.001, angular);
  double previous_error = std::numeric_limits<double>::infinity();
  std::size_t previous_triangles = 0;
  for (double d : {0.1, 0.03, 0.01, 0.003, 0.001}) {
    SCOPED_TRACE(testing::Message() << "deflection " << d);
    const TriangleMesh mesh = st::tessellate_shape(s, d, angular);
    const double volume = st::signed_volume(mesh);
    const auto [lo, hi] = chordal_volume_range(t, d);
    EXPECT_GE(volume, lo);
    EXPECT_LE(volume, hi);
    EXPECT_LE(max_side_deviation(t, mesh), d * (1 + 1e-9));
    // The chordal error of a circle is linear in the deflection: a third of the deflection
    // removes well over half of the error.
    const double error = std::abs(volume - exact);
    EXPECT_LT(error, 0.5 * previous_error);
    EXPECT_GT(mesh.face_count(), previous_triangles);
    previous_error = error;
    previous_triangles = mesh.face_count();
  }
  EXPECT_LT(previous_error, 1e-3 * exact);
}

// Regression: BRepMesh_IncrementalMesh keeps a finer triangulation it finds on the faces, so with
// OpenCASCADE 7.6.3 meshing the shape itself returned the 0.001 mesh again for 0.1.
TEST(OcctSleeve, TessellationLeavesTheShapeUntouched) {
  const TopoDS_Shape s = st::make_sleeve_shape(make_tube(Vec3(0, 0, 1)));
  const TriangleMesh fine = st::tessellate_shape(s, 0.001);
  const TriangleMesh coarse = st::tessellate_shape(s, 0.1);
  EXPECT_LT(coarse.face_count(), fine.face_count());
  for (TopExp_Explorer e(s, TopAbs_FACE); e.More(); e.Next()) {
    TopLoc_Location loc;
    EXPECT_TRUE(BRep_Tool::Triangulation(TopoDS::Face(e.Current()), loc).IsNull());
  }
}

TEST(OcctSleeve, LocatedShapeIsTessellatedWhereItIs) {
  // A sleeve along +z at the origin, moved onto an oblique tube: the faces carry the location.
  const TubeSpec local = make_tube(Vec3(0, 0, -1), 2.0, 3.0, 20.0, 1.5, Vec3::Zero());
  const Vec3 target_axis = Vec3(1, -2, 2).normalized();
  const Vec3 target_entry(5, 6, -7);
  const Eigen::Quaterniond q = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), target_axis);
  const Eigen::AngleAxisd aa(q);
  gp_Trsf rotation, translation;
  rotation.SetRotation(gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(aa.axis().x(), aa.axis().y(), aa.axis().z())), aa.angle());
  translation.SetTranslation(gp_Vec(target_entry.x(), target_entry.y(), target_entry.z()));
  const TopoDS_Shape moved = st::make_sleeve_shape(local).Moved(TopLoc_Location(translation * rotation));

  const TriangleMesh mesh = st::tessellate_shape(moved, 0.01);
  st::test::expect_valid_solid(mesh);
  TubeSpec target = local;
  target.entry = target_entry;
  target.direction = -target_axis;
  for (const Vec3& p : mesh.positions) {
    const Cyl c = cylindrical(target, p);
    ASSERT_GE(c.rho, target.inner_radius - kOnSurface);
    ASSERT_LE(c.rho, target.outer_radius + kOnSurface);
    ASSERT_GE(c.z, target.offset - kOnSurface);
    ASSERT_LE(c.z, target.offset + target.length + kOnSurface);
  }
  const auto [lo, hi] = chordal_volume_range(target, 0.01);
  EXPECT_GE(st::signed_volume(mesh), lo);
  EXPECT_LE(st::signed_volume(mesh), hi);
}

TEST(OcctSleeve, SphereWithDegenerateEdgesIsWelded) {
  // Poles are degenerate edges: their nodes weld into one vertex and the collapsed triangles go.
  const double R = 5.0, d = 0.01;
  const TriangleMesh mesh = st::tessellate_shape(BRepPrimAPI_MakeSphere(gp_Pnt(1, 2, 3), R).Shape(), d);
  st::test::expect_valid_solid(mesh);
  for (const Vec3& p : mesh.positions) ASSERT_NEAR((p - Vec3(1, 2, 3)).norm(), R, kOnSurface);
  // An inscribed polyhedron within d of the sphere holds the ball of radius R - d.
  const double volume = st::signed_volume(mesh);
  EXPECT_LE(volume, 4.0 / 3.0 * kPi * R * R * R);
  EXPECT_GE(volume, 4.0 / 3.0 * kPi * std::pow(R - d, 3));
}

// ---- BREP text ---------------------------------------------------------------------------------------

TEST(OcctSleeve, BrepTextRoundTripsToTheSameSolid) {
  for (const Vec3& dir : {Vec3(0, 0, 1), Vec3(1, 2, -3)}) {
    SCOPED_TRACE(testing::Message() << "direction " << dir.transpose());
    const TubeSpec t = make_tube(dir, 1.25, 2.0, 15.0, 3.0);
    const TopoDS_Shape s = st::make_sleeve_shape(t);
    st::tessellate_shape(s, 0.01); // no triangulation sneaks into the text either way
    const std::string text = st::shape_to_brep(s);
    EXPECT_LT(text.find("CASCADE Topology V2"), 4u) << text.substr(0, 60); // after a blank line
    EXPECT_EQ(text.find("Triangulations 1"), std::string::npos);

    const TopoDS_Shape back = read_brep(text);
    ASSERT_FALSE(back.IsNull());
    EXPECT_EQ(back.ShapeType(), TopAbs_SOLID);
    EXPECT_TRUE(BRepCheck_Analyzer(back).IsValid());
    EXPECT_EQ(face_count(back), 4);
    EXPECT_NEAR(gprop_volume(back), gprop_volume(s), 1e-9 * gprop_volume(s));
    EXPECT_NEAR(gprop_volume(back), exact_sleeve_volume(t), 1e-9 * exact_sleeve_volume(t));
    // And it meshes like the original.
    const TriangleMesh mesh = st::tessellate_shape(back, 0.01);
    EXPECT_TRUE(st::check_solid(mesh).valid());
  }
}

// ---- invalid input -----------------------------------------------------------------------------------

TEST(OcctSleeve, InvalidTubesThrowInvalidInputNamingTheKey) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto expect_invalid = [](TubeSpec t, const std::string& key) {
    try {
      st::make_sleeve_shape(t);
      ADD_FAILURE() << "no exception for " << key;
    } catch (const st::InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("test-tube"), std::string::npos) << e.what();
    }
  };
  expect_invalid(make_tube(Vec3::Zero()), "direction");
  expect_invalid(make_tube(Vec3(0, nan, 1)), "direction");
  expect_invalid(make_tube(Vec3(0, 0, 1), 2.0, 3.0, 20.0, 1.5, Vec3(nan, 0, 0)), "entry");
  expect_invalid(make_tube(Vec3(0, 0, 1), 3.0, 3.0), "outer_radius");
  expect_invalid(make_tube(Vec3(0, 0, 1), 3.5, 3.0), "outer_radius");
  expect_invalid(make_tube(Vec3(0, 0, 1), 0.0, 3.0), "inner_radius");
  expect_invalid(make_tube(Vec3(0, 0, 1), nan, 3.0), "inner_radius");
  expect_invalid(make_tube(Vec3(0, 0, 1), 2.0, 3.0, -1.0), "length");
  expect_invalid(make_tube(Vec3(0, 0, 1), 2.0, 3.0, 20.0, nan), "offset");

  EXPECT_THROW(st::make_cylinder_shape({Vec3::Zero(), Vec3::Zero(), 1.0, 1.0}), st::InvalidInput);
  EXPECT_THROW(st::make_cylinder_shape({Vec3::Zero(), Vec3::UnitZ(), -1.0, 1.0}), st::InvalidInput);
  EXPECT_THROW(st::make_cylinder_shape({Vec3::Zero(), Vec3::UnitZ(), 1.0, nan}), st::InvalidInput);
}

TEST(OcctSleeve, BadDeflectionsAndShapesAreRefused) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const TopoDS_Shape s = st::make_sleeve_shape(make_tube(Vec3(0, 0, 1)));
  for (double d : {-0.01, 0.0, nan, inf}) {
    EXPECT_THROW(st::tessellate_shape(s, d), st::InvalidInput) << d;
    EXPECT_THROW(st::tessellate_shape(s, 0.01, d), st::InvalidInput) << d;
  }
  EXPECT_THROW(st::tessellate_shape(TopoDS_Shape(), 0.01), st::InvalidInput);
  EXPECT_THROW(st::shape_to_brep(TopoDS_Shape()), st::InvalidInput);
  // A single face is no solid: its mesh has a border.
  const TopoDS_Shape square = BRepBuilderAPI_MakeFace(gp_Pln(), -1.0, 1.0, -1.0, 1.0).Shape();
  EXPECT_THROW(st::tessellate_shape(square, 0.01), st::GeometryError);
}

} // namespace
