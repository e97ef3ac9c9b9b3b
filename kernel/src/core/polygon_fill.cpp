#include "st/core/polygon_fill.h"

#include "st/core/predicates.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace st {

namespace {

/// The polygon being clipped: a circular doubly linked list of corners over the points.
class EarClipper {
public:
  explicit EarClipper(const std::vector<Point2>& points) : points_(points) {}

  /// Adds a loop as a new circular list; returns one of its nodes.
  int add_loop(const std::vector<Index>& loop) {
    const int first = static_cast<int>(nodes_.size());
    const int n = static_cast<int>(loop.size());
    for (int i = 0; i < n; ++i) nodes_.push_back({loop[i], first + (i + n - 1) % n, first + (i + 1) % n});
    return first;
  }

  /// Joins the hole through `hole` (a node of it) to the list through `outer` by a bridge; false when
  /// no corner of the outer list sees the hole's rightmost corner.
  bool bridge(int outer, int hole) {
    int m = hole;
    for (int i = nodes_[hole].next; i != hole; i = nodes_[i].next)
      if (x(i) > x(m) || (x(i) == x(m) && y(i) < y(m))) m = i;
    // The nearest edge the ray from m along +x meets, and the corner of it to bridge to.
    double best_x = std::numeric_limits<double>::infinity();
    int p = -1;
    int i = outer;
    do {
      const int j = nodes_[i].next;
      const double yi = y(i), yj = y(j), my = y(m);
      if ((yi <= my && yj >= my) || (yi >= my && yj <= my)) {
        double xi;
        if (yi == yj) xi = std::max(x(i), x(j));
        else xi = x(i) + (my - yi) * (x(j) - x(i)) / (yj - yi);
        if (xi >= x(m) && xi < best_x) {
          best_x = xi;
          if (yi == my && x(i) == xi) p = i;
          else if (yj == my && x(j) == xi) p = j;
          else p = x(i) > x(j) ? i : j;
        }
      }
      i = j;
    } while (i != outer);
    if (p < 0) return false;
    // A reflex corner inside the triangle (m, hit, p) would hide p: take the one nearest the ray.
    const Point2 hit{best_x, y(m)};
    const Point2& pm = pt(m);
    double best_angle = std::numeric_limits<double>::infinity();
    int chosen = p;
    i = outer;
    do {
      if (i != p && orient(i) <= 0 && x(i) >= x(m) && inside(pm, hit, pt(p), pt(i))) {
        const double angle = std::abs(std::atan2(y(i) - y(m), x(i) - x(m)));
        if (angle < best_angle || (angle == best_angle && x(i) < x(chosen))) {
          best_angle = angle;
          chosen = i;
        }
      }
      i = nodes_[i].next;
    } while (i != outer);
    // Among corners at the same point (earlier bridges repeat points), the one whose wedge holds m.
    i = outer;
    do {
      if (points_[nodes_[i].point] == points_[nodes_[chosen].point] && wedge_holds(i, pm)) {
        chosen = i;
        break;
      }
      i = nodes_[i].next;
    } while (i != outer);
    splice(chosen, m);
    return true;
  }

  /// Clips ears off the list through `start` until a triangle is left.
  bool clip(int start, std::vector<std::array<Index, 3>>& out) {
    int remaining = 1;
    for (int i = nodes_[start].next; i != start; i = nodes_[i].next) ++remaining;
    int e = start;
    int since_last = 0;
    bool allow_flat = false;
    while (remaining > 3) {
      if (is_ear(e, allow_flat)) {
        const Node& n = nodes_[e];
        // A corner of no area in the plane is still a face in space (a wall along the direction),
        // unless it turns back onto the same point (a bridge's two sides).
        if (nodes_[n.prev].point != nodes_[n.next].point)
          out.push_back({nodes_[n.prev].point, n.point, nodes_[n.next].point});
        nodes_[n.prev].next = n.next;
        nodes_[n.next].prev = n.prev;
        e = n.next;
        --remaining;
        since_last = 0;
        allow_flat = false;
        continue;
      }
      e = nodes_[e].next;
      if (++since_last > remaining) {
        if (allow_flat) return false;
        allow_flat = true;
        since_last = 0;
      }
    }
    if (orient(e) < 0) return false;
    if (nodes_[nodes_[e].prev].point != nodes_[nodes_[e].next].point)
      out.push_back({nodes_[nodes_[e].prev].point, nodes_[e].point, nodes_[nodes_[e].next].point});
    return true;
  }

private:
  struct Node {
    Index point;
    int prev, next;
  };

  [[nodiscard]] const Point2& pt(int i) const { return points_[nodes_[i].point]; }
  [[nodiscard]] double x(int i) const { return pt(i)[0]; }
  [[nodiscard]] double y(int i) const { return pt(i)[1]; }
  static int orient(const Point2& a, const Point2& b, const Point2& c) {
    return orient2d(a.data(), b.data(), c.data());
  }
  /// The turn at corner i: > 0 convex, < 0 reflex, 0 straight.
  [[nodiscard]] int orient(int i) const { return orient(pt(nodes_[i].prev), pt(i), pt(nodes_[i].next)); }
  /// Whether r lies in the closed triangle (a, b, c) (counter-clockwise or clockwise).
  static bool inside(const Point2& a, const Point2& b, const Point2& c, const Point2& r) {
    const int s1 = orient(a, b, r), s2 = orient(b, c, r), s3 = orient(c, a, r);
    return (s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0);
  }
  /// Whether q lies in the polygon's wedge at corner i (near i).
  [[nodiscard]] bool wedge_holds(int i, const Point2& q) const {
    const Point2 &a = pt(nodes_[i].prev), &b = pt(i), &c = pt(nodes_[i].next);
    if (orient(a, b, c) >= 0) return orient(a, b, q) >= 0 && orient(b, c, q) >= 0;
    return orient(a, b, q) >= 0 || orient(b, c, q) >= 0;
  }

  [[nodiscard]] bool is_ear(int e, bool allow_flat) const {
    const int turn = orient(e);
    if (turn < 0 || (turn == 0 && !allow_flat)) return false;
    if (turn == 0) return true; // a corner of no area: clipping it leaves the rest unchanged
    const int p = nodes_[e].prev, n = nodes_[e].next;
    const Point2 &a = pt(p), &b = pt(e), &c = pt(n);
    for (int i = nodes_[n].next; i != p; i = nodes_[i].next) {
      const Point2& r = pt(i);
      if (r == a || r == b || r == c) continue;
      if (orient(i) <= 0 && inside(a, b, c, r)) return false;
    }
    return true;
  }

  /// Bridge a -> m: a, m, (the hole around from m), m', a', (a's old next).
  void splice(int a, int m) {
    const int a2 = static_cast<int>(nodes_.size());
    const int m2 = a2 + 1;
    const int an = nodes_[a].next, mp = nodes_[m].prev;
    nodes_.push_back({nodes_[a].point, m2, an});
    nodes_.push_back({nodes_[m].point, mp, a2});
    nodes_[a].next = m;
    nodes_[m].prev = a;
    nodes_[an].prev = a2;
    nodes_[mp].next = m2;
  }

  const std::vector<Point2>& points_;
  std::vector<Node> nodes_;
};

} // namespace

double loop_area2(const std::vector<Point2>& points, const std::vector<Index>& loop) {
  double sum = 0.0;
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const Point2& a = points[loop[i]];
    const Point2& b = points[loop[(i + 1) % loop.size()]];
    sum += a[0] * b[1] - a[1] * b[0];
  }
  return sum;
}

std::optional<std::vector<std::array<Index, 3>>> fill_polygon(const std::vector<Point2>& points,
                                                              std::vector<std::vector<Index>> loops) {
  if (loops.empty() || loops[0].size() < 3) return std::nullopt;
  EarClipper clipper(points);
  const int outer = clipper.add_loop(loops[0]);
  // Holes from right to left, so that each bridge runs to the outer loop or to a hole already joined.
  std::vector<std::pair<double, std::size_t>> order;
  for (std::size_t k = 1; k < loops.size(); ++k) {
    if (loops[k].size() < 3) return std::nullopt;
    double right = -std::numeric_limits<double>::infinity();
    for (Index v : loops[k]) right = std::max(right, points[v][0]);
    order.emplace_back(-right, k);
  }
  std::sort(order.begin(), order.end());
  for (const auto& [key, k] : order)
    if (!clipper.bridge(outer, clipper.add_loop(loops[k]))) return std::nullopt;
  std::vector<std::array<Index, 3>> triangles;
  if (!clipper.clip(outer, triangles)) return std::nullopt;
  return triangles;
}

} // namespace st
