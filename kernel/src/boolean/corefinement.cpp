// One corefinement of two closed meshes: intersection curve, faces split along it, pieces classified
// inside or outside the other operand, the result assembled.

#include "boolean/corefinement.h"

#include "detail/format.h"
#include "detail/morton.h"
#include "st/boolean/triangle_intersection.h"
#include "st/core/aabb_tree.h"
#include "st/core/errors.h"
#include "st/core/float32.h"
#include "st/core/predicates.h"
#include "st/core/topology.h"
#include "st/core/union_find.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <array>
#include <chrono>
#include <cmath>
#include <unordered_map>

namespace st::boolean_detail {

namespace {

class Corefinement {
public:
  Corefinement(const TriangleMesh& a, const BoundingBox& a_box, const TriangleMesh& b, const BooleanOptions& options,
               double short_edge)
      : a_(a), b_(b), a_box_(a_box), options_(options), na_(a.vertex_count()), nb_(b.vertex_count()),
        short_edge_(short_edge) {}

  BooleanResult run(BooleanOp op) {
    auto t = std::chrono::steady_clock::now();
    auto lap = [&](const char* what) {
      if (!debug_) return;
      const auto now = std::chrono::steady_clock::now();
      std::fprintf(stderr, "  %-10s %.4f s\n", what, std::chrono::duration<double>(now - t).count());
      t = now;
    };
    find_segments();
    merge_coincident_points();
    for (const SeamSegment& g : seam_) seam_edges_.push_back(edge_key(g.p, g.q)); // both sides use it
    std::sort(seam_edges_.begin(), seam_edges_.end());
    seam_edges_.erase(std::unique(seam_edges_.begin(), seam_edges_.end()), seam_edges_.end());
    lap("segments");
    split_faces();
    lap("split");
    for (int s = 0; s < 2; ++s) collect_pieces(s);
    for (int s = 0; s < 2; ++s) classify(s);
    if (op == BooleanOp::Union && !options_.seat.empty()) resolve_seat();
    lap("classify");
    BooleanResult result = assemble(op);
    lap("assemble");
    return result;
  }

private:
  const Vec3& position(Index id) const {
    if (id < na_) return a_.positions[id];
    if (id < na_ + nb_) return b_.positions[id - na_];
    return points_[id - na_ - nb_];
  }
  const TriangleMesh& mesh(int s) const { return s == 0 ? a_ : b_; }
  Index base(int s) const { return s == 0 ? 0 : na_; }
  std::array<Vec3, 3> corners(int s, Index f) const {
    const TriangleMesh& m = mesh(s);
    const Triangle& t = m.triangles[f];
    return {m.positions[t[0]], m.positions[t[1]], m.positions[t[2]]};
  }

  // The point where edge (u, v) of operand s (its own vertex ids) crosses face f of the other.
  Index crossing_point(int s, Index u, Index v, Index f, double& t_canonical) {
    const Index gu = base(s) + u, gv = base(s) + v;
    const PointKey key{edge_key(gu, gv), s == 0 ? f + a_.face_count() : f};
    const auto it = point_index_.find(key);
    if (it != point_index_.end()) {
      t_canonical = point_t_[it->second];
      return na_ + nb_ + it->second;
    }
    const Vec3& p = position(std::min(gu, gv));
    const Vec3& q = position(std::max(gu, gv));
    const auto c = corners(1 - s, f);
    const Vec3 n = (c[1] - c[0]).cross(c[2] - c[0]);
    const double dp = n.dot(p - c[0]), dq = n.dot(q - c[0]);
    const double t = dp / (dp - dq);
    if (!(t > 0.0 && t < 1.0)) throw Degenerate{"a crossing at an edge's end"};
    const Index id = static_cast<Index>(points_.size());
    Vec3 at = p + t * (q - p);
    // Rounded now, so that every face is triangulated with the coordinates the result will hold.
    if (options_.round_to_float) at = to_float32(at);
    points_.push_back(at);
    point_t_.push_back(t);
    point_on_second_edge_.push_back(s == 1);
    point_index_.emplace(key, id);
    t_canonical = t;
    return na_ + nb_ + id;
  }

  static void add_point(FaceWork& w, const FacePoint& p) {
    for (const FacePoint& q : w.points)
      if (q.id == p.id) return;
    w.points.push_back(p);
  }

  void find_segments() {
    // Oriented boxes around the smaller operand's components select the other's near faces tightly;
    // the larger operand's axis-aligned box is enough the other way (and costs no pass over it).
    auto whole_box = [](const BoundingBox& world) {
      OrientedBox box;
      box.world = world;
      box.axes.setIdentity();
      box.centre = box.world.center();
      box.half = 0.5 * box.world.size();
      return std::vector<OrientedBox>{box};
    };
    const bool a_smaller = a_.face_count() < b_.face_count();
    const std::vector<Index> near_a = faces_near(a_, a_smaller ? whole_box(bounding_box(b_)) : component_boxes(b_));
    const std::vector<Index> near_b = faces_near(b_, a_smaller ? component_boxes(a_) : whole_box(a_box_));
    // Each near face's plane, for the side tests of the other operand's corners.
    for (int s = 0; s < 2; ++s) {
      const std::vector<Index>& near = s == 0 ? near_a : near_b;
      near_slot_[s].assign(mesh(s).face_count(), kInvalidIndex);
      planes_[s].reserve(near.size());
      for (Index f : near) {
        near_slot_[s][f] = static_cast<Index>(planes_[s].size());
        const auto c = corners(s, f);
        planes_[s].emplace_back(c[0], c[1], c[2]);
      }
    }
    if (near_a.empty() || near_b.empty()) return;
    const AabbTree tree_a(a_, near_a);
    const AabbTree tree_b(b_, near_b);
    tree_a.for_each_overlapping_pair(tree_b, [&](Index fa, Index fb) { intersect_pair(fa, fb); });
  }

  void intersect_pair(Index fa, Index fb) {
    const auto pa = corners(0, fa), pb = corners(1, fb);
    const PlaneOrientation& plane_a = planes_[0][near_slot_[0][fa]];
    const PlaneOrientation& plane_b = planes_[1][near_slot_[1][fb]];
    int sa[3], sb[3];
    for (int i = 0; i < 3; ++i) sa[i] = plane_b(pa[i]); // orient3d(pb[0], pb[1], pb[2], pa[i])
    if ((sa[0] > 0 && sa[1] > 0 && sa[2] > 0) || (sa[0] < 0 && sa[1] < 0 && sa[2] < 0)) return;
    for (int i = 0; i < 3; ++i) sb[i] = plane_a(pb[i]);
    if ((sb[0] > 0 && sb[1] > 0 && sb[2] > 0) || (sb[0] < 0 && sb[1] < 0 && sb[2] < 0)) return;
    if (sa[0] == 0 || sa[1] == 0 || sa[2] == 0 || sb[0] == 0 || sb[1] == 0 || sb[2] == 0) {
      if (triangles_intersect(pa[0], pa[1], pa[2], pb[0], pb[1], pb[2]))
        throw Degenerate{"a vertex on the other operand's face plane, near " + detail::where(pa[0])};
      return;
    }
    struct Event {
      Index point;
      int side; // 0: an edge of fa crosses fb; 1: an edge of fb crosses fa
      int edge; // which edge of its face
      double t; // parameter along that edge, from its corner `edge`
    };
    std::array<Event, 4> events{};
    int count = 0;
    auto edges_through = [&](int s, const std::array<Vec3, 3>& p, const int* sp, const std::array<Vec3, 3>& q,
                             Index f_own, Index f_other) {
      const Triangle& tri = mesh(s).triangles[f_own];
      for (int i = 0; i < 3; ++i) {
        const int j = (i + 1) % 3;
        if (sp[i] == sp[j]) continue;
        int o[3];
        for (int k = 0; k < 3; ++k) o[k] = orient3d(p[i], p[j], q[k], q[(k + 1) % 3]);
        const bool pos = o[0] >= 0 && o[1] >= 0 && o[2] >= 0, neg = o[0] <= 0 && o[1] <= 0 && o[2] <= 0;
        if (!pos && !neg) continue;
        if (o[0] == 0 || o[1] == 0 || o[2] == 0)
          throw Degenerate{"an edge through the other operand's edge, near " + detail::where(p[i])};
        if (count == 4) throw Degenerate{"too many crossings"};
        double t_canonical = 0.0;
        const Index id = crossing_point(s, tri[i], tri[j], f_other, t_canonical);
        const bool forward = base(s) + tri[i] < base(s) + tri[j];
        events[count++] = {id, s, i, forward ? t_canonical : 1.0 - t_canonical};
      }
    };
    edges_through(0, pa, sa, pb, fa, fb);
    edges_through(1, pb, sb, pa, fb, fa);
    if (count == 0) return;
    if (count != 2) throw Degenerate{"an odd crossing near " + detail::where(pa[0])};
    FaceWork& wa = work_[0][fa];
    FaceWork& wb = work_[1][fb];
    for (int e = 0; e < 2; ++e) {
      const Event& ev = events[e];
      const Vec3& at = points_[ev.point - na_ - nb_];
      add_point(ev.side == 0 ? wa : wb, {ev.point, ev.edge, ev.t, at});
      add_point(ev.side == 0 ? wb : wa, {ev.point, -1, 0.0, at});
    }
    if (events[0].point == events[1].point) throw Degenerate{"a zero-length intersection"};
    wa.segments.emplace_back(events[0].point, events[1].point);
    wb.segments.emplace_back(events[0].point, events[1].point);
    seam_.push_back({events[0].point, events[1].point, fa, fb});
  }

  // Curve points are rounded to float32 as they are made. Where an edge of one operand passes within
  // an ulp or two of an edge of the other, the point where the first crosses a face and the point
  // where the second crosses a face of the first round to the same coordinates, or to neighbouring
  // ones on either side of the face's edge: they are one point of the curve, which passes there
  // through both edges. Such points (equal after rounding, or the ends of a curve segment a few ulp
  // long, one made by an edge of each operand) are merged, the point on a face's edge keeping its
  // place on that edge, and the segment dropped, so the faces are split as if the curve passed
  // through that point once. A point that rounds onto a vertex of a face it lies in is that vertex.
  void merge_coincident_points() {
    if (!options_.round_to_float || points_.empty()) return;
    struct Hash {
      std::size_t operator()(const Vec3& p) const {
        std::size_t h = 0;
        for (int k = 0; k < 3; ++k) h = h * 0x9E3779B97F4A7C15ull ^ std::hash<double>()(p[k]);
        return h;
      }
    };
    const Index offset = na_ + nb_;
    UnionFind clusters(static_cast<Index>(points_.size()));
    bool merged = false;
    std::unordered_map<Vec3, Index, Hash> first;
    for (Index i = 0; i < points_.size(); ++i) {
      const auto [it, inserted] = first.emplace(points_[i], i);
      if (!inserted) merged |= clusters.join_under(it->second, i);
    }
    const double close = short_edge_ / 32.0; // 8 float ulp of the coordinates (short_edge_ is 256)
    for (const SeamSegment& g : seam_) {
      const Index p = g.p - offset, q = g.q - offset;
      if (point_on_second_edge_[p] != point_on_second_edge_[q] &&
          (points_[p] - points_[q]).squaredNorm() <= close * close)
        merged |= clusters.join_under(p, q); // the cluster takes q's coordinates
    }
    // A point that rounds onto a corner of a face it lies in is that corner, a vertex of the operand:
    // the curve passes through the vertex.
    std::vector<Index> vertex(points_.size(), kInvalidIndex);
    for (int s = 0; s < 2; ++s)
      for (const auto& [f, w] : work_[s])
        for (const FacePoint& p : w.points) {
          const Index c = clusters.find(p.id - offset);
          for (Index corner : mesh(s).triangles[f]) {
            if (mesh(s).positions[corner] != points_[c] || vertex[c] == base(s) + corner) continue;
            if (vertex[c] != kInvalidIndex) throw Degenerate{"a curve point on two vertices"};
            vertex[c] = base(s) + corner;
            merged = true;
          }
        }
    if (!merged) return;
    auto map = [&](Index id) {
      if (id < offset) return id;
      const Index c = clusters.find(id - offset);
      return vertex[c] != kInvalidIndex ? vertex[c] : offset + c;
    };
    for (int s = 0; s < 2; ++s)
      for (auto& [f, w] : work_[s]) {
        std::vector<FacePoint> points;
        const Triangle& t = mesh(s).triangles[f];
        for (FacePoint p : w.points) {
          p.id = map(p.id);
          if (p.id >= base(s) && p.id < base(s) + mesh(s).vertex_count()) { // a vertex of this operand
            if (p.id != base(s) + t[0] && p.id != base(s) + t[1] && p.id != base(s) + t[2])
              throw Degenerate{"a curve point on a vertex off its face"};
            continue; // a corner of this face
          }
          p.position = position(p.id);
          const auto it = std::find_if(points.begin(), points.end(), [&](const FacePoint& q) { return q.id == p.id; });
          if (it == points.end()) {
            points.push_back(p);
          } else if (p.edge >= 0 && it->edge >= 0 && it->edge != p.edge) {
            // Crossings of two edges of the face, one point: the curve cuts off their common corner.
            if (w.cut.corner >= 0) throw Degenerate{"two corners of a face cut off"};
            const bool leaving = p.edge == (it->edge + 1) % 3; // p on the edge leaving the corner
            w.cut = {leaving ? p.edge : it->edge, p.id, leaving ? p.t : it->t, leaving ? it->t : p.t};
          } else if (p.edge >= 0) {
            *it = p;
          }
        }
        w.points = std::move(points);
        std::vector<std::pair<Index, Index>> segments;
        for (auto [u, v] : w.segments) {
          u = map(u);
          v = map(v);
          if (u == v) continue;
          const bool known = std::any_of(segments.begin(), segments.end(), [&](const auto& e) {
            return (e.first == u && e.second == v) || (e.first == v && e.second == u);
          });
          if (!known) segments.emplace_back(u, v);
        }
        w.segments = std::move(segments);
      }
    std::vector<SeamSegment> seam;
    for (SeamSegment g : seam_) {
      g.p = map(g.p);
      g.q = map(g.q);
      if (g.p != g.q) seam.push_back(g);
    }
    seam_ = std::move(seam);
  }

  void split_faces() {
    for (int s = 0; s < 2; ++s)
      for (auto& [f, w] : work_[s]) {
        FaceSplitInput in;
        in.corners = corners(s, f);
        const Triangle& t = mesh(s).triangles[f];
        in.corner_ids = {base(s) + t[0], base(s) + t[1], base(s) + t[2]};
        in.points = w.points;
        in.segments = w.segments;
        in.cut = w.cut;
        try {
          split_[s][f] = split_face(in);
        } catch (const GeometryError& e) {
          throw Degenerate{std::string(e.what()) + " near " + detail::where(in.corners[0])};
        }
      }
  }

  void collect_pieces(int s) {
    const TriangleMesh& m = mesh(s);
    std::vector<Piece>& pieces = pieces_[s];
    for (Index f = 0; f < m.face_count(); ++f) {
      if (near_slot_[s][f] == kInvalidIndex) continue;
      const auto it = split_[s].find(f);
      if (it == split_[s].end()) {
        const Triangle& t = m.triangles[f];
        pieces.push_back({{base(s) + t[0], base(s) + t[1], base(s) + t[2]}, f});
      } else {
        for (const Triangle& t : it->second) pieces.push_back({t, f});
      }
    }
  }

  void classify(int s) {
    std::vector<Piece>& pieces = pieces_[s];
    const std::size_t n = pieces.size();
    // Each piece's edges by key, a key's pieces in their order (a stable radix sort).
    std::vector<detail::MortonKeyed> edges;
    edges.reserve(3 * n);
    for (Index i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k) edges.push_back({edge_key(pieces[i].t[k], pieces[i].t[(k + 1) % 3]), i});
    detail::sort_by_code(edges);
    UnionFind uf(n);
    std::vector<std::uint8_t> touches_outside(n, 0);
    std::unordered_map<std::uint64_t, std::array<Index, 2>>& seam_pieces = seam_pieces_[s];
    auto next_seam = seam_edges_.begin(); // the curve's edges, met in the same order
    for (std::size_t i = 0; i < edges.size();) {
      std::size_t j = i;
      while (j < edges.size() && edges[j].code == edges[i].code) ++j;
      const std::size_t uses = j - i;
      while (next_seam != seam_edges_.end() && *next_seam < edges[i].code) ++next_seam;
      const bool seam = next_seam != seam_edges_.end() && *next_seam == edges[i].code;
      const auto piece = [&](std::size_t e) { return static_cast<Index>(edges[e].item); };
      if (uses == 1) {
        if (seam) throw Degenerate{"an intersection edge with one side"};
        touches_outside[piece(i)] = 1; // shared with a face far from the other operand
      } else if (uses == 2) {
        if (seam) seam_pieces[edges[i].code] = {piece(i), piece(i + 1)};
        else uf.join(piece(i), piece(i + 1));
      } else {
        throw Degenerate{"an edge with " + std::to_string(uses) + " faces after splitting"};
      }
      i = j;
    }
    std::vector<Index>& component = components_[s];
    component.assign(n, 0);
    std::vector<Index> root_to_component(n, kInvalidIndex); // numbered in the order pieces meet them
    Index components = 0;
    for (Index i = 0; i < n; ++i) {
      Index& c = root_to_component[uf.find(i)];
      if (c == kInvalidIndex) c = components++;
      component[i] = c;
    }
    std::vector<Verdict>& verdicts = verdicts_[s];
    verdicts.assign(components, {});
    const std::vector<std::uint8_t>& seat = options_.seat;
    for (Index i = 0; i < n; ++i) {
      Verdict& v = verdicts[component[i]];
      if (touches_outside[i]) v.exterior = true;
      if (s == 1 || seat.empty() || !seat[pieces[i].source]) v.all_seat = false;
    }
    // Side test at the intersection curve: the piece next to a segment lies in its face on one side
    // of the segment, so on one side of the other operand's face through it; its corner off the
    // segment tells which, exactly. Not when that corner is a curve point too (a piece between two
    // curve segments where the curve bends over an edge of the other operand): it lies on the
    // neighbouring face, and its side of this face's plane tells that edge's angle, not the piece's
    // side; the component's other pieces decide.
    for (const SeamSegment& g : seam_) {
      const auto it = seam_pieces.find(edge_key(g.p, g.q));
      if (it == seam_pieces.end()) throw Degenerate{"an intersection edge missing after splitting"};
      const auto other = corners(1 - s, s == 0 ? g.fb : g.fa);
      const Vec3 normal = (other[1] - other[0]).cross(other[2] - other[0]);
      const double length = normal.norm();
      for (Index piece : it->second) {
        const Triangle& t = pieces[piece].t;
        Verdict& v = verdicts[component[piece]];
        if (s == 1 && !seat.empty()) (seat[g.fa] ? v.on_seat_curve : v.on_other_curve) = true;
        const Index opposite = t[0] != g.p && t[0] != g.q ? t[0] : t[1] != g.p && t[1] != g.q ? t[1] : t[2];
        if (opposite >= na_ + nb_) continue;
        const Vec3& corner = position(opposite);
        const int side = orient3d(other[0], other[1], other[2], corner);
        if (side == 0) continue;
        const double margin = std::abs(normal.dot(corner - other[0])) / length;
        double& confidence = side > 0 ? v.inside_confidence : v.outside_confidence;
        confidence = std::max(confidence, margin);
      }
    }
    for (std::size_t c = 0; c < verdicts.size(); ++c) {
      Verdict& v = verdicts[c];
      const double in = v.inside_confidence, out = v.outside_confidence;
      if (in > 0.0 || out > 0.0) {
        if (std::min(in, out) > 1e-3 * std::max(in, out)) throw Degenerate{"a piece on both sides"};
        v.inside = in > out ? 1 : 0;
        if (v.exterior && v.inside) throw Degenerate{"a piece inside joined to faces far outside"};
      } else if (v.exterior) {
        v.inside = 0;
      }
    }
    std::vector<std::pair<Index, Index>> across; // the components on the two sides of each curve edge
    for (const SeamSegment& g : seam_) {
      const std::array<Index, 2>& two = seam_pieces.at(edge_key(g.p, g.q));
      across.emplace_back(component[two[0]], component[two[1]]);
    }
    decide_across_curve(across, verdicts);
    // Pieces no curve reaches and not joined to far faces (a part wholly inside or outside): rays.
    for (Index i = 0; i < n; ++i) {
      Verdict& v = verdicts[component[i]];
      if (v.inside >= 0) continue;
      const Triangle& t = pieces[i].t;
      const Vec3 centroid = (position(t[0]) + position(t[1]) + position(t[2])) / 3.0;
      v.inside = inside_by_rays(centroid, mesh(1 - s)) ? 1 : 0;
    }
  }

  // The seat (union only): a piece of the second operand outside the first whose curves all lie on
  // seat faces is beyond the seat and dropped, and the seat faces inside the second operand stay
  // instead. The two decisions must agree along every curve they share; where they cannot (a piece
  // that also passes beside the seat), both fall back to the plain union, which keeps the result
  // closed. Decided to a fixed point: flags only ever go from true to false.
  void resolve_seat() {
    for (Verdict& v : verdicts_[0]) v.seat_keep = v.inside == 1 && v.all_seat;
    for (Verdict& v : verdicts_[1]) v.seat_drop = v.inside == 0 && v.on_seat_curve && !v.on_other_curve;
    std::vector<std::pair<Index, Index>> pairs; // (first's inside component, second's outside component)
    for (const SeamSegment& g : seam_) {
      const std::uint64_t key = edge_key(g.p, g.q);
      Index a_in = kInvalidIndex, b_out = kInvalidIndex;
      for (Index piece : seam_pieces_[0].at(key))
        if (verdicts_[0][components_[0][piece]].inside == 1) a_in = components_[0][piece];
      for (Index piece : seam_pieces_[1].at(key))
        if (verdicts_[1][components_[1][piece]].inside == 0) b_out = components_[1][piece];
      if (a_in != kInvalidIndex && b_out != kInvalidIndex) pairs.emplace_back(a_in, b_out);
    }
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    for (bool changed = true; changed;) {
      changed = false;
      for (const auto& [a, b] : pairs) {
        Verdict &va = verdicts_[0][a], &vb = verdicts_[1][b];
        if (va.seat_keep != vb.seat_drop) {
          va.seat_keep = vb.seat_drop = false;
          changed = true;
        }
      }
    }
  }

  bool keep(int s, const Verdict& v, BooleanOp op) const {
    const bool inside = v.inside == 1;
    switch (op) {
    case BooleanOp::Union:
      if (s == 0 && inside && v.seat_keep) return true;
      if (s == 1 && !inside && v.seat_drop) return false;
      return !inside;
    case BooleanOp::Intersection: return inside;
    case BooleanOp::Difference: return s == 0 ? !inside : inside;
    }
    return false;
  }

  BooleanResult assemble(BooleanOp op) {
    BooleanResult result;
    const std::size_t total = na_ + nb_ + points_.size();
    std::vector<Index> remap(total, kInvalidIndex);
    TriangleMesh& out = result.mesh;
    // At most every face far from the other operand and every piece: reserved once (a template of
    // 100k faces would otherwise be copied as its arrays grow).
    const std::size_t most = a_.face_count() + b_.face_count() + pieces_[0].size() + pieces_[1].size();
    out.positions.reserve(total);
    out.triangles.reserve(most);
    result.from_b.reserve(most);
    result.source_face.reserve(most);
    // Every coordinate is what the result holds already: with round_to_float the operands come
    // rounded (mesh_boolean) and so does every curve point (crossing_point).
    auto vertex = [&](Index id) {
      if (remap[id] == kInvalidIndex) {
        remap[id] = out.vertex_count();
        out.positions.push_back(position(id));
      }
      return remap[id];
    };
    auto emit = [&](const Triangle& t, bool reverse, std::uint8_t from_b, Index source) {
      const Index a = vertex(t[0]), b = vertex(t[1]), c = vertex(t[2]);
      out.triangles.push_back(reverse ? Triangle{a, c, b} : Triangle{a, b, c});
      result.from_b.push_back(from_b);
      result.source_face.push_back(source);
    };
    // Faces far from the other operand are outside it.
    const Verdict far_outside{.exterior = true, .inside = 0};
    // Faces made or moved here (split pieces, their new corners rounded now) are checked after rounding;
    // unsplit local faces of either operand only where they touch those: mesh_boolean rounds the
    // operands to float32 first, so rounding moves none of their corners, and two unsplit faces cannot
    // cross (of two operands the corefinement would have split them; of one, it is a solid's).
    std::vector<Index> fresh, unchanged;
    for (int s = 0; s < 2; ++s) {
      const bool reverse = op == BooleanOp::Difference && s == 1;
      const TriangleMesh& m = mesh(s);
      if (keep(s, far_outside, op)) // as emit() would, without its cases: most of a large operand
        append_far_faces(m, near_slot_[s], remap.data() + base(s), reverse, static_cast<std::uint8_t>(s), result);
      // keep() is evaluated once per component.
      std::vector<std::int8_t> kept(verdicts_[s].size(), -1);
      for (std::size_t i = 0; i < pieces_[s].size(); ++i) {
        const Index c = components_[s][i];
        if (kept[c] < 0) kept[c] = keep(s, verdicts_[s][c], op) ? 1 : 0;
        if (!kept[c]) continue;
        (split_[s].count(pieces_[s][i].source) ? fresh : unchanged).push_back(out.face_count());
        emit(pieces_[s][i].t, reverse, static_cast<std::uint8_t>(s), pieces_[s][i].source);
      }
    }
    if (debug_)
      std::fprintf(stderr, "  local faces %zu + %zu, pairs %zu, fresh %zu\n", pieces_[0].size(), pieces_[1].size(),
                   seam_.size(), fresh.size());
    if (options_.round_to_float) {
      std::vector<VertexOrigin> origin(out.vertex_count(), VertexOrigin::first);
      for (std::size_t id = na_; id < total; ++id)
        if (remap[id] != kInvalidIndex)
          origin[remap[id]] = id < na_ + nb_                          ? VertexOrigin::second
                              : point_on_second_edge_[id - na_ - nb_] ? VertexOrigin::curve_on_second_edge
                                                                      : VertexOrigin::curve_on_first_edge;
      result.collapsed_edges = collapse_short_edges(result, origin, short_edge_, fresh, unchanged);
      if (debug_) std::fprintf(stderr, "  collapsed %zu edges under %.3g\n", result.collapsed_edges, short_edge_);
    }
    if (options_.check_result) {
      check_fresh(out, fresh, unchanged, debug_);
      check_closed_at_curve(out, fresh, unchanged);
    }
    result.intersecting_pairs = seam_.size();
    result.curve_segments = seam_.size();
    result.split_faces = split_[0].size() + split_[1].size();
    return result;
  }

  const TriangleMesh& a_;
  const TriangleMesh& b_;
  const BoundingBox a_box_;
  const BooleanOptions& options_;
  const Index na_, nb_;
  const double short_edge_;
  const bool debug_ = std::getenv("ST_DEBUG_BOOLEAN") != nullptr; // phase times and failures to stderr
  std::vector<Vec3> points_;
  std::vector<double> point_t_;
  std::vector<std::uint8_t> point_on_second_edge_; // per point: made by an edge of the second operand
  std::unordered_map<PointKey, Index, PointKeyHash> point_index_;
  std::unordered_map<Index, FaceWork> work_[2];
  std::unordered_map<Index, std::vector<Triangle>> split_[2];
  std::vector<SeamSegment> seam_;
  std::vector<std::uint64_t> seam_edges_;   // edge keys of seam_, sorted, for both sides' classification
  std::vector<PlaneOrientation> planes_[2]; // the near faces' planes
  std::vector<Index> near_slot_[2];         // per face: its plane in planes_; kInvalidIndex for a far face
  std::vector<Piece> pieces_[2];
  std::vector<Index> components_[2];
  std::vector<Verdict> verdicts_[2];
  std::unordered_map<std::uint64_t, std::array<Index, 2>> seam_pieces_[2]; // curve edge -> its two pieces
};

} // namespace

BooleanResult corefine(const TriangleMesh& a, const BoundingBox& a_box, const TriangleMesh& b, BooleanOp op,
                       const BooleanOptions& options, double short_edge) {
  return Corefinement(a, a_box, b, options, short_edge).run(op);
}

} // namespace st::boolean_detail
