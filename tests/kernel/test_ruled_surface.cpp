// Ruled wall: m + n triangles, every contour segment used once, no crossing, consistent orientation.

#include "helpers.h"

#include "st/core/errors.h"
#include "st/design/ruled_surface.h"
#include "st/boolean/triangle_intersection.h"

#include <algorithm>
#include <limits>
#include <numbers>
#include <random>

using namespace st;

namespace {

std::vector<Vec3> ellipse(int n, double a, double b, double z, double phase) {
  std::vector<Vec3> pts;
  for (int i = 0; i < n; ++i) {
    const double t = phase + 2 * std::numbers::pi * i / n;
    pts.emplace_back(a * std::cos(t), b * std::sin(t), z + 0.3 * std::sin(3 * t));
  }
  return pts;
}

} // namespace

TEST(RuledSurface, HasMPlusNTrianglesUsingEverySegmentOnce) {
  const auto p = ellipse(37, 10, 6, 0, 0.0);
  const auto q = ellipse(53, 10.5, 6.4, 2.5, 1.0);
  const RuledResult r = ruled_surface(p, q, 0, 37);
  ASSERT_EQ(r.triangles.size(), 37u + 53u);
  // Each P segment i -> i+1 and each Q segment j+1 -> j appears exactly once.
  std::map<std::pair<Index, Index>, int> uses;
  for (const Triangle& t : r.triangles)
    for (int k = 0; k < 3; ++k) uses[{t[k], t[(k + 1) % 3]}]++;
  for (Index i = 0; i < 37; ++i) EXPECT_EQ((uses[{i, (i + 1) % 37}]), 1) << i;
  for (Index j = 0; j < 53; ++j) EXPECT_EQ((uses[{37 + (j + 1) % 53, 37 + j}]), 1) << j;
  // Spans are shared by exactly two triangles in opposite directions: the strip is a closed band.
  for (const auto& [e, n] : uses) {
    const bool p_seg = e.first < 37 && e.second < 37;
    const bool q_seg = e.first >= 37 && e.second >= 37;
    if (p_seg || q_seg) continue;
    EXPECT_EQ(n, 1);
    EXPECT_EQ((uses[{e.second, e.first}]), 1);
  }
}

TEST(RuledSurface, StripDoesNotCrossItself) {
  const auto p = ellipse(60, 10, 6, 0, 0.0);
  const auto q = ellipse(90, 10.8, 6.6, 2.5, 2.0);
  std::vector<Vec3> pts = p;
  pts.insert(pts.end(), q.begin(), q.end());
  const RuledResult r = ruled_surface(p, q, 0, 60);
  for (std::size_t a = 0; a < r.triangles.size(); ++a)
    for (std::size_t b = a + 1; b < r.triangles.size(); ++b) {
      const Triangle& ta = r.triangles[a];
      const Triangle& tb = r.triangles[b];
      EXPECT_FALSE(
          mesh_triangles_intersect(ta, {pts[ta[0]], pts[ta[1]], pts[ta[2]]}, tb, {pts[tb[0]], pts[tb[1]], pts[tb[2]]}))
          << a << " " << b;
    }
}

TEST(RuledSurface, PicksAGoodStartForRotatedLoops) {
  // Q is P lifted and rotated in index: the best strip pairs each P_i with the Q above it.
  const auto p = ellipse(40, 10, 6, 0, 0.0);
  auto q = ellipse(40, 10, 6, 2.0, 0.0);
  std::rotate(q.begin(), q.begin() + 17, q.end());
  const RuledResult r = ruled_surface(p, q, 0, 40);
  // Every span is about 2 mm long (the lift), none cuts across the ellipse.
  for (const Triangle& t : r.triangles)
    for (int k = 0; k < 3; ++k) {
      const Index a = t[k], b = t[(k + 1) % 3];
      if ((a < 40) != (b < 40)) {
        const Vec3 pa = a < 40 ? p[a] : q[a - 40];
        const Vec3 pb = b < 40 ? p[b] : q[b - 40];
        EXPECT_LT((pa - pb).norm(), 3.0);
      }
    }
}

TEST(RuledSurface, RefusesTooShortLoops) {
  EXPECT_THROW(ruled_surface({Vec3::Zero()}, {Vec3::Zero(), Vec3::UnitX()}, 0, 1), InvalidInput);
}

// The wall is the shortest strip over the starting spans tried: a plain dynamic program per start
// (the paper's, one start at a time) finds the same length and the same triangles, for loops of a few
// to a few hundred points, one to eleven starts (the starts are taken eight at a time), noisy and
// with repeated points.
TEST(RuledSurface, IsTheShortestStripAPlainProgramFinds) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> size(2, 300);
  std::normal_distribution<double> noise(0.0, 0.4);
  for (int trial = 0; trial < 60; ++trial) {
    const int m = trial < 3 ? 2 + trial : size(rng), n = trial < 3 ? 3 : size(rng);
    std::vector<Vec3> p = ellipse(m, 10, 6, 0, 0.1 * trial), q = ellipse(n, 10.5, 6.4, 2.5, 0.3 * trial);
    for (Vec3& x : p) x += Vec3(noise(rng), noise(rng), noise(rng));
    if (trial % 5 == 0 && m > 3) p[2] = p[1];
    RuledOptions options;
    options.start_candidates = 1 + trial % 11;
    const RuledResult r = ruled_surface(p, q, 0, static_cast<Index>(m), options);

    // The starts: the Q point nearest P_0, then its neighbours alternately after and before it.
    std::size_t best_j = 0;
    for (std::size_t j = 1; j < q.size(); ++j)
      if ((p[0] - q[j]).squaredNorm() < (p[0] - q[best_j]).squaredNorm()) best_j = j;
    double best = std::numeric_limits<double>::infinity();
    std::vector<Triangle> expected;
    for (int c = 0; c < options.start_candidates; ++c) {
      const long offset = (c % 2 == 0 ? 1 : -1) * static_cast<long>((c + 1) / 2);
      const auto start = static_cast<std::size_t>(((static_cast<long>(best_j) + offset) % n + n) % n);
      auto P = [&](std::size_t i) { return p[i % m]; };
      auto Q = [&](std::size_t j) { return q[(j + start) % n]; };
      std::vector<std::vector<double>> d(m + 1, std::vector<double>(n + 1));
      std::vector<std::vector<bool>> up(m + 1, std::vector<bool>(n + 1, false));
      for (int i = 0; i <= m; ++i)
        for (int j = 0; j <= n; ++j) {
          const double span = (P(i) - Q(j)).norm();
          if (i == 0 && j == 0) d[i][j] = span;
          else if (i == 0) d[i][j] = d[i][j - 1] + span;
          else if (j == 0) d[i][j] = d[i - 1][j] + span, up[i][j] = true;
          else if (d[i - 1][j] <= d[i][j - 1]) d[i][j] = d[i - 1][j] + span, up[i][j] = true;
          else d[i][j] = d[i][j - 1] + span;
        }
      if (!(d[m][n] < best)) continue;
      best = d[m][n];
      expected.clear();
      for (int i = m, j = n; i > 0 || j > 0;) {
        if (up[i][j])
          --i, expected.push_back({static_cast<Index>(i % m), static_cast<Index>((i + 1) % m),
                                   static_cast<Index>(m + (j + start) % n)});
        else
          --j, expected.push_back({static_cast<Index>(i % m), static_cast<Index>(m + (j + 1 + start) % n),
                                   static_cast<Index>(m + (j + start) % n)});
      }
      std::reverse(expected.begin(), expected.end());
    }
    EXPECT_EQ(r.span_length, best) << "trial " << trial;
    EXPECT_EQ(r.triangles, expected) << "trial " << trial;
  }
}
