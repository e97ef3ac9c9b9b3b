#include "st/boolean/triangle_intersection.h"

#include "st/core/predicates.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <utility>

// Every decision below is a sign of orient3d / orient2d or a comparison of input coordinates, so the
// results are exact. Throughout, "projection k" drops coordinate k and keeps ((k+1)%3, (k+2)%3); its
// orient2d equals the sign of the k-th component of the exact normal (b - a) x (c - a). A projection is
// only used on points lying exactly in a plane on which it is one-to-one, where it preserves every
// incidence, so the 2D answer is the 3D answer.

namespace st {
namespace {

struct Point2 {
  double xy[2];
};

inline Point2 project(int k, const Vec3& p) {
  const double* d = p.data();
  return {{d[(k + 1) % 3], d[(k + 2) % 3]}};
}

inline int orient2(const Point2& a, const Point2& b, const Point2& c) { return orient2d(a.xy, b.xy, c.xy); }

inline int orient2_dropping(int k, const Vec3& a, const Vec3& b, const Vec3& c) {
  return orient2(project(k, a), project(k, b), project(k, c));
}

inline bool same_point(const Vec3& a, const Vec3& b) { return a[0] == b[0] && a[1] == b[1] && a[2] == b[2]; }

// True when the signs contain both a positive and a negative one.
inline bool mixed(int s0, int s1, int s2) { return (s0 < 0 || s1 < 0 || s2 < 0) && (s0 > 0 || s1 > 0 || s2 > 0); }

// The coordinate to drop so that the projection of triangle (a, b, c) is non-degenerate, or -1 when
// the three points are collinear (all three exact normal components vanish). The axis of the largest
// approximate normal component is tried first, so one exact orient2d usually decides.
int projection_axis(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double* pa = a.data();
  const double* pb = b.data();
  const double* pc = c.data();
  const double ux = pb[0] - pa[0], uy = pb[1] - pa[1], uz = pb[2] - pa[2];
  const double vx = pc[0] - pa[0], vy = pc[1] - pa[1], vz = pc[2] - pa[2];
  const double n[3] = {std::fabs(uy * vz - uz * vy), std::fabs(uz * vx - ux * vz), std::fabs(ux * vy - uy * vx)};
  int order[3] = {0, 1, 2};
  if (n[order[1]] > n[order[0]]) std::swap(order[0], order[1]);
  if (n[order[2]] > n[order[0]]) std::swap(order[0], order[2]);
  if (n[order[2]] > n[order[1]]) std::swap(order[1], order[2]);
  for (int k : order)
    if (orient2_dropping(k, a, b, c) != 0) return k;
  return -1;
}

inline bool collinear(const Vec3& a, const Vec3& b, const Vec3& c) { return projection_axis(a, b, c) < 0; }

inline bool lex_less(const Vec3& p, const Vec3& q) {
  for (int k = 0; k < 3; ++k)
    if (p[k] != q[k]) return p[k] < q[k];
  return false;
}

// The end points of the segment that three collinear points span. Along a line every coordinate is
// monotone, so the lexicographic order is the order along the line.
std::pair<const Vec3*, const Vec3*> span_of_collinear(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3* lo = &a;
  const Vec3* hi = &a;
  for (const Vec3* p : {&b, &c}) {
    if (lex_less(*p, *lo)) lo = p;
    if (lex_less(*hi, *p)) hi = p;
  }
  return {lo, hi};
}

// Is x inside the axis-aligned box of p and q (a necessary condition for x on [p, q])?
inline bool in_box(const Vec3& x, const Vec3& p, const Vec3& q) {
  for (int k = 0; k < 3; ++k)
    if (x[k] < std::min(p[k], q[k]) || x[k] > std::max(p[k], q[k])) return false;
  return true;
}

inline bool boxes_overlap(std::initializer_list<const Vec3*> a, std::initializer_list<const Vec3*> b) {
  for (int k = 0; k < 3; ++k) {
    double amin = HUGE_VAL, amax = -HUGE_VAL, bmin = HUGE_VAL, bmax = -HUGE_VAL;
    for (const Vec3* p : a) {
      amin = std::min(amin, (*p)[k]);
      amax = std::max(amax, (*p)[k]);
    }
    for (const Vec3* p : b) {
      bmin = std::min(bmin, (*p)[k]);
      bmax = std::max(bmax, (*p)[k]);
    }
    if (amax < bmin || bmax < amin) return false;
  }
  return true;
}

// ---- 2D, on exactly coplanar points ---------------------------------------------------------------

// Closed point-in-triangle for a non-degenerate triangle: x is inside or on the boundary exactly when
// it is on no edge's outer side, i.e. the three edge orientations are not of mixed sign.
inline bool point_in_triangle_2d(const Point2& x, const Point2& a, const Point2& b, const Point2& c) {
  return !mixed(orient2(a, b, x), orient2(b, c, x), orient2(c, a, x));
}

// Closed segments [p, q] and [r, s]; either may be a point.
bool segments_intersect_2d(const Point2& p, const Point2& q, const Point2& r, const Point2& s) {
  const int d1 = orient2(p, q, r), d2 = orient2(p, q, s);
  if (d1 * d2 > 0) return false;
  const int d3 = orient2(r, s, p), d4 = orient2(r, s, q);
  if (d3 * d4 > 0) return false;
  // Not all on one line: both segments are proper, each line separates or touches the other segment
  // and the lines are not parallel, so they meet in one point that lies on both segments.
  if (d1 != 0 || d2 != 0 || d3 != 0 || d4 != 0) return true;
  // All four points on one line: compare along a coordinate that is not constant on it.
  const int k = (p.xy[0] != q.xy[0] || p.xy[0] != r.xy[0] || p.xy[0] != s.xy[0]) ? 0 : 1;
  const double lo = std::max(std::min(p.xy[k], q.xy[k]), std::min(r.xy[k], s.xy[k]));
  const double hi = std::min(std::max(p.xy[k], q.xy[k]), std::max(r.xy[k], s.xy[k]));
  return lo <= hi;
}

// Segment [p, q] and non-degenerate triangle (a, b, c), all exactly in one plane on which projection
// k is one-to-one.
bool coplanar_segment_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c, int k) {
  const Point2 p2 = project(k, p), q2 = project(k, q);
  const Point2 a2 = project(k, a), b2 = project(k, b), c2 = project(k, c);
  return point_in_triangle_2d(p2, a2, b2, c2) || point_in_triangle_2d(q2, a2, b2, c2) ||
         segments_intersect_2d(p2, q2, a2, b2) || segments_intersect_2d(p2, q2, b2, c2) ||
         segments_intersect_2d(p2, q2, c2, a2);
}

// Point x exactly in the plane of the non-degenerate triangle (a, b, c), projection k one-to-one there.
inline bool coplanar_point_in_triangle(const Vec3& x, const Vec3& a, const Vec3& b, const Vec3& c, int k) {
  return point_in_triangle_2d(project(k, x), project(k, a), project(k, b), project(k, c));
}

// Two non-degenerate triangles in one plane, projection k one-to-one on it. They intersect exactly when
// a vertex of one lies in the other or two edges cross properly: any other contact of the boundaries
// puts a vertex on an edge, which the vertex tests see.
bool coplanar_triangles_intersect(const Vec3* const a[3], const Vec3* const b[3], int k) {
  Point2 pa[3], pb[3];
  for (int i = 0; i < 3; ++i) {
    pa[i] = project(k, *a[i]);
    pb[i] = project(k, *b[i]);
  }
  int side_of_a[3][3]; // [edge i of a][vertex j of b]
  int side_of_b[3][3]; // [edge j of b][vertex i of a]
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      side_of_a[i][j] = orient2(pa[i], pa[(i + 1) % 3], pb[j]);
      side_of_b[i][j] = orient2(pb[i], pb[(i + 1) % 3], pa[j]);
    }
  for (int j = 0; j < 3; ++j)
    if (!mixed(side_of_a[0][j], side_of_a[1][j], side_of_a[2][j])) return true;
  for (int i = 0; i < 3; ++i)
    if (!mixed(side_of_b[0][i], side_of_b[1][i], side_of_b[2][i])) return true;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (side_of_a[i][j] * side_of_a[i][(j + 1) % 3] < 0 && side_of_b[j][i] * side_of_b[j][(i + 1) % 3] < 0)
        return true;
  return false;
}

// ---- 3D -----------------------------------------------------------------------------------------

// Closed segment [p, q] contains x (p == q allowed).
bool point_on_segment(const Vec3& x, const Vec3& p, const Vec3& q) {
  if (!in_box(x, p, q)) return false;
  // Inside the box of [p, q], a point of the line pq is on the segment; a point box is the point.
  return same_point(p, q) || collinear(p, q, x);
}

// Closed segments [p, q] and [r, s] in space; either may be a point.
bool segments_intersect_3d(const Vec3& p, const Vec3& q, const Vec3& r, const Vec3& s) {
  if (!boxes_overlap({&p, &q}, {&r, &s})) return false;
  if (same_point(p, q)) return point_on_segment(p, r, s);
  if (same_point(r, s)) return point_on_segment(r, p, q);
  if (orient3d(p, q, r, s) != 0) return false;
  int k = projection_axis(p, q, r);
  if (k < 0) k = projection_axis(p, q, s);
  // All four on the line pq: the overlapping boxes mean overlapping intervals on that line.
  if (k < 0) return true;
  return segments_intersect_2d(project(k, p), project(k, q), project(k, r), project(k, s));
}

// Closed triangle (a, b, c), possibly degenerate, contains x.
bool point_in_triangle_3d(const Vec3& x, const Vec3& a, const Vec3& b, const Vec3& c) {
  if (!boxes_overlap({&x}, {&a, &b, &c})) return false;
  const int k = projection_axis(a, b, c);
  if (k < 0) {
    const auto [lo, hi] = span_of_collinear(a, b, c);
    return point_on_segment(x, *lo, *hi);
  }
  return orient3d(a, b, c, x) == 0 && coplanar_point_in_triangle(x, a, b, c, k);
}

// Segment [p, q] and non-degenerate triangle (a, b, c) with projection axis k, given the sides
// sp = orient3d(a, b, c, p) and sq = orient3d(a, b, c, q).
bool segment_meets_proper_triangle(const Vec3& p, const Vec3& q, int sp, int sq, const Vec3& a, const Vec3& b,
                                   const Vec3& c, int k) {
  if (sp == sq && sp != 0) return false;
  if (sp == 0 && sq == 0) return coplanar_segment_triangle(p, q, a, b, c, k);
  if (sp == 0) return coplanar_point_in_triangle(p, a, b, c, k);
  if (sq == 0) return coplanar_point_in_triangle(q, a, b, c, k);
  // The segment crosses the plane in one point X. Seen along the line pq, the three edges turn the
  // same way around X exactly when X is inside; a zero means X is on that edge's line.
  return !mixed(orient3d(p, q, a, b), orient3d(p, q, b, c), orient3d(p, q, c, a));
}

bool segment_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  if (!boxes_overlap({&p, &q}, {&a, &b, &c})) return false;
  const int k = projection_axis(a, b, c);
  if (k < 0) {
    const auto [lo, hi] = span_of_collinear(a, b, c);
    return segments_intersect_3d(p, q, *lo, *hi);
  }
  return segment_meets_proper_triangle(p, q, orient3d(a, b, c, p), orient3d(a, b, c, q), a, b, c, k);
}

// Triangles of which one is degenerate, or which are coplanar (the plane tests gave all zeros).
bool triangles_intersect_special(const Vec3* const a[3], const Vec3* const b[3]) {
  const int ka = projection_axis(*a[0], *a[1], *a[2]);
  const int kb = projection_axis(*b[0], *b[1], *b[2]);
  if (ka >= 0 && kb >= 0) return coplanar_triangles_intersect(a, b, ka);
  if (ka < 0 && kb < 0) {
    const auto [alo, ahi] = span_of_collinear(*a[0], *a[1], *a[2]);
    const auto [blo, bhi] = span_of_collinear(*b[0], *b[1], *b[2]);
    return segments_intersect_3d(*alo, *ahi, *blo, *bhi);
  }
  if (ka < 0) {
    const auto [lo, hi] = span_of_collinear(*a[0], *a[1], *a[2]);
    return segment_triangle(*lo, *hi, *b[0], *b[1], *b[2]);
  }
  const auto [lo, hi] = span_of_collinear(*b[0], *b[1], *b[2]);
  return segment_triangle(*lo, *hi, *a[0], *a[1], *a[2]);
}

// Non-degenerate triangles in different planes, neither strictly on one side of the other's plane;
// side_a[i] = orient3d(b0, b1, b2, a_i), side_b[j] = orient3d(a0, a1, a2, b_j).
//
// The triangles meet on the line L common to both planes, each in a segment whose end points lie on
// its edges; the two segments overlap exactly when an end point of one lies in the other triangle.
// So they intersect exactly when some edge of one meets the other triangle.
bool crossing_triangles_intersect(const Vec3* const a[3], const Vec3* const b[3], const int side_a[3],
                                  const int side_b[3]) {
  // edge_edge[i][j] = orient3d(a_i, a_i+1, b_j, b_j+1) = orient3d(b_j, b_j+1, a_i, a_i+1) (an even
  // permutation), shared by the tests of edge i of a against b and of edge j of b against a.
  int edge_edge[3][3];
  bool known[3][3] = {};
  auto ee = [&](int i, int j) {
    if (!known[i][j]) {
      edge_edge[i][j] = orient3d(*a[i], *a[(i + 1) % 3], *b[j], *b[(j + 1) % 3]);
      known[i][j] = true;
    }
    return edge_edge[i][j];
  };
  int ka = -2, kb = -2; // projection axes, computed on first use
  auto axis_a = [&]() { return ka == -2 ? (ka = projection_axis(*a[0], *a[1], *a[2])) : ka; };
  auto axis_b = [&]() { return kb == -2 ? (kb = projection_axis(*b[0], *b[1], *b[2])) : kb; };

  for (int i = 0; i < 3; ++i) { // edges of a against triangle b
    const int s = side_a[i], t = side_a[(i + 1) % 3];
    const Vec3& p = *a[i];
    const Vec3& q = *a[(i + 1) % 3];
    if (s == t && s != 0) continue;
    if (s == 0 && t == 0) {
      if (coplanar_segment_triangle(p, q, *b[0], *b[1], *b[2], axis_b())) return true;
    } else if (s == 0 || t == 0) {
      if (coplanar_point_in_triangle(s == 0 ? p : q, *b[0], *b[1], *b[2], axis_b())) return true;
    } else if (!mixed(ee(i, 0), ee(i, 1), ee(i, 2))) {
      return true;
    }
  }
  for (int j = 0; j < 3; ++j) { // edges of b against triangle a
    const int s = side_b[j], t = side_b[(j + 1) % 3];
    const Vec3& p = *b[j];
    const Vec3& q = *b[(j + 1) % 3];
    if (s == t && s != 0) continue;
    if (s == 0 && t == 0) {
      if (coplanar_segment_triangle(p, q, *a[0], *a[1], *a[2], axis_a())) return true;
    } else if (s == 0 || t == 0) {
      if (coplanar_point_in_triangle(s == 0 ? p : q, *a[0], *a[1], *a[2], axis_a())) return true;
    } else if (!mixed(ee(0, j), ee(1, j), ee(2, j))) {
      return true;
    }
  }
  return false;
}

// ---- faces of one mesh that share vertices ------------------------------------------------------

// [v, s] and [v, t] share a point other than v: both leave v in the same direction along one line.
bool rays_overlap(const Vec3& v, const Vec3& s, const Vec3& t) {
  if (same_point(s, v) || same_point(t, v) || !collinear(v, s, t)) return false;
  int m = 0;
  while (s[m] == v[m]) ++m; // s != v; on the common line coordinate m is not constant
  return (s[m] > v[m]) == (t[m] > v[m]);
}

// [v, s] and [t1, t2] share a point other than v.
bool meets_segment_beyond(const Vec3& v, const Vec3& s, const Vec3& t1, const Vec3& t2) {
  if (same_point(s, v)) return false;
  if (point_on_segment(v, t1, t2)) return rays_overlap(v, s, t1) || rays_overlap(v, s, t2);
  return segments_intersect_3d(v, s, t1, t2);
}

// [v, s] and triangle (v, t1, t2) share a point other than v. With [v, s] meeting the triangle in
// [v, w], w != v: either w = s, so s is in the triangle, or w is where the segment leaves the
// triangle, which is a point of the edge [t1, t2] (leaving along edge v t1 happens at t1).
bool enters_triangle_beyond(const Vec3& v, const Vec3& s, const Vec3& t1, const Vec3& t2) {
  if (same_point(s, v)) return false;
  return point_in_triangle_3d(s, v, t1, t2) || meets_segment_beyond(v, s, t1, t2);
}

// [s0, s1] and triangle (v, t1, t2) share a point other than v.
bool meets_triangle_beyond(const Vec3& s0, const Vec3& s1, const Vec3& v, const Vec3& t1, const Vec3& t2) {
  if (!point_on_segment(v, s0, s1)) return segment_triangle(s0, s1, v, t1, t2);
  return enters_triangle_beyond(v, s0, t1, t2) || enters_triangle_beyond(v, s1, t1, t2);
}

// Faces (v, a1, a2) and (v, b1, b2) share a point other than v. Every point x != v of the first face
// lies on a segment [v, z] with z on [a1, a2], z != v, and likewise for the second face; for a common x
// both z lie on one ray from v and the nearer one is a common point on an opposite edge. So the faces
// share a point other than v exactly when an opposite edge meets the other face away from v.
bool vertex_neighbours_overlap(const Vec3& va, const Vec3& a1, const Vec3& a2, const Vec3& vb, const Vec3& b1,
                               const Vec3& b2) {
  return meets_triangle_beyond(a1, a2, vb, b1, b2) || meets_triangle_beyond(b1, b2, va, a1, a2);
}

// x, on the line uw, lies beyond w as seen from u (u != w).
bool beyond(const Vec3& u, const Vec3& w, const Vec3& x) {
  int m = 0;
  while (u[m] == w[m]) ++m;
  return w[m] > u[m] ? x[m] > w[m] : x[m] < w[m];
}

// Faces (u, w, a) and (u, w, b) share a point off the segment [u, w].
bool edge_neighbours_overlap(const Vec3& u, const Vec3& w, const Vec3& a, const Vec3& b) {
  if (same_point(u, w)) return rays_overlap(u, a, b); // the faces are the segments [u, a], [u, b]
  const int ka = projection_axis(u, w, a), kb = projection_axis(u, w, b);
  if (ka >= 0 && kb >= 0) {
    // A proper face meets the plane of the other, if different, only along the line uw, where both
    // are [u, w]. In a common plane they overlap beyond the edge when a and b are on the same side.
    if (orient3d(u, w, a, b) != 0) return false;
    return orient2_dropping(ka, u, w, a) == orient2_dropping(ka, u, w, b);
  }
  // A degenerate face lies on the line uw; a proper face meets that line only in [u, w]. Two
  // degenerate faces overlap beyond the edge when both reach past the same end.
  if (ka < 0 && kb < 0) return (beyond(u, w, a) && beyond(u, w, b)) || (beyond(w, u, a) && beyond(w, u, b));
  return false;
}

inline int find_index(const std::array<Index, 3>& t, Index v) {
  for (int i = 0; i < 3; ++i)
    if (t[i] == v) return i;
  return -1;
}

} // namespace

bool triangles_intersect(const Vec3& a0, const Vec3& a1, const Vec3& a2, const Vec3& b0, const Vec3& b1,
                         const Vec3& b2) {
  if (!boxes_overlap({&a0, &a1, &a2}, {&b0, &b1, &b2})) return false;
  const int side_b[3] = {orient3d(a0, a1, a2, b0), orient3d(a0, a1, a2, b1), orient3d(a0, a1, a2, b2)};
  if (side_b[0] == side_b[1] && side_b[1] == side_b[2] && side_b[0] != 0) return false;
  const int side_a[3] = {orient3d(b0, b1, b2, a0), orient3d(b0, b1, b2, a1), orient3d(b0, b1, b2, a2)};
  if (side_a[0] == side_a[1] && side_a[1] == side_a[2] && side_a[0] != 0) return false;
  const Vec3* const a[3] = {&a0, &a1, &a2};
  const Vec3* const b[3] = {&b0, &b1, &b2};
  // All zeros: the triangles are coplanar, or one is degenerate (a degenerate triangle gives zero
  // orientations for every point and is never counted as a plane).
  if ((side_b[0] == 0 && side_b[1] == 0 && side_b[2] == 0) || (side_a[0] == 0 && side_a[1] == 0 && side_a[2] == 0))
    return triangles_intersect_special(a, b);
  return crossing_triangles_intersect(a, b, side_a, side_b);
}

bool segment_intersects_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  return segment_triangle(p, q, a, b, c);
}

bool mesh_triangles_intersect(const std::array<Index, 3>& ta, const std::array<Vec3, 3>& pa,
                              const std::array<Index, 3>& tb, const std::array<Vec3, 3>& pb) {
  std::array<Index, 3> sa = ta, sb = tb;
  std::sort(sa.begin(), sa.end());
  std::sort(sb.begin(), sb.end());
  if (sa == sb) return true; // duplicate face

  Index shared[3];
  int shared_count = 0;
  for (int i = 0; i < 3; ++i)
    if (find_index(tb, ta[i]) >= 0 && std::find(shared, shared + shared_count, ta[i]) == shared + shared_count)
      shared[shared_count++] = ta[i];

  if (shared_count == 0) return triangles_intersect(pa[0], pa[1], pa[2], pb[0], pb[1], pb[2]);
  if (shared_count == 1) {
    const int ia = find_index(ta, shared[0]), ib = find_index(tb, shared[0]);
    return vertex_neighbours_overlap(pa[ia], pa[(ia + 1) % 3], pa[(ia + 2) % 3], pb[ib], pb[(ib + 1) % 3],
                                     pb[(ib + 2) % 3]);
  }
  if (shared_count == 2) {
    const int iu = find_index(ta, shared[0]), iw = find_index(ta, shared[1]);
    const int ib_u = find_index(tb, shared[0]), ib_w = find_index(tb, shared[1]);
    return edge_neighbours_overlap(pa[iu], pa[iw], pa[3 - iu - iw], pb[3 - ib_u - ib_w]);
  }
  return true; // three distinct shared indices make equal triples, handled above
}

} // namespace st
