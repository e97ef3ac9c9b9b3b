#include "validate/embedded_patch.h"

#include "detail/parallel.h"
#include "st/core/predicates.h"

#include <algorithm>
#include <array>
#include <bit>
#include <utility>

namespace st::validate_detail {

namespace {

using Point2 = std::array<double, 2>;

Point2 dropped(const Vec3& p, int axis) { return {p[(axis + 1) % 3], p[(axis + 2) % 3]}; }

// Whether c, on the line through a and b, lies on the closed segment [a, b].
bool within(const Point2& a, const Point2& b, const Point2& c) {
  return std::min(a[0], b[0]) <= c[0] && c[0] <= std::max(a[0], b[0]) && std::min(a[1], b[1]) <= c[1] &&
         c[1] <= std::max(a[1], b[1]);
}

// Whether the closed segments [a, b] and [c, d] share a point.
bool segments_meet(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  const int o1 = orient2d(a.data(), b.data(), c.data()), o2 = orient2d(a.data(), b.data(), d.data());
  const int o3 = orient2d(c.data(), d.data(), a.data()), o4 = orient2d(c.data(), d.data(), b.data());
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;
  return (o1 == 0 && within(a, b, c)) || (o2 == 0 && within(a, b, d)) || (o3 == 0 && within(c, d, a)) ||
         (o4 == 0 && within(c, d, b));
}

// Whether segments [a, s] and [s, d], both of positive length, share a point besides s: on one line,
// a and d on the same side of s.
bool fold_at(const Point2& a, const Point2& s, const Point2& d) {
  if (orient2d(a.data(), s.data(), d.data()) != 0) return false;
  const int m = a[0] != s[0] ? 0 : 1;
  return (a[m] > s[m]) == (d[m] > s[m]);
}

// Whether the closed polygon through `loop` (at least 3 points) is simple: consecutive edges meet only
// at their common corner, others not at all. The pairs whose boxes overlap, by a sweep along x.
bool simple_polygon(const std::vector<Point2>& loop) {
  const std::size_t n = loop.size();
  struct Edge {
    double x0, x1, y0, y1;
    std::size_t i; // from loop[i] to loop[i + 1]
  };
  std::vector<Edge> edges(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Point2 &p = loop[i], &q = loop[(i + 1) % n];
    edges[i] = {std::min(p[0], q[0]), std::max(p[0], q[0]), std::min(p[1], q[1]), std::max(p[1], q[1]), i};
  }
  std::sort(edges.begin(), edges.end(), [](const Edge& a, const Edge& b) { return a.x0 < b.x0; });
  for (std::size_t u = 0; u < n; ++u)
    for (std::size_t w = u + 1; w < n && edges[w].x0 <= edges[u].x1; ++w) {
      const Edge &e = edges[u], &f = edges[w];
      if (f.y0 > e.y1 || e.y0 > f.y1) continue;
      const std::size_t i = std::min(e.i, f.i), j = std::max(e.i, f.i);
      const Point2 &a = loop[i], &b = loop[(i + 1) % n], &c = loop[j], &d = loop[(j + 1) % n];
      if (j == i + 1) { // [a, b] then [b, d]
        if (fold_at(a, b, d)) return false;
      } else if (i == 0 && j == n - 1) { // [c, a] then [a, b]
        if (fold_at(c, a, b)) return false;
      } else if (segments_meet(a, b, c, d)) {
        return false;
      }
    }
  return true;
}

} // namespace

std::vector<std::uint8_t> projection_turns(const TriangleMesh& mesh) {
  std::vector<std::uint8_t> turns(mesh.face_count(), 0);
  detail::parallel_for(mesh.face_count(), 4096, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f) {
      const Triangle& t = mesh.triangles[f];
      if (!mesh.positions[t[0]].allFinite() || !mesh.positions[t[1]].allFinite() || !mesh.positions[t[2]].allFinite())
        continue; // no turn: no patch holds it, its pairs are all tested
      std::uint8_t bits = 0;
      for (int k = 0; k < 3; ++k) {
        const Point2 a = dropped(mesh.positions[t[0]], k), b = dropped(mesh.positions[t[1]], k),
                     c = dropped(mesh.positions[t[2]], k);
        const int o = orient2d(a.data(), b.data(), c.data());
        if (o > 0) bits |= std::uint8_t(1u << (2 * k));
        if (o < 0) bits |= std::uint8_t(1u << (2 * k + 1));
      }
      turns[f] = bits;
    }
  });
  return turns;
}

Patches::Patches(const TriangleMesh& mesh, const std::vector<Index>& opposite, const std::vector<std::uint8_t>& turns,
                 std::span<const Index> order)
    : mesh_(mesh), opposite_(opposite), order_(order), position_(mesh.face_count(), kInvalidIndex),
      runs_(order.size() + 1) {
  const Index n = static_cast<Index>(order.size());
  for (Index i = 0; i < n; ++i) position_[order[i]] = i;
  runs_[n].fill(n);
  for (Index i = n; i-- > 0;)
    for (int b = 0; b < 6; ++b) runs_[i][b] = (turns[order[i]] >> b) & 1u ? runs_[i + 1][b] : i;
}

bool Patches::embedded(Index begin, Index end) const {
  int bit = 0;
  while (bit < 6 && runs_[begin][bit] < end) ++bit;
  if (bit == 6) return false;
  const int axis = bit / 2;

  // The border: half-edges whose partner is missing or outside the patch, as (from, to) corners.
  std::vector<std::pair<Index, Index>> border;
  for (Index i = begin; i < end; ++i) {
    const Index f = order_[i];
    const Triangle& t = mesh_.triangles[f];
    for (Index k = 0; k < 3; ++k) {
      const Index o = opposite_[3 * f + k];
      if (o != kInvalidIndex) {
        const Index at = position_[o / 3];
        if (at >= begin && at < end) continue;
      }
      border.emplace_back(t[k], t[(k + 1) % 3]);
    }
  }
  if (border.size() < 3) return false;
  // One loop: each corner starts one border half-edge, and the walk from one returns after all.
  std::sort(border.begin(), border.end());
  for (std::size_t i = 1; i < border.size(); ++i)
    if (border[i].first == border[i - 1].first) return false;
  std::vector<Point2> loop;
  loop.reserve(border.size());
  const Index start = border.front().first;
  Index v = start;
  do {
    loop.push_back(dropped(mesh_.positions[v], axis));
    const auto next = std::lower_bound(border.begin(), border.end(), std::pair<Index, Index>{v, 0});
    if (next == border.end() || next->first != v) return false;
    v = next->second;
  } while (v != start && loop.size() < border.size());
  if (v != start || loop.size() != border.size()) return false;
  return simple_polygon(loop);
}

} // namespace st::validate_detail
