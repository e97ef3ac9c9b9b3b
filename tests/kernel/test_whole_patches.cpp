// The solid check passes over the pairs within a whole patch (validate/embedded_patch.h): a sheet whose
// faces all turn one way seen along an axis, bordered by loops that project to simple polygons apart
// from each other, none of them wound the wrong way. A sheet with holes is one such patch; a strip
// grown from a hole's edge over the sheet and down through it is not: its crossings are counted as
// testing every pair of overlapping boxes counts them. On a grid of exact (dyadic) coordinates, the
// strip meeting the sheet exactly at its vertices, and on a wavy one.

#include "helpers.h"

#include "st/boolean/triangle_intersection.h"
#include "st/core/topology.h"
#include "st/validate/validate.h"
#include "validate/embedded_patch.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <vector>

namespace st {
namespace {

/// A sheet over [0, 10]^2 in cells of 0.5 at height z(x, y), without the cells in `holes` (each
/// {x0, x1, y0, y1}); with `strip`, a strip grown from the right edge of the first hole leftwards to x
/// = 2, y in [4.5, 5.5], at height strip(x), sharing the hole's corners at x = 6.
TriangleMesh holed_sheet(const std::function<double(double, double)>& z,
                         const std::vector<std::array<double, 4>>& holes, const std::function<double(double)>& strip) {
  TriangleMesh m;
  constexpr int n = 20;
  auto id = [](int i, int j) { return static_cast<Index>(j * (n + 1) + i); };
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.positions.emplace_back(0.5 * i, 0.5 * j, z(0.5 * i, 0.5 * j));
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = 0.5 * i + 0.25, y = 0.5 * j + 0.25;
      bool hole = false;
      for (const auto& h : holes) hole = hole || (x > h[0] && x < h[1] && y > h[2] && y < h[3]);
      if (hole) continue;
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  if (strip) {
    std::map<std::pair<int, int>, Index> at; // (column from x = 2, row from y = 4.5) -> vertex
    for (int c = 0; c <= 8; ++c)
      for (int r = 0; r <= 2; ++r) {
        const double x = 2.0 + 0.5 * c, y = 4.5 + 0.5 * r;
        if (c == 8) {
          at[{c, r}] = id(12, 9 + r); // the hole's corner at x = 6
        } else {
          at[{c, r}] = m.vertex_count();
          m.positions.emplace_back(x, y, strip(x));
        }
      }
    for (int c = 0; c < 8; ++c)
      for (int r = 0; r < 2; ++r) {
        m.triangles.push_back({at[{c, r}], at[{c + 1, r}], at[{c + 1, r + 1}]});
        m.triangles.push_back({at[{c, r}], at[{c + 1, r + 1}], at[{c, r + 1}]});
      }
  }
  return m;
}

/// Pairs of faces that meet (but where they share corners or edges), testing every pair.
std::size_t crossing_pairs(const TriangleMesh& m) {
  std::size_t count = 0;
  for (Index a = 0; a < m.face_count(); ++a)
    for (Index b = a + 1; b < m.face_count(); ++b) {
      if (!triangle_box(m, a).overlaps(triangle_box(m, b))) continue;
      const Triangle &ta = m.triangles[a], &tb = m.triangles[b];
      count += mesh_triangles_intersect(ta, {m.positions[ta[0]], m.positions[ta[1]], m.positions[ta[2]]}, tb,
                                        {m.positions[tb[0]], m.positions[tb[1]], m.positions[tb[2]]})
                   ? 1
                   : 0;
    }
  return count;
}

std::size_t faces_in_whole_patches(const TriangleMesh& m) {
  const std::vector<Index> opposite = MeshTopology(m).all_opposites();
  const std::vector<Index> whole = validate_detail::whole_patches(m, opposite, validate_detail::projection_turns(m));
  return static_cast<std::size_t>(
      std::count_if(whole.begin(), whole.end(), [](Index p) { return p != kInvalidIndex; }));
}

const std::vector<std::array<double, 4>> kHoles = {{4.0, 6.0, 4.0, 6.0}, {1.0, 2.5, 7.0, 9.0}, {7.5, 9.0, 1.0, 2.0}};

TEST(WholePatches, ASheetWithHolesIsOneWholePatch) {
  const auto flat = [](double, double) { return 0.0; };
  const auto wavy = [](double x, double y) { return 0.4 * std::sin(0.9 * x) * std::cos(0.7 * y); };
  SolidOptions all;
  all.max_reported = std::numeric_limits<std::size_t>::max();
  for (const auto& z : {std::function<double(double, double)>(flat), std::function<double(double, double)>(wavy)}) {
    const TriangleMesh sheet = holed_sheet(z, kHoles, nullptr);
    EXPECT_EQ(faces_in_whole_patches(sheet), sheet.face_count());
    EXPECT_EQ(check_solid(sheet, all).self_intersections, 0u);
  }
}

TEST(WholePatches, AStripFromAHoleDownThroughTheSheetIsCountedAsEveryPairCountsIt) {
  const auto flat = [](double, double) { return 0.0; };
  const auto wavy = [](double x, double y) { return 0.1 * std::sin(0.9 * x) * std::cos(0.7 * y); };
  // Rising from the hole's edge at x = 6 (37 degrees: a gentle edge, the strip turns as the sheet),
  // back to 0 at x = 3 over the sheet (exactly, on the flat one: the strip's corners there lie on it)
  // and below it to x = 2.
  const auto strip = [](double x) { return 0.25 * (6.0 - x) * (x - 3.0); };
  SolidOptions all;
  all.max_reported = std::numeric_limits<std::size_t>::max();
  for (const auto& z : {std::function<double(double, double)>(flat), std::function<double(double, double)>(wavy)}) {
    const TriangleMesh m = holed_sheet(z, kHoles, strip);
    const std::size_t expected = crossing_pairs(m);
    EXPECT_GT(expected, 0u);
    EXPECT_EQ(check_solid(m, all).self_intersections, expected);
    EXPECT_LT(faces_in_whole_patches(m), m.face_count());
  }
}

TEST(WholePatches, TwoWholePatchesThatCrossAreTestedAgainstEachOther) {
  // The holed sheet and a separate plate tilted through it (not joined): each a whole patch, the
  // pairs between them tested.
  const TriangleMesh sheet = holed_sheet([](double, double) { return 0.0; }, kHoles, nullptr);
  const TriangleMesh plate = test::make_grid_patch(
      8, 6.5, 9.5, 5.0, 8.0, [](double u, double v) { return Vec3(u, v, 0.5 * (u - 8.0) + 0.125); });
  TriangleMesh both = sheet;
  const Index n = both.vertex_count();
  both.positions.insert(both.positions.end(), plate.positions.begin(), plate.positions.end());
  for (const Triangle& t : plate.triangles) both.triangles.push_back({t[0] + n, t[1] + n, t[2] + n});
  EXPECT_EQ(faces_in_whole_patches(both), both.face_count());
  SolidOptions all;
  all.max_reported = std::numeric_limits<std::size_t>::max();
  const std::size_t expected = crossing_pairs(both);
  EXPECT_GT(expected, 0u);
  EXPECT_EQ(check_solid(both, all).self_intersections, expected);
}

} // namespace
} // namespace st
