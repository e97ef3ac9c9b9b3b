#pragma once
// Exact references for the triangle-intersection tests, on small integer coordinates (see
// test_triangle_intersection.cpp): hulls meeting by Caratheodory, faces sharing vertices by basic
// solutions, and random pairs of many degenerate kinds.

#include "st/core/mesh.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

namespace exact_reference {

using st::Vec3;
using I3 = std::array<std::int64_t, 3>;
using ITri = std::array<I3, 3>;
__extension__ typedef __int128 I128;

// ---- exact integer references ---------------------------------------------------------------------

inline I3 sub(const I3& a, const I3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline I3 cross(const I3& a, const I3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline std::int64_t dot(const I3& a, const I3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline std::int64_t det3(const I3& a, const I3& b, const I3& c) { return dot(a, cross(b, c)); }
inline bool is_zero(const I3& a) { return a[0] == 0 && a[1] == 0 && a[2] == 0; }
inline int sgn(std::int64_t x) { return (x > 0) - (x < 0); }

// Is the origin in the convex hull of the points? Caratheodory: then it is in the hull of at most four
// affinely independent ones, each case an exact integer test.
inline bool origin_in_hull(const std::vector<I3>& d) {
  const std::size_t n = d.size();
  for (int k = 0; k < 3; ++k) { // all on one side of a coordinate plane: the box excludes the origin
    bool all_positive = true, all_negative = true;
    for (const I3& p : d) {
      all_positive = all_positive && p[k] > 0;
      all_negative = all_negative && p[k] < 0;
    }
    if (all_positive || all_negative) return false;
  }
  for (std::size_t i = 0; i < n; ++i)
    if (is_zero(d[i])) return true;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j)
      if (d[i] != d[j] && is_zero(cross(d[i], d[j])) && dot(d[i], d[j]) <= 0) return true;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j)
      for (std::size_t k = j + 1; k < n; ++k) {
        const I3 &p = d[i], &q = d[j], &r = d[k];
        const I3 nrm = cross(sub(q, p), sub(r, p));
        if (is_zero(nrm) || dot(nrm, p) != 0) continue;
        if (dot(cross(p, q), nrm) >= 0 && dot(cross(q, r), nrm) >= 0 && dot(cross(r, p), nrm) >= 0) return true;
      }
  const I3 o = {0, 0, 0};
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j)
      for (std::size_t k = j + 1; k < n; ++k)
        for (std::size_t l = k + 1; l < n; ++l) {
          const I3 &p = d[i], &q = d[j], &r = d[k], &s = d[l];
          const int v = sgn(det3(sub(q, p), sub(r, p), sub(s, p)));
          if (v == 0) continue;
          const std::int64_t w[4] = {det3(sub(q, o), sub(r, o), sub(s, o)), det3(sub(o, p), sub(r, p), sub(s, p)),
                                     det3(sub(q, p), sub(o, p), sub(s, p)), det3(sub(q, p), sub(r, p), sub(o, p))};
          if (sgn(w[0]) * v >= 0 && sgn(w[1]) * v >= 0 && sgn(w[2]) * v >= 0 && sgn(w[3]) * v >= 0) return true;
        }
  return false;
}

// Do the closed hulls of the point sets a and b meet?
inline bool reference_hulls_meet(const std::vector<I3>& a, const std::vector<I3>& b) {
  std::vector<I3> d;
  for (const I3& p : a)
    for (const I3& q : b) d.push_back(sub(p, q));
  return origin_in_hull(d);
}

// Determinant of the n x n matrix m (Bareiss, exact).
inline I128 determinant(std::array<std::array<I128, 5>, 5> m, int n) {
  I128 sign = 1, previous = 1;
  for (int k = 0; k + 1 < n; ++k) {
    if (m[k][k] == 0) {
      int r = k + 1;
      while (r < n && m[r][k] == 0) ++r;
      if (r == n) return 0;
      std::swap(m[k], m[r]);
      sign = -sign;
    }
    for (int i = k + 1; i < n; ++i)
      for (int j = k + 1; j < n; ++j) m[i][j] = (m[i][j] * m[k][k] - m[i][k] * m[k][j]) / previous;
    previous = m[k][k];
  }
  return sign * m[n - 1][n - 1];
}

// Is the rational point n / den (den > 0) in the hull of the 0, 1 or 2 points `hull`?
inline bool rational_in_hull(const std::array<I128, 3>& n, I128 den, const std::vector<I3>& hull) {
  if (hull.empty()) return false;
  const I3& u = hull[0];
  const std::array<I128, 3> x = {n[0] - den * u[0], n[1] - den * u[1], n[2] - den * u[2]};
  const I3 e = hull.size() == 2 ? sub(hull[1], u) : I3{0, 0, 0};
  if (is_zero(e)) return x[0] == 0 && x[1] == 0 && x[2] == 0;
  const std::array<I128, 3> c = {x[1] * e[2] - x[2] * e[1], x[2] * e[0] - x[0] * e[2], x[0] * e[1] - x[1] * e[0]};
  if (c[0] != 0 || c[1] != 0 || c[2] != 0) return false;
  const I128 t = x[0] * e[0] + x[1] * e[1] + x[2] * e[2];
  return t >= 0 && t <= den * dot(e, e);
}

// Does triangle a meet triangle b in a point outside the hull of `shared` (with `shared` empty: do
// they meet at all)? Enumerates the basic feasible solutions of the barycentric system.
inline bool reference_meet_beyond(const ITri& a, const ITri& b, const std::vector<I3>& shared) {
  I128 m[5][6];
  const I128 rhs[5] = {0, 0, 0, 1, 1};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) {
      m[k][i] = a[i][k];
      m[k][3 + i] = -b[i][k];
    }
  for (int i = 0; i < 3; ++i) {
    m[3][i] = 1, m[4][i] = 0;
    m[3][3 + i] = 0, m[4][3 + i] = 1;
  }
  for (int cols = 1; cols < 64; ++cols) {
    if ((cols & 7) == 0 || (cols >> 3) == 0) continue;
    const int k = std::popcount(unsigned(cols));
    if (k > 5) continue;
    int col[5], kc = 0;
    for (int c = 0; c < 6; ++c)
      if (cols >> c & 1) col[kc++] = c;
    for (int rows = 0; rows < 32; ++rows) {
      if (std::popcount(unsigned(rows)) != k) continue;
      int row[5], kr = 0;
      for (int r = 0; r < 5; ++r)
        if (rows >> r & 1) row[kr++] = r;
      std::array<std::array<I128, 5>, 5> sq{};
      for (int i = 0; i < k; ++i)
        for (int j = 0; j < k; ++j) sq[i][j] = m[row[i]][col[j]];
      I128 den = determinant(sq, k);
      if (den == 0) continue;
      // The columns are independent: the only candidate solution is Cramer's on these rows.
      I128 num[5];
      for (int t = 0; t < k; ++t) {
        auto s2 = sq;
        for (int i = 0; i < k; ++i) s2[i][t] = rhs[row[i]];
        num[t] = determinant(s2, k);
      }
      bool solves = true;
      for (int r = 0; r < 5 && solves; ++r) {
        I128 lhs = 0;
        for (int t = 0; t < k; ++t) lhs += m[r][col[t]] * num[t];
        solves = lhs == rhs[r] * den;
      }
      if (den < 0) {
        den = -den;
        for (int t = 0; t < k; ++t) num[t] = -num[t];
      }
      bool feasible = solves;
      for (int t = 0; t < k && feasible; ++t) feasible = num[t] >= 0;
      if (feasible) {
        std::array<I128, 3> point = {0, 0, 0};
        for (int t = 0; t < k; ++t)
          if (col[t] < 3)
            for (int c = 0; c < 3; ++c) point[c] += num[t] * a[col[t]][c];
        if (!rational_in_hull(point, den, shared)) return true;
      }
      break;
    }
  }
  return false;
}

// ---- random configurations ------------------------------------------------------------------------

struct Randomizer {
  std::mt19937_64 rng;
  explicit Randomizer(std::uint64_t seed) : rng(seed) {}
  int uniform(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); }
  I3 point(int lo, int hi) { return {uniform(lo, hi), uniform(lo, hi), uniform(lo, hi)}; }
};

// An exact invertible affine map applied to integer points: integer shear, axis permutation and
// signs, then per axis a power-of-two scale and an offset (both exact on these small integers).
// Intersections are invariant under it, and it moves the predicates into their exact paths.
struct ExactMap {
  int shear[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  int perm[3] = {0, 1, 2};
  int sign[3] = {1, 1, 1};
  int exponent[3] = {0, 0, 0};
  double offset[3] = {0, 0, 0};

  static ExactMap random(Randomizer& r) {
    ExactMap m;
    if (r.uniform(0, 1)) { // unit lower-triangular shear: invertible over the integers
      m.shear[1][0] = r.uniform(-2, 2);
      m.shear[2][0] = r.uniform(-2, 2);
      m.shear[2][1] = r.uniform(-2, 2);
    }
    std::shuffle(m.perm, m.perm + 3, r.rng);
    const double offsets[] = {0.0, 0x1p26, 0x1p40, 0x1p52 - 64};
    const int exponents[] = {0, 0, -3, 20, -600, 500};
    for (int k = 0; k < 3; ++k) {
      m.sign[k] = r.uniform(0, 1) ? 1 : -1;
      m.exponent[k] = exponents[r.uniform(0, 5)];
      m.offset[k] = offsets[r.uniform(0, 3)];
    }
    return m;
  }

  I3 shear_point(const I3& p) const {
    I3 q;
    for (int i = 0; i < 3; ++i) q[i] = shear[i][0] * p[0] + shear[i][1] * p[1] + shear[i][2] * p[2];
    return q;
  }
  Vec3 operator()(const I3& p) const {
    const I3 q = shear_point(p);
    Vec3 v;
    for (int k = 0; k < 3; ++k) v[k] = std::ldexp(offset[k] + sign[k] * static_cast<double>(q[perm[k]]), exponent[k]);
    return v;
  }
};

inline bool collinear_int(const ITri& t) { return is_zero(cross(sub(t[1], t[0]), sub(t[2], t[0]))); }

// Random triangle pairs of many kinds, most of them degenerate in some way.
inline std::pair<ITri, ITri> random_pair(Randomizer& r, int mode) {
  ITri a, b;
  auto shared_pool = [&](const ITri& t, int scale) {
    // Vertices, edge midpoints and random points of a triangle with coordinates multiplied by 2.
    std::vector<I3> pool;
    for (int i = 0; i < 3; ++i) {
      pool.push_back(t[i]);
      pool.push_back(
          {(t[i][0] + t[(i + 1) % 3][0]) / 2, (t[i][1] + t[(i + 1) % 3][1]) / 2, (t[i][2] + t[(i + 1) % 3][2]) / 2});
    }
    for (int i = 0; i < 3; ++i) pool.push_back(r.point(0, scale));
    return pool;
  };
  switch (mode) {
  case 0: // anything in a small cube: many coplanar, collinear, shared points
    for (auto& p : a) p = r.point(0, 3);
    for (auto& p : b) p = r.point(0, 3);
    break;
  case 1: // coplanar, on z = 0
    for (auto& p : a) p = {r.uniform(0, 5), r.uniform(0, 5), 0};
    for (auto& p : b) p = {r.uniform(0, 5), r.uniform(0, 5), 0};
    break;
  case 2: { // b built from a's vertices, edge midpoints and random points
    for (auto& p : a) p = {2 * r.uniform(0, 3), 2 * r.uniform(0, 3), 2 * r.uniform(0, 3)};
    const auto pool = shared_pool(a, 6);
    for (auto& p : b) p = pool[r.uniform(0, int(pool.size()) - 1)];
    break;
  }
  case 3: { // the same in the plane z = 0
    for (auto& p : a) p = {2 * r.uniform(0, 3), 2 * r.uniform(0, 3), 0};
    auto pool = shared_pool(a, 6);
    for (auto& p : pool) p[2] = 0;
    for (auto& p : b) p = pool[r.uniform(0, int(pool.size()) - 1)];
    break;
  }
  case 4: { // a degenerate triangle (segment or point) against anything
    const I3 o = r.point(0, 4), d = r.point(-1, 1);
    for (auto& p : a) {
      const int t = r.uniform(-2, 2);
      p = {o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]};
    }
    for (auto& p : b) p = r.point(-1, 5);
    if (r.uniform(0, 3) == 0) { // both degenerate
      const I3 o2 = r.point(0, 4), d2 = r.point(-1, 1);
      for (auto& p : b) {
        const int t = r.uniform(-2, 2);
        p = {o2[0] + t * d2[0], o2[1] + t * d2[1], o2[2] + t * d2[2]};
      }
    }
    break;
  }
  default: // general position-ish in a larger box
    for (auto& p : a) p = r.point(-8, 8);
    for (auto& p : b) p = r.point(-8, 8);
    break;
  }
  if (r.uniform(0, 1)) std::swap(a, b);
  return {a, b};
}

} // namespace exact_reference
