// Ear clipping of polygons with holes (the block-out's fill, design/polygon_fill.h): areas add up,
// every triangle turns counter-clockwise, and rings, combs and exactly repeated points are filled.

#include "st/core/polygon_fill.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace st {
namespace {

double area_of(const std::vector<Point2>& pts, const std::vector<std::array<Index, 3>>& tris) {
  double a = 0.0;
  for (const auto& t : tris) {
    const Point2 &p = pts[t[0]], &q = pts[t[1]], &r = pts[t[2]];
    const double twice = (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
    EXPECT_GE(twice, 0.0);
    a += 0.5 * twice;
  }
  return a;
}

/// A ring of n points of radius r, counter-clockwise (or clockwise), indices appended to `pts`.
std::vector<Index> ring(std::vector<Point2>& pts, int n, double r, bool ccw, double phase = 0.0) {
  std::vector<Index> loop;
  for (int k = 0; k < n; ++k) {
    const double a = (ccw ? 1.0 : -1.0) * (2.0 * std::numbers::pi * k / n + phase);
    loop.push_back(static_cast<Index>(pts.size()));
    pts.push_back({r * std::cos(a), r * std::sin(a)});
  }
  return loop;
}

TEST(PolygonFill, AnnulusBetweenTwoRings) {
  std::vector<Point2> pts;
  const auto outer = ring(pts, 192, 4.3, true, 0.01);
  const auto hole = ring(pts, 128, 4.0, false);
  const auto tris = fill_polygon(pts, {outer, hole});
  ASSERT_TRUE(tris.has_value());
  EXPECT_NEAR(area_of(pts, *tris), 0.5 * (loop_area2(pts, outer) + loop_area2(pts, hole)), 1e-9);
  EXPECT_EQ(tris->size(), 192u + 128u);
}

TEST(PolygonFill, CombWithTwoHolesAndCollinearRuns) {
  // A comb (ten teeth: many reflex corners), its back a run of collinear points, with two square
  // holes in the back: the triangles cover exactly the comb minus the holes.
  std::vector<Point2> pts;
  std::vector<Index> outer;
  auto add = [&](double x, double y, std::vector<Index>& loop) {
    loop.push_back(static_cast<Index>(pts.size()));
    pts.push_back({x, y});
  };
  for (int k = 0; k <= 20; ++k) add(k, 0.0, outer); // the back's lower edge, collinear
  for (int k = 10; k > 0; --k) {                    // teeth, right to left
    add(2.0 * k, 8.0, outer);
    add(2.0 * k - 1.0, 8.0, outer);
    add(2.0 * k - 1.0, 3.0, outer);
    add(2.0 * k - 2.0, 3.0, outer);
  }
  outer.pop_back(); // (0, 3) closes onto (0, 0) through the left edge
  add(0.0, 8.0, outer);
  std::vector<Index> hole1, hole2;
  for (const auto& [x, y] : std::vector<std::array<double, 2>>{{2, 1}, {2, 2}, {4, 2}, {4, 1}}) add(x, y, hole1);
  for (const auto& [x, y] : std::vector<std::array<double, 2>>{{12, 1}, {12, 2}, {15, 2}, {15, 1}}) add(x, y, hole2);
  ASSERT_GT(loop_area2(pts, outer), 0.0);
  ASSERT_LT(loop_area2(pts, hole1), 0.0);
  const auto tris = fill_polygon(pts, {outer, hole1, hole2});
  ASSERT_TRUE(tris.has_value());
  EXPECT_NEAR(area_of(pts, *tris), 0.5 * (loop_area2(pts, outer) + loop_area2(pts, hole1) + loop_area2(pts, hole2)),
              1e-9);
}

TEST(PolygonFill, LoopsThatCrossAreRefused) {
  // A bow tie (the loop crosses itself): no ear clipping covers it; nothing is returned.
  const std::vector<Point2> pts = {{0, 0}, {2, 2}, {2, 0}, {0, 2}};
  EXPECT_FALSE(fill_polygon(pts, {{0, 1, 2, 3}}).has_value());
}

} // namespace
} // namespace st
