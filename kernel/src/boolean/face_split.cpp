#include "st/boolean/face_split.h"

#include "st/core/errors.h"
#include "st/core/predicates.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace st {

namespace {

struct Vertex {
  double xy[2];
  Index id;
  unsigned edges; // bit k: lies on the face's original edge k
};

// Triangle (v0, v1, v2), counter-clockwise; edge i runs from v[i] to v[i+1], n[i] is the triangle
// across it (-1 on the face's border) and fixed[i] marks borders and constraints (never flipped).
struct Tri {
  std::array<int, 3> v;
  std::array<int, 3> n;
  std::array<bool, 3> fixed;
};

class Triangulation {
public:
  explicit Triangulation(std::vector<Vertex> corners) : verts_(std::move(corners)) {
    tris_.push_back({{0, 1, 2}, {-1, -1, -1}, {true, true, true}});
  }

  int add_vertex(const Vertex& v) {
    verts_.push_back(v);
    return static_cast<int>(verts_.size()) - 1;
  }

  const std::vector<Tri>& triangles() const { return tris_; }
  const Vertex& vertex(int i) const { return verts_[i]; }

  // Puts vertex p on the border edge from a to b (both on p's original edge, p between them).
  void split_border(int a, int b, int p) {
    for (int t = 0; t < static_cast<int>(tris_.size()); ++t)
      for (int i = 0; i < 3; ++i)
        if (tris_[t].v[i] == a && tris_[t].v[(i + 1) % 3] == b && tris_[t].n[i] < 0) {
          const int c = tris_[t].v[(i + 2) % 3];
          if (orient2d(verts_[a].xy, verts_[p].xy, verts_[c].xy) <= 0 ||
              orient2d(verts_[p].xy, verts_[b].xy, verts_[c].xy) <= 0)
            throw GeometryError("face split: a border point lies too close to a corner or another point");
          split_edge(t, i, p);
          legalize_around(p);
          return;
        }
    throw GeometryError("face split: a border point has no border edge to go on");
  }

  // Inserts vertex p strictly inside the current triangulation.
  void insert_inside(int p) {
    const double* q = verts_[p].xy;
    for (int t = 0; t < static_cast<int>(tris_.size()); ++t) {
      const Tri& tri = tris_[t];
      int s[3];
      for (int i = 0; i < 3; ++i) s[i] = orient2d(verts_[tri.v[i]].xy, verts_[tri.v[(i + 1) % 3]].xy, q);
      if (s[0] < 0 || s[1] < 0 || s[2] < 0) continue;
      const int zeros = (s[0] == 0) + (s[1] == 0) + (s[2] == 0);
      if (zeros == 0) {
        split_inside(t, p);
      } else if (zeros == 1) {
        const int i = s[0] == 0 ? 0 : (s[1] == 0 ? 1 : 2);
        if (tri.n[i] < 0) throw GeometryError("face split: an inner point lies on the face's border");
        if (tri.fixed[i]) throw GeometryError("face split: a point lies on a constraint");
        split_edge(t, i, p);
      } else {
        throw GeometryError("face split: two points coincide");
      }
      legalize_around(p);
      return;
    }
    throw GeometryError("face split: an inner point lies outside the face");
  }

  // Makes the segment a-b an edge of the triangulation and fixes it.
  void insert_constraint(int a, int b, int depth = 0) {
    if (depth > 64) throw GeometryError("face split: constraints pass through each other");
    if (fix_edge(a, b)) return;
    // A vertex exactly on the open segment splits the constraint there.
    for (int v = 0; v < static_cast<int>(verts_.size()); ++v) {
      if (v == a || v == b || !used(v)) continue;
      if (orient2d(verts_[a].xy, verts_[b].xy, verts_[v].xy) == 0 && between(a, b, v)) {
        insert_constraint(a, v, depth + 1);
        insert_constraint(v, b, depth + 1);
        return;
      }
    }
    std::vector<std::pair<int, int>> crossing = crossing_edges(a, b);
    std::size_t guard = 0;
    const std::size_t limit = 64 * (crossing.size() + 4) * (crossing.size() + 4);
    while (!crossing.empty()) {
      if (++guard > limit) throw GeometryError("face split: constraint recovery does not converge");
      const auto [u, w] = crossing.front();
      crossing.erase(crossing.begin());
      int t = -1, i = -1;
      if (!find_edge(u, w, t, i)) throw GeometryError("face split: lost an edge during recovery");
      if (tris_[t].fixed[i]) throw GeometryError("face split: two constraints cross");
      if (!can_flip(t, i)) {
        crossing.emplace_back(u, w);
        continue;
      }
      const auto [c, d] = flip(t, i);
      if (properly_cross(a, b, c, d)) crossing.emplace_back(c, d);
    }
    if (!fix_edge(a, b)) throw GeometryError("face split: a constraint could not be recovered");
  }

  // Delaunay flips on every free edge (bounded number of passes: the flips are only for shape).
  void legalize_all() {
    for (int pass = 0; pass < 8; ++pass) {
      bool changed = false;
      for (int t = 0; t < static_cast<int>(tris_.size()); ++t)
        for (int i = 0; i < 3; ++i)
          if (should_flip(t, i)) {
            flip(t, i);
            changed = true;
          }
      if (!changed) break;
    }
  }

private:
  bool used(int v) const {
    for (const Tri& t : tris_)
      if (t.v[0] == v || t.v[1] == v || t.v[2] == v) return true;
    return false;
  }

  bool between(int a, int b, int v) const {
    double d = 0.0, s = 0.0;
    for (int k = 0; k < 2; ++k) {
      const double ab = verts_[b].xy[k] - verts_[a].xy[k];
      d += ab * (verts_[v].xy[k] - verts_[a].xy[k]);
      s += ab * ab;
    }
    return d > 0.0 && d < s;
  }

  bool find_edge(int a, int b, int& t, int& i) const {
    for (t = 0; t < static_cast<int>(tris_.size()); ++t)
      for (i = 0; i < 3; ++i)
        if (tris_[t].v[i] == a && tris_[t].v[(i + 1) % 3] == b) return true;
    return false;
  }

  bool fix_edge(int a, int b) {
    bool found = false;
    int t, i;
    if (find_edge(a, b, t, i)) {
      tris_[t].fixed[i] = true;
      found = true;
    }
    if (find_edge(b, a, t, i)) {
      tris_[t].fixed[i] = true;
      found = true;
    }
    return found;
  }

  bool properly_cross(int a, int b, int c, int d) const {
    const double *pa = verts_[a].xy, *pb = verts_[b].xy, *pc = verts_[c].xy, *pd = verts_[d].xy;
    return orient2d(pa, pb, pc) * orient2d(pa, pb, pd) < 0 && orient2d(pc, pd, pa) * orient2d(pc, pd, pb) < 0;
  }

  std::vector<std::pair<int, int>> crossing_edges(int a, int b) const {
    std::vector<std::pair<int, int>> out;
    for (const Tri& t : tris_)
      for (int i = 0; i < 3; ++i) {
        const int u = t.v[i], w = t.v[(i + 1) % 3];
        if (u < w && t.n[i] >= 0 && properly_cross(a, b, u, w)) out.emplace_back(u, w);
      }
    return out;
  }

  // The two triangles of edge i of t, as (a, b, c) and (b, a, d).
  bool can_flip(int t, int i) const {
    const Tri& T = tris_[t];
    if (T.n[i] < 0 || T.fixed[i]) return false;
    const int a = T.v[i], b = T.v[(i + 1) % 3], c = T.v[(i + 2) % 3];
    const Tri& U = tris_[T.n[i]];
    int j = 0;
    while (U.v[j] != b) ++j;
    const int d = U.v[(j + 2) % 3];
    // Never a triangle of three points of one original edge: it would be a sliver in 3D.
    if ((verts_[c].edges & verts_[d].edges & (verts_[a].edges | verts_[b].edges)) != 0) return false;
    return orient2d(verts_[a].xy, verts_[d].xy, verts_[c].xy) > 0 &&
           orient2d(verts_[b].xy, verts_[c].xy, verts_[d].xy) > 0;
  }

  bool should_flip(int t, int i) const {
    if (!can_flip(t, i)) return false;
    const Tri& T = tris_[t];
    const int a = T.v[i], b = T.v[(i + 1) % 3], c = T.v[(i + 2) % 3];
    const Tri& U = tris_[T.n[i]];
    int j = 0;
    while (U.v[j] != b) ++j;
    const int d = U.v[(j + 2) % 3];
    return incircle(a, b, c, d);
  }

  // True when d lies clearly inside the circle through the counter-clockwise a, b, c.
  bool incircle(int a, int b, int c, int d) const {
    const double* p[3] = {verts_[a].xy, verts_[b].xy, verts_[c].xy};
    const double* q = verts_[d].xy;
    double m[3][3];
    double scale = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double x = p[k][0] - q[0], y = p[k][1] - q[1];
      m[k][0] = x;
      m[k][1] = y;
      m[k][2] = x * x + y * y;
      scale = std::max(scale, m[k][2]);
    }
    const double det = m[0][0] * (m[1][1] * m[2][2] - m[2][1] * m[1][2]) -
                       m[1][0] * (m[0][1] * m[2][2] - m[2][1] * m[0][2]) +
                       m[2][0] * (m[0][1] * m[1][2] - m[1][1] * m[0][2]);
    return det > 1e-10 * scale * scale;
  }

  void set_neighbour(int t, int a, int b, int value) {
    if (t < 0) return;
    for (int i = 0; i < 3; ++i)
      if (tris_[t].v[i] == a && tris_[t].v[(i + 1) % 3] == b) {
        tris_[t].n[i] = value;
        return;
      }
  }

  // Flips edge i of t; returns the new edge (c, d).
  std::pair<int, int> flip(int t, int i) {
    const Tri T = tris_[t];
    const int u = T.n[i];
    const Tri U = tris_[u];
    const int a = T.v[i], b = T.v[(i + 1) % 3], c = T.v[(i + 2) % 3];
    int j = 0;
    while (U.v[j] != b) ++j;
    const int d = U.v[(j + 2) % 3];
    const int t_bc = T.n[(i + 1) % 3], t_ca = T.n[(i + 2) % 3];
    const bool f_bc = T.fixed[(i + 1) % 3], f_ca = T.fixed[(i + 2) % 3];
    const int u_ad = U.n[(j + 1) % 3], u_db = U.n[(j + 2) % 3];
    const bool f_ad = U.fixed[(j + 1) % 3], f_db = U.fixed[(j + 2) % 3];
    tris_[t] = {{a, d, c}, {u_ad, u, t_ca}, {f_ad, false, f_ca}};
    tris_[u] = {{b, c, d}, {t_bc, t, u_db}, {f_bc, false, f_db}};
    set_neighbour(u_ad, d, a, t);
    set_neighbour(t_bc, c, b, u);
    return {c, d};
  }

  void split_inside(int t, int p) {
    const Tri T = tris_[t];
    const int t1 = static_cast<int>(tris_.size()), t2 = t1 + 1;
    const int a = T.v[0], b = T.v[1], c = T.v[2];
    tris_[t] = {{a, b, p}, {T.n[0], t1, t2}, {T.fixed[0], false, false}};
    tris_.push_back({{b, c, p}, {T.n[1], t2, t}, {T.fixed[1], false, false}});
    tris_.push_back({{c, a, p}, {T.n[2], t, t1}, {T.fixed[2], false, false}});
    set_neighbour(T.n[1], c, b, t1);
    set_neighbour(T.n[2], a, c, t2);
  }

  void split_edge(int t, int i, int p) {
    const Tri T = tris_[t];
    const int a = T.v[i], b = T.v[(i + 1) % 3], c = T.v[(i + 2) % 3];
    const int n_bc = T.n[(i + 1) % 3], n_ca = T.n[(i + 2) % 3];
    const bool f_ab = T.fixed[i], f_bc = T.fixed[(i + 1) % 3], f_ca = T.fixed[(i + 2) % 3];
    const int u = T.n[i];
    const int t2 = static_cast<int>(tris_.size());
    if (u < 0) {
      tris_[t] = {{a, p, c}, {-1, t2, n_ca}, {f_ab, false, f_ca}};
      tris_.push_back({{p, b, c}, {-1, n_bc, t}, {f_ab, f_bc, false}});
      set_neighbour(n_bc, c, b, t2);
      return;
    }
    const Tri U = tris_[u];
    int j = 0;
    while (U.v[j] != b) ++j;
    const int d = U.v[(j + 2) % 3];
    const int n_ad = U.n[(j + 1) % 3], n_db = U.n[(j + 2) % 3];
    const bool f_ad = U.fixed[(j + 1) % 3], f_db = U.fixed[(j + 2) % 3];
    const int u2 = t2 + 1;
    tris_[t] = {{a, p, c}, {u2, t2, n_ca}, {f_ab, false, f_ca}};
    tris_.push_back({{p, b, c}, {u, n_bc, t}, {f_ab, f_bc, false}});
    tris_[u] = {{b, p, d}, {t2, u2, n_db}, {f_ab, false, f_db}};
    tris_.push_back({{p, a, d}, {t, n_ad, u}, {f_ab, f_ad, false}});
    set_neighbour(n_bc, c, b, t2);
    set_neighbour(n_ad, d, a, u2);
  }

  // Lawson flips around a new vertex.
  void legalize_around(int p) {
    std::vector<std::pair<int, int>> stack;
    for (const Tri& t : tris_)
      for (int i = 0; i < 3; ++i)
        if (t.v[(i + 2) % 3] == p) stack.emplace_back(t.v[i], t.v[(i + 1) % 3]);
    std::size_t guard = 0;
    while (!stack.empty() && ++guard < 10000) {
      const auto [a, b] = stack.back();
      stack.pop_back();
      int t, i;
      if (!find_edge(a, b, t, i) || !should_flip(t, i)) continue;
      const int c = tris_[t].v[(i + 2) % 3];
      const auto [x, d] = flip(t, i);
      (void)x;
      // The edges opposite the new vertex's wedge may now be illegal.
      const int other = c == p ? d : c;
      stack.emplace_back(a, other);
      stack.emplace_back(other, b);
    }
  }

  std::vector<Vertex> verts_;
  std::vector<Tri> tris_;
};

// The face with its cut corner replaced by the point that cuts it: corners (point, next, previous),
// the points on the two cut edges moved to the parts of those edges left (their parameters rescaled).
FaceSplitInput without_cut_corner(const FaceSplitInput& input) {
  const CutCorner& cut = input.cut;
  const int c = cut.corner, next = (c + 1) % 3, previous = (c + 2) % 3;
  if (!(cut.t_leaving > 0.0 && cut.t_leaving < 1.0 && cut.t_arriving > 0.0 && cut.t_arriving < 1.0))
    throw GeometryError("face split: a cut corner's point off its edges");
  FaceSplitInput out;
  out.corner_ids = {cut.id, input.corner_ids[next], input.corner_ids[previous]};
  out.corners[1] = input.corners[next];
  out.corners[2] = input.corners[previous];
  out.segments = input.segments;
  for (FacePoint p : input.points) {
    if (p.id == cut.id) {
      out.corners[0] = p.position;
      continue;
    }
    if (p.edge == c) {
      if (!(p.t > cut.t_leaving)) throw GeometryError("face split: a point in the cut corner");
      p.t = (p.t - cut.t_leaving) / (1.0 - cut.t_leaving);
      p.edge = 0;
    } else if (p.edge == next) {
      p.edge = 1;
    } else if (p.edge == previous) {
      if (!(p.t < cut.t_arriving)) throw GeometryError("face split: a point in the cut corner");
      p.t /= cut.t_arriving;
      p.edge = 2;
    }
    out.points.push_back(p);
  }
  if (out.points.size() == input.points.size()) throw GeometryError("face split: a cut corner's point missing");
  return out;
}

} // namespace

std::vector<Triangle> split_face(const FaceSplitInput& input) {
  if (input.cut.corner >= 0) return split_face(without_cut_corner(input));
  const Vec3& c0 = input.corners[0];
  const Vec3 e1 = input.corners[1] - c0, e2 = input.corners[2] - c0;
  const Vec3 normal = e1.cross(e2);
  if (!(normal.norm() > 0.0) || !(e1.norm() > 0.0)) throw GeometryError("face split: a degenerate face");
  const Vec3 x = e1.normalized();
  const Vec3 y = normal.normalized().cross(x);
  auto to2d = [&](const Vec3& p) {
    const Vec3 d = p - c0;
    return std::array<double, 2>{d.dot(x), d.dot(y)};
  };
  std::array<std::array<double, 2>, 3> c2d = {std::array<double, 2>{0.0, 0.0}, to2d(input.corners[1]),
                                              to2d(input.corners[2])};
  c2d[1][1] = 0.0;
  std::vector<Vertex> corners(3);
  for (int k = 0; k < 3; ++k)
    corners[k] = {{c2d[k][0], c2d[k][1]}, input.corner_ids[k], (1u << k) | (1u << ((k + 2) % 3))};
  if (orient2d(corners[0].xy, corners[1].xy, corners[2].xy) <= 0) throw GeometryError("face split: a degenerate face");
  Triangulation tri(corners);

  std::unordered_map<Index, int> local; // caller id -> vertex
  for (int k = 0; k < 3; ++k) local[input.corner_ids[k]] = k;

  // Border points, edge by edge in order along each edge.
  std::vector<const FacePoint*> border;
  for (const FacePoint& p : input.points)
    if (p.edge >= 0) border.push_back(&p);
  std::sort(border.begin(), border.end(), [](const FacePoint* a, const FacePoint* b) {
    return a->edge != b->edge ? a->edge < b->edge : a->t < b->t;
  });
  std::array<int, 3> last = {0, 1, 2};
  for (const FacePoint* p : border) {
    const int k = p->edge;
    if (k > 2 || !(p->t > 0.0 && p->t < 1.0)) throw GeometryError("face split: a border point off its edge");
    // The point as it is (rounded by the caller, perhaps an ulp off the edge's line), so that the
    // triangles are valid for the coordinates the result holds.
    const auto xy = to2d(p->position);
    const int id = tri.add_vertex({{xy[0], xy[1]}, p->id, 1u << k});
    if (!local.emplace(p->id, id).second) throw GeometryError("face split: a point given twice");
    tri.split_border(last[k], (k + 1) % 3, id);
    last[k] = id;
  }
  // Inner points.
  for (const FacePoint& p : input.points) {
    if (p.edge >= 0) continue;
    const auto xy = to2d(p.position);
    const int id = tri.add_vertex({{xy[0], xy[1]}, p.id, 0u});
    if (!local.emplace(p.id, id).second) throw GeometryError("face split: a point given twice");
    tri.insert_inside(id);
  }
  for (const auto& [a, b] : input.segments) {
    const auto ia = local.find(a), ib = local.find(b);
    if (ia == local.end() || ib == local.end()) throw GeometryError("face split: a segment to an unknown point");
    if (ia->second != ib->second) tri.insert_constraint(ia->second, ib->second);
  }
  tri.legalize_all();

  std::vector<Triangle> out;
  out.reserve(tri.triangles().size());
  for (const Tri& t : tri.triangles())
    out.push_back({tri.vertex(t.v[0]).id, tri.vertex(t.v[1]).id, tri.vertex(t.v[2]).id});
  return out;
}

} // namespace st
