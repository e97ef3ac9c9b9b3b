// Coordinates rounded to float32 (float32.h): the rounding survives the optimizer, and the guide the
// kernel checks holds exactly the coordinates its STL file holds. Decided on the doubles' bits, not
// with another conversion the compiler could fold away.

#include "helpers.h"

#include "st/boolean/boolean.h"
#include "st/core/float32.h"
#include "st/design/template_design.h"
#include "st/io/case_file.h"
#include "st/io/mesh_io.h"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <random>

namespace st {
namespace {

/// Whether x is a normal float32 value or zero, from its bits: the significand's low 29 bits clear
/// and the exponent within float32's normal range.
bool fits_float32(double x) {
  if (x == 0.0) return true;
  const auto bits = std::bit_cast<std::uint64_t>(x);
  const int exponent = static_cast<int>((bits >> 52) & 0x7FF) - 1023;
  return (bits & ((std::uint64_t{1} << 29) - 1)) == 0 && exponent >= -126 && exponent <= 127;
}

std::size_t positions_off_float32(const TriangleMesh& mesh) {
  std::size_t off = 0;
  for (const Vec3& p : mesh.positions) off += !(fits_float32(p.x()) && fits_float32(p.y()) && fits_float32(p.z()));
  return off;
}

// The pattern GCC 12's SLP vectorizer broke in the Boolean operation's curve points: a point computed
// in doubles, then its coordinates rounded one after the other.
[[gnu::noinline]] Vec3 rounded_point_on_segment(const Vec3& p, const Vec3& q, double t) {
  return to_float32(Vec3(p + t * (q - p)));
}

TEST(Float32, CoordinatesRoundedInVectorizableCodeAreFloat32Values) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> coordinate(-700.0, 700.0), t(0.0, 1.0);
  for (int k = 0; k < 10000; ++k) {
    const Vec3 p(coordinate(rng), coordinate(rng), coordinate(rng));
    const Vec3 q(coordinate(rng), coordinate(rng), coordinate(rng));
    const Vec3 r = rounded_point_on_segment(p, q, t(rng));
    ASSERT_TRUE(fits_float32(r.x()) && fits_float32(r.y()) && fits_float32(r.z()))
        << "case " << k << ": " << r.transpose() << " is not a float32 point";
    ASSERT_TRUE(is_float32(r));
  }
  EXPECT_FALSE(is_float32(Vec3(0.1, 0.0, 0.0)));
  EXPECT_EQ(to_float32(0.1), static_cast<double>(0.1f));
}

TEST(Float32, BooleanResultsHoldFloat32Coordinates) {
  const TriangleMesh a = test::make_icosphere(10.0, 3, Vec3(600.3, 400.7, 350.1));
  const TriangleMesh b = test::make_icosphere(7.0, 3, Vec3(608.6, 401.8, 349.4));
  for (const BooleanOp op : {BooleanOp::Union, BooleanOp::Difference, BooleanOp::Intersection}) {
    const BooleanResult r = mesh_boolean(a, b, op);
    EXPECT_GT(r.curve_segments, 50u);
    EXPECT_EQ(positions_off_float32(r.mesh), 0u) << "of " << r.mesh.vertex_count() << " vertices";
  }
}

TEST(Float32, AGuideIsCheckedWithTheCoordinatesItsStlHolds) {
  // The tibia lies 600 mm from the scan's origin, where float32 values are 6e-5 mm apart: a coordinate
  // left in double there moves when written, and two faces that did not cross may cross in the file.
  const CaseFile c = read_case(test::examples_dir() + "/cases/tibia-osteotomy.json");
  const TriangleMesh bone = read_mesh(c.bone);
  const TemplateResult r = design_template(bone, st::test::case_options(c));
  EXPECT_EQ(positions_off_float32(r.shell), 0u) << "of " << r.shell.vertex_count() << " vertices";
  const std::string path = test::output_dir() + "/float32-tibia.stl";
  write_stl(r.shell, path);
  const TriangleMesh back = read_mesh(path);
  ASSERT_EQ(back.face_count(), r.shell.face_count());
  const SolidReport report = check_solid(back);
  EXPECT_TRUE(report.valid()) << "the written guide: " << report.summary();
  EXPECT_NEAR(report.volume, signed_volume(r.shell), 1e-9 * report.volume);
}

} // namespace
} // namespace st
