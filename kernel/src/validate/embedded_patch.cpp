#include "validate/embedded_patch.h"

#include "detail/parallel.h"
#include "st/core/predicates.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
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

// Whether the closed polygons through `loops` (at least 3 points each) are simple and apart: consecutive
// edges of a loop meet only at their common corner, other edges not at all. The pairs whose boxes
// overlap, by a sweep along x.
bool simple_and_apart(const std::vector<std::vector<Point2>>& loops) {
  struct Edge {
    double x0, x1, y0, y1;
    std::size_t loop, i; // from loops[loop][i] to the next
  };
  std::vector<Edge> edges;
  for (std::size_t l = 0; l < loops.size(); ++l) {
    const std::vector<Point2>& loop = loops[l];
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const Point2 &p = loop[i], &q = loop[(i + 1) % loop.size()];
      edges.push_back({std::min(p[0], q[0]), std::max(p[0], q[0]), std::min(p[1], q[1]), std::max(p[1], q[1]), l, i});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const Edge& a, const Edge& b) { return a.x0 < b.x0; });
  for (std::size_t u = 0; u < edges.size(); ++u)
    for (std::size_t w = u + 1; w < edges.size() && edges[w].x0 <= edges[u].x1; ++w) {
      const Edge &e = edges[u], &f = edges[w];
      if (f.y0 > e.y1 || e.y0 > f.y1) continue;
      const std::vector<Point2>&le = loops[e.loop], &lf = loops[f.loop];
      if (e.loop != f.loop) {
        if (segments_meet(le[e.i], le[(e.i + 1) % le.size()], lf[f.i], lf[(f.i + 1) % lf.size()])) return false;
        continue;
      }
      const std::size_t n = le.size(), i = std::min(e.i, f.i), j = std::max(e.i, f.i);
      const Point2 &a = le[i], &b = le[(i + 1) % n], &c = le[j], &d = le[(j + 1) % n];
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

// Whether p, not on the simple polygon `loop`, lies inside it: the parity of the edges crossing the
// ray from p along +x (an edge counts when one end lies above p's line and the other not, and p lies
// on its left going up).
bool inside(const std::vector<Point2>& loop, const Point2& p) {
  bool in = false;
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const Point2 &a = loop[i], &b = loop[(i + 1) % loop.size()];
    if ((a[1] > p[1]) == (b[1] > p[1])) continue;
    const int o = orient2d(a.data(), b.data(), p.data());
    if (b[1] > a[1] ? o > 0 : o < 0) in = !in;
  }
  return in;
}

// 1 when the simple polygon `loop` runs counterclockwise, -1 clockwise: the turn at its least corner
// (by x, then y), a corner of its hull.
int orientation(const std::vector<Point2>& loop) {
  const std::size_t n = loop.size();
  std::size_t m = 0;
  for (std::size_t i = 1; i < n; ++i)
    if (loop[i] < loop[m]) m = i;
  return orient2d(loop[(m + n - 1) % n].data(), loop[m].data(), loop[(m + 1) % n].data()) > 0 ? 1 : -1;
}

// Whether faces that all turn the way of turn bit `bit` (projection_turns) and have this border lie one
// over any point of the axis plane: the border half-edges (from, to) form loops, each corner starting
// and ending one, that project to simple polygons apart from each other, and just right of each loop
// (mirrored for a clockwise bit) the loops wind 0 times in sum. Over a point off the edges the faces
// number the loops' winding (each face turns one way: +1), which is 1 just left of a border edge
// (a face lies there) and so 1 more than just right of it; 0 on every right side leaves 0 or 1
// everywhere. The winding of another loop is the same over all of a loop it does not meet: read at
// one corner. Sorts `border`.
bool one_sheet(const TriangleMesh& mesh, std::vector<std::pair<Index, Index>>& border, int bit) {
  if (border.size() < 3) return false;
  std::sort(border.begin(), border.end());
  for (std::size_t i = 1; i < border.size(); ++i)
    if (border[i].first == border[i - 1].first) return false;
  const int axis = bit / 2;
  const bool mirrored = (bit & 1) != 0;
  auto projected = [&](Index v) {
    Point2 p = dropped(mesh.positions[v], axis);
    if (mirrored) std::swap(p[0], p[1]);
    return p;
  };
  std::vector<std::vector<Point2>> loops;
  std::vector<std::uint8_t> walked(border.size(), 0);
  for (std::size_t s = 0; s < border.size(); ++s) {
    if (walked[s]) continue;
    std::vector<Point2> loop;
    std::size_t at = s;
    do {
      walked[at] = 1;
      loop.push_back(projected(border[at].first));
      const auto next = std::lower_bound(border.begin(), border.end(), std::pair<Index, Index>{border[at].second, 0});
      if (next == border.end() || next->first != border[at].second) return false;
      at = static_cast<std::size_t>(next - border.begin());
    } while (at != s && !walked[at]);
    if (at != s || loop.size() < 3) return false; // a corner ends two border half-edges
    loops.push_back(std::move(loop));
  }
  if (!simple_and_apart(loops)) return false;
  std::vector<int> turn(loops.size());
  for (std::size_t i = 0; i < loops.size(); ++i) turn[i] = orientation(loops[i]);
  for (std::size_t i = 0; i < loops.size(); ++i) {
    int winding = turn[i] < 0 ? -1 : 0; // its own, just right of it
    for (std::size_t j = 0; j < loops.size(); ++j)
      if (j != i && inside(loops[j], loops[i][0])) winding += turn[j];
    if (winding != 0) return false;
  }
  return true;
}

// The border of `faces`: their half-edges whose partner is missing or not in the patch (in(face)
// false), as (from, to) corners.
template <class In> void border_of(const TriangleMesh& mesh, const std::vector<Index>& opposite,
                                   std::span<const Index> faces, In&& in,
                                   std::vector<std::pair<Index, Index>>& border) {
  border.clear();
  for (const Index f : faces) {
    const Triangle& t = mesh.triangles[f];
    for (Index k = 0; k < 3; ++k) {
      const Index o = opposite[3 * f + k];
      if (o == kInvalidIndex || !in(o / 3)) border.emplace_back(t[k], t[(k + 1) % 3]);
    }
  }
}

/// Whole patches smaller than this are left to the nodes' own.
constexpr std::size_t kMinWhole = 32;

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
                 const std::vector<Index>& whole, std::span<const Index> order)
    : mesh_(mesh), opposite_(opposite), order_(order), position_(mesh.face_count(), kInvalidIndex),
      runs_(order.size() + 1) {
  const Index n = static_cast<Index>(order.size());
  for (Index i = 0; i < n; ++i) position_[order[i]] = i;
  runs_[n].fill(n);
  for (Index i = n; i-- > 0;)
    for (int b = 0; b < 6; ++b) runs_[i][b] = (turns[order[i]] >> b) & 1u ? runs_[i + 1][b] : i;
  whole_.assign(n + 1, kInvalidIndex);
  whole_run_.assign(n + 1, n);
  for (Index i = 0; i < n; ++i) whole_[i] = whole[order[i]];
  for (Index i = n; i-- > 0;)
    whole_run_[i] = whole_[i] != kInvalidIndex && whole_[i + 1] == whole_[i] ? whole_run_[i + 1] : i + 1;
}

std::vector<Index> whole_patches(const TriangleMesh& mesh, const std::vector<Index>& opposite,
                                 const std::vector<std::uint8_t>& turns) {
  const Index faces = mesh.face_count();
  constexpr Index kNone = kInvalidIndex - 1; // reached, in no whole patch
  std::vector<Index> patch(faces, kInvalidIndex);
  std::vector<Index> members, stack;
  std::vector<std::pair<Index, Index>> border;
  Index patches = 0;
  // Across an edge whose faces turn by less than 60 degrees: a sheet, not around a crease onto a wall
  // over it (which the border's test would find, losing the whole sheet).
  auto gentle = [&](const Vec3& a, Index h) {
    const Vec3 b = triangle_normal(mesh, h);
    return a.dot(b) > 0.5 * a.norm() * b.norm();
  };
  // Seeds facing close to an axis first (within about 25 degrees), so that a sheet grows from its
  // flat middle, not from a steep edge along another axis; then any.
  for (int pass = 0; pass < 2; ++pass)
    for (Index seed = 0; seed < faces; ++seed) {
      if (patch[seed] != kInvalidIndex || turns[seed] == 0) continue;
      const Vec3 n = triangle_normal(mesh, seed);
      int axis = 0;
      for (int k = 1; k < 3; ++k)
        if (std::abs(n[k]) > std::abs(n[axis])) axis = k;
      if (pass == 0 && !(std::abs(n[axis]) >= 0.9 * n.norm())) continue;
      int bit = 2 * axis + (n[axis] > 0.0 ? 0 : 1);
      if (!((turns[seed] >> bit) & 1u)) bit = std::countr_zero(static_cast<unsigned>(turns[seed]));
      const Index id = patches;
      members.clear();
      stack.assign(1, seed);
      patch[seed] = id;
      while (!stack.empty()) {
        const Index g = stack.back();
        stack.pop_back();
        members.push_back(g);
        const Vec3 normal = triangle_normal(mesh, g);
        for (Index k = 0; k < 3; ++k) {
          const Index o = opposite[3 * g + k];
          if (o == kInvalidIndex) continue;
          const Index h = o / 3;
          if (patch[h] == kInvalidIndex && ((turns[h] >> bit) & 1u) && gentle(normal, h)) {
            patch[h] = id;
            stack.push_back(h);
          }
        }
      }
      border_of(
          mesh, opposite, members, [&](Index h) { return patch[h] == id; }, border);
      const bool whole = members.size() >= kMinWhole && one_sheet(mesh, border, bit);
      for (const Index g : members) patch[g] = whole ? id : kNone;
      if (whole) ++patches;
    }
  for (Index& p : patch)
    if (p == kNone) p = kInvalidIndex;
  return patch;
}

bool Patches::apart(Index a_begin, Index a_end, Index b_begin, Index b_end) const {
  const Index p = whole_[a_begin];
  if (p != kInvalidIndex && whole_run_[a_begin] >= a_end && whole_[b_begin] == p && whole_run_[b_begin] >= b_end)
    return true;
  return a_begin == b_begin && a_end == b_end && a_end - a_begin <= kMaxLocal && embedded(a_begin, a_end);
}

bool Patches::embedded(Index begin, Index end) const {
  int bit = 0;
  while (bit < 6 && runs_[begin][bit] < end) ++bit;
  if (bit == 6) return false;

  std::vector<std::pair<Index, Index>> border;
  border_of(
      mesh_, opposite_, order_.subspan(begin, end - begin),
      [&](Index f) { return position_[f] >= begin && position_[f] < end; }, border);
  return one_sheet(mesh_, border, bit);
}

} // namespace st::validate_detail
