#include "st/design/decimate.h"
#include "detail/format.h"

#include "st/core/errors.h"
#include "st/core/topology.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

namespace st {
namespace {

/// Weight of the squared edge length in the queue key, relative to the quadric cost (both mm^2): among
/// collapses of (nearly) equal cost, short edges, i.e. slivers, go first.
constexpr double kLengthWeight = 1e-4;

/// A new edge may be at most this factor longer than the target edge length.
constexpr double kMaxNewEdgeFactor = 1.5;

/// Triangles of lower quality (see decimate.h) are never made: they are (nearly) degenerate.
constexpr double kDegenerateQuality = 1e-6;

/// The plane and normal of a triangle of lower quality (a sliver: three nearly collinear points on
/// the surface) say little about the surface: such input triangles enter the quadrics with weight
/// quality / kTrustQuality and not the plane-distance check, and the normal-change test skips current
/// triangles of lower quality (the test against the original normals still applies).
constexpr double kTrustQuality = 0.05;

/// The optimal point of a quadric is used when det(A) exceeds this times (trace(A)/3)^3.
constexpr double kSolveConditioning = 1e-10;

/// Collapse passes: each rebuilds the queue, so edges refused earlier are tried once more.
constexpr int kMaxPasses = 8;
/// ... while the last pass collapsed more than this fraction of the faces left.
constexpr double kRepassFraction = 0.02;

/// Symmetric quadric x^T A x + 2 b.x + c, coordinates relative to the mesh centre.
struct Quadric {
  double xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0, bx = 0, by = 0, bz = 0, c = 0;

  void add_plane(const Vec3& n, double d, double w) {
    xx += w * n.x() * n.x();
    xy += w * n.x() * n.y();
    xz += w * n.x() * n.z();
    yy += w * n.y() * n.y();
    yz += w * n.y() * n.z();
    zz += w * n.z() * n.z();
    bx += w * d * n.x();
    by += w * d * n.y();
    bz += w * d * n.z();
    c += w * d * d;
  }
  Quadric& operator+=(const Quadric& q) {
    xx += q.xx, xy += q.xy, xz += q.xz, yy += q.yy, yz += q.yz, zz += q.zz;
    bx += q.bx, by += q.by, bz += q.bz, c += q.c;
    return *this;
  }
  [[nodiscard]] Vec3 times(const Vec3& p) const {
    return {xx * p.x() + xy * p.y() + xz * p.z(), xy * p.x() + yy * p.y() + yz * p.z(),
            xz * p.x() + yz * p.y() + zz * p.z()};
  }
  [[nodiscard]] double operator()(const Vec3& p) const {
    return std::max(0.0, p.dot(times(p)) + 2.0 * (bx * p.x() + by * p.y() + bz * p.z()) + c);
  }
};

struct Plane {
  Vec3 n = Vec3::Zero(); // unit, or zero for a degenerate input triangle
  double d = 0.0;        // n.(x - origin) + d = 0
};

/// A queued edge: half-edge `h` with the larger stamp of its end points when queued. Stamps are
/// handed out in increasing order whenever a vertex changes, so the entry is current exactly when
/// the larger stamp of the half-edge's (present) end points still equals it.
struct QueueEntry {
  Index h;
  std::uint32_t stamp;
};

/// Monotone bucket queue on non-negative keys: a key's bucket is its IEEE bit pattern without the
/// low 48 bits (16 buckets per octave), so popping goes by increasing key up to a factor 2^(1/16),
/// each operation O(1) and cache friendly (a binary heap of a million entries spends most of its time
/// in cache misses). Entries of one bucket come out last-in first-out.
class BucketQueue {
public:
  static constexpr int kShift = 48;
  static constexpr std::size_t kBuckets = std::size_t{1} << (64 - 1 - kShift);

  BucketQueue() : buckets_(kBuckets) {}
  void clear() {
    for (std::size_t b = first_; b <= last_ && b < kBuckets; ++b) buckets_[b].clear();
    first_ = kBuckets;
    last_ = 0;
  }
  void push(double key, const QueueEntry& e) {
    const std::size_t b =
        key > 0.0 ? std::min<std::size_t>(std::bit_cast<std::uint64_t>(key) >> kShift, kBuckets - 1) : 0;
    buckets_[b].push_back(e);
    first_ = std::min(first_, b);
    last_ = std::max(last_, b);
  }
  bool pop(QueueEntry& e) {
    while (first_ <= last_ && first_ < kBuckets && buckets_[first_].empty()) ++first_;
    if (first_ > last_ || first_ >= kBuckets) return false;
    e = buckets_[first_].back();
    buckets_[first_].pop_back();
    return true;
  }

private:
  std::vector<std::vector<QueueEntry>> buckets_;
  std::size_t first_ = kBuckets, last_ = 0;
};

/// A planned collapse: vertex `removed` merges into `kept`, which moves to `p`.
struct Candidate {
  Index h = kInvalidIndex;
  Index removed = kInvalidIndex;
  Index kept = kInvalidIndex;
  Vec3 p;
  double cost = 0.0;
};

double quality(const Vec3& a, const Vec3& b, const Vec3& c, Vec3* normal) {
  *normal = (b - a).cross(c - a);
  const double sum = (b - a).squaredNorm() + (c - b).squaredNorm() + (a - c).squaredNorm();
  return sum > 0.0 ? 2.0 * std::numbers::sqrt3 * normal->norm() / sum : 0.0;
}

bool same_position(const Vec3& a, const Vec3& b) { return a.x() == b.x() && a.y() == b.y() && a.z() == b.z(); }

class Decimator {
public:
  Decimator(const TriangleMesh& mesh, const DecimateOptions& options);
  DecimateResult run();

private:
  [[nodiscard]] Index from(Index h) const { return corner_[h]; }
  [[nodiscard]] Index to(Index h) const { return corner_[next_halfedge(h)]; }
  [[nodiscard]] bool is_border(Index v) const { return border_[v] != 0; }
  [[nodiscard]] bool is_pinned(Index v) const { return options_.keep_border && is_border(v); }
  [[nodiscard]] Vec3 local(const Vec3& p) const { return p - origin_; }

  void collect_fan(Index v, std::vector<Index>& fan) const;
  void normalise_start(Index v, Index h);
  bool plan(Index h, Candidate& c) const;
  bool collapse_allowed(const Candidate& c);
  bool within_error(Index v, const Vec3& p) const;
  void collapse(const Candidate& c);
  void push_edge(Index h);
  void push_vertex_edges(Index v);
  DecimateResult extract() const;

  const DecimateOptions& options_;
  Vec3 origin_;
  double cos_max_turn_;
  double max_edge_; // longest edge a collapse may create (infinite: no limit)

  std::vector<Vec3> pos_;
  std::vector<Index> corner_; // vertex of corner / half-edge h = 3f + k
  std::vector<Index> opp_;    // opposite half-edge or kInvalidIndex
  std::vector<char> face_alive_;
  std::vector<Index> out_;   // per vertex: outgoing half-edge starting its fan (border one)
  std::vector<char> locked_; // not a manifold vertex of the input: never touched
  std::vector<char> border_; // out_ is a border half-edge
  std::vector<char> vertex_alive_;
  std::vector<char> moved_;
  std::vector<Index> source_face_; // input triangle index of each face
  std::vector<Quadric> quadric_;
  std::vector<Vec3> normal_sum_; // sum of area vectors of the input triangles of the region
  std::vector<Plane> planes_;    // per face
  std::vector<Index> region_head_, region_tail_, region_next_; // lists of corners per vertex
  std::vector<std::uint32_t> stamp_;
  std::uint32_t stamp_counter_ = 0;
  std::vector<std::uint32_t> mark_;
  std::uint32_t mark_counter_ = 0;
  BucketQueue queue_;
  std::vector<Index> fan_removed_, fan_kept_;
  std::size_t collapses_ = 0;
  std::size_t alive_faces_ = 0;
};

Decimator::Decimator(const TriangleMesh& mesh, const DecimateOptions& options) : options_(options) {
  origin_ = bounding_box(mesh).center();
  if (!origin_.allFinite()) origin_ = Vec3::Zero();
  cos_max_turn_ = std::cos(options.max_normal_change_deg * std::numbers::pi / 180.0);
  max_edge_ = options.target_edge_length > 0.0 ? kMaxNewEdgeFactor * options.target_edge_length
                                               : std::numeric_limits<double>::infinity();
  pos_ = mesh.positions;
  const Index nv = mesh.vertex_count();

  // Faces: the input triangles without repeated corners.
  TriangleMesh work;
  work.triangles.reserve(mesh.triangles.size());
  source_face_.reserve(mesh.triangles.size());
  for (Index f = 0; f < mesh.face_count(); ++f) {
    const Triangle& t = mesh.triangles[f];
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) continue;
    work.triangles.push_back(t);
    source_face_.push_back(f);
  }
  work.positions.resize(nv); // topology only reads the vertex count
  const Index nf = work.face_count();
  corner_.resize(static_cast<std::size_t>(nf) * 3);
  for (Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) corner_[3 * f + k] = work.triangles[f][k];
  opp_ = MeshTopology(work).all_opposites();
  face_alive_.assign(nf, 1);
  alive_faces_ = nf;

  // Fan starts; a vertex with two outgoing border half-edges, or whose faces do not form one fan, is
  // locked.
  out_.assign(nv, kInvalidIndex);
  locked_.assign(nv, 0);
  std::vector<Index> incident(nv, 0);
  for (Index h = 0; h < corner_.size(); ++h) {
    const Index v = corner_[h];
    ++incident[v];
    if (opp_[h] != kInvalidIndex) continue;
    if (out_[v] != kInvalidIndex && opp_[out_[v]] == kInvalidIndex) locked_[v] = 1;
    else out_[v] = h;
  }
  for (Index h = 0; h < corner_.size(); ++h)
    if (out_[corner_[h]] == kInvalidIndex) out_[corner_[h]] = h;
  for (Index v = 0; v < nv && v < options_.frozen.size(); ++v)
    if (options_.frozen[v]) locked_[v] = 1;
  vertex_alive_.assign(nv, 0);
  border_.assign(nv, 0);
  for (Index v = 0; v < nv; ++v) {
    if (out_[v] == kInvalidIndex) continue;
    border_[v] = opp_[out_[v]] == kInvalidIndex;
    vertex_alive_[v] = 1;
    if (locked_[v]) continue;
    collect_fan(v, fan_kept_);
    if (fan_kept_.size() != incident[v]) locked_[v] = 1;
  }

  // Planes, quadrics, region lists, reference normals.
  planes_.resize(nf);
  quadric_.assign(nv, Quadric{});
  normal_sum_.assign(nv, Vec3::Zero());
  region_head_.assign(nv, kInvalidIndex);
  region_tail_.assign(nv, kInvalidIndex);
  region_next_.assign(corner_.size(), kInvalidIndex);
  for (Index f = 0; f < nf; ++f) {
    const Vec3 a = local(pos_[corner_[3 * f]]);
    const Vec3 b = local(pos_[corner_[3 * f + 1]]);
    const Vec3 c = local(pos_[corner_[3 * f + 2]]);
    Vec3 area;
    const double q = quality(a, b, c, &area);
    const double len = area.norm();
    Vec3 n = Vec3::Zero();
    double d = 0.0;
    if (len > 0.0 && std::isfinite(len)) {
      n = area / len;
      d = -n.dot(a);
    }
    if (q >= kTrustQuality) planes_[f] = {n, d};
    for (int k = 0; k < 3; ++k) {
      const Index v = corner_[3 * f + k];
      quadric_[v].add_plane(n, d, std::min(1.0, q / kTrustQuality));
      normal_sum_[v] += area;
      const Index h = 3 * f + static_cast<Index>(k);
      region_next_[h] = region_head_[v];
      region_head_[v] = h;
      if (region_tail_[v] == kInvalidIndex) region_tail_[v] = h;
    }
  }
  if (!options.keep_border) {
    // Planes through border edges, orthogonal to their triangle, hold the border in place.
    for (Index h = 0; h < corner_.size(); ++h) {
      if (opp_[h] != kInvalidIndex) continue;
      const Vec3 a = local(pos_[from(h)]);
      const Vec3 e = local(pos_[to(h)]) - a;
      Vec3 n = e.cross(e.cross(local(pos_[corner_[prev_halfedge(h)]]) - a));
      const double len = n.norm();
      if (!(len > 0.0)) continue;
      n /= len;
      for (Index v : {from(h), to(h)}) quadric_[v].add_plane(n, -n.dot(a), 1.0);
    }
  }
  moved_.assign(nv, 0);
  stamp_.assign(nv, 0);
  mark_.assign(nv, 0);
}

void Decimator::collect_fan(Index v, std::vector<Index>& fan) const {
  fan.clear();
  const Index start = out_[v];
  Index h = start;
  do {
    fan.push_back(h);
    h = opp_[prev_halfedge(h)];
  } while (h != kInvalidIndex && h != start && fan.size() <= corner_.size());
}

void Decimator::normalise_start(Index v, Index h) {
  // Turn backwards until a border half-edge or the start again.
  const Index start = h;
  for (;;) {
    const Index o = opp_[h];
    if (o == kInvalidIndex) break;
    const Index back = next_halfedge(o);
    if (back == start) break;
    h = back;
  }
  out_[v] = h;
  border_[v] = opp_[h] == kInvalidIndex;
}

bool Decimator::plan(Index h, Candidate& c) const {
  const Index a = from(h), b = to(h);
  const double len2 = (pos_[b] - pos_[a]).squaredNorm();
  if (options_.target_edge_length > 0.0 && len2 > options_.target_edge_length * options_.target_edge_length)
    return false;
  if (locked_[a] || locked_[b]) return false;
  const bool pin_a = is_pinned(a), pin_b = is_pinned(b);
  if (pin_a && pin_b) return false;
  c.h = h;
  Quadric q = quadric_[a];
  q += quadric_[b];
  if (pin_a || pin_b) {
    c.kept = pin_a ? a : b;
    c.removed = pin_a ? b : a;
    c.p = pos_[c.kept];
  } else {
    c.kept = a;
    c.removed = b;
    const Vec3 la = local(pos_[a]), lb = local(pos_[b]);
    Eigen::Matrix3d m;
    m << q.xx, q.xy, q.xz, q.xy, q.yy, q.yz, q.xz, q.yz, q.zz;
    const double trace = (q.xx + q.yy + q.zz) / 3.0;
    const double det = m.determinant();
    bool solved = false;
    if (trace > 0.0 && std::abs(det) > kSolveConditioning * trace * trace * trace) {
      const Vec3 p = -(m.inverse() * Vec3(q.bx, q.by, q.bz));
      if (p.allFinite() && (p - 0.5 * (la + lb)).squaredNorm() <= len2) {
        c.p = p + origin_;
        solved = true;
      }
    }
    if (!solved) {
      // Best point on the edge.
      const Vec3 d = lb - la;
      const double dad = d.dot(q.times(d));
      double t = 0.5;
      if (dad > 1e-12 * trace * d.squaredNorm())
        t = std::clamp(-(q.times(la) + Vec3(q.bx, q.by, q.bz)).dot(d) / dad, 0.0, 1.0);
      c.p = (t == 0.0) ? pos_[a] : (t == 1.0) ? pos_[b] : pos_[a] + t * (pos_[b] - pos_[a]);
    }
  }
  c.cost = q(local(c.p));
  return true;
}

bool Decimator::within_error(Index v, const Vec3& p) const {
  const Vec3 lp = local(p);
  const double e = options_.max_error;
  for (Index h = region_head_[v]; h != kInvalidIndex; h = region_next_[h]) {
    const Plane& plane = planes_[h / 3];
    if (std::abs(plane.n.dot(lp) + plane.d) > e) return false;
  }
  return true;
}

bool Decimator::collapse_allowed(const Candidate& c) {
  const Index h = c.h;
  const Index a = from(h), b = to(h);
  const Index o = opp_[h];
  const Index f0 = h / 3;
  const Index f1 = o == kInvalidIndex ? kInvalidIndex : o / 3;

  // Topology.
  if (o != kInvalidIndex && is_border(a) && is_border(b)) return false; // would pinch the surface
  if (o == kInvalidIndex && options_.keep_border) return false;
  const Index apex0 = corner_[prev_halfedge(h)];
  if (locked_[apex0]) return false;
  if (opp_[next_halfedge(h)] == kInvalidIndex && opp_[prev_halfedge(h)] == kInvalidIndex) return false;
  Index apex1 = kInvalidIndex;
  if (o != kInvalidIndex) {
    apex1 = corner_[prev_halfedge(o)];
    if (locked_[apex1]) return false;
    if (opp_[next_halfedge(o)] == kInvalidIndex && opp_[prev_halfedge(o)] == kInvalidIndex) return false;
  }
  collect_fan(c.removed, fan_removed_);
  collect_fan(c.kept, fan_kept_);
  // Valence of the apexes: an interior apex of valence 3 would end with two triangles on one edge.
  for (Index apex : {apex0, apex1}) {
    if (apex == kInvalidIndex || is_border(apex)) continue;
    Index valence = 0;
    Index g = out_[apex];
    do {
      ++valence;
      g = opp_[prev_halfedge(g)];
    } while (g != out_[apex] && valence < 4);
    if (valence <= 3) return false;
  }
  // Link condition: the end points share exactly the apexes.
  ++mark_counter_;
  auto mark_neighbours = [&](const std::vector<Index>& fan, Index v) {
    for (Index g : fan) mark_[to(g)] = mark_counter_;
    if (is_border(v)) mark_[corner_[prev_halfedge(fan.back())]] = mark_counter_;
  };
  mark_neighbours(fan_removed_, c.removed);
  int shared = 0;
  for (Index g : fan_kept_)
    if (mark_[to(g)] == mark_counter_) ++shared;
  if (is_border(c.kept) && mark_[corner_[prev_halfedge(fan_kept_.back())]] == mark_counter_) ++shared;
  if (shared != (o == kInvalidIndex ? 1 : 2)) return false;

  // Geometry of the changed triangles. Quality: the worst changed triangle may fall below the
  // minimum only if it is still better than the worst triangle before (the removed ones included).
  const bool kept_moves = !same_position(c.p, pos_[c.kept]);
  double worst_before = std::numeric_limits<double>::infinity();
  double worst_after = std::numeric_limits<double>::infinity();
  auto triangle_ok = [&](Index f) {
    std::array<Vec3, 3> before, after;
    std::array<Index, 3> v{};
    for (int k = 0; k < 3; ++k) {
      v[k] = corner_[3 * f + k];
      before[k] = pos_[v[k]];
      after[k] = (v[k] == c.removed || v[k] == c.kept) ? c.p : before[k];
    }
    Vec3 n_before, n_after;
    const double q_before = quality(before[0], before[1], before[2], &n_before);
    worst_before = std::min(worst_before, q_before);
    if (f == f0 || f == f1) return true;
    const double q_after = quality(after[0], after[1], after[2], &n_after);
    worst_after = std::min(worst_after, q_after);
    if (!(q_after >= kDegenerateQuality)) return false;
    if (q_before >= kTrustQuality && n_after.dot(n_before) < cos_max_turn_ * n_after.norm() * n_before.norm())
      return false;
    Vec3 reference = normal_sum_[c.removed] + normal_sum_[c.kept];
    for (int k = 0; k < 3; ++k)
      if (v[k] != c.removed && v[k] != c.kept) reference += normal_sum_[v[k]];
    if (!(n_after.dot(reference) > 0.0)) return false;
    for (int k = 0; k < 3; ++k)
      if (v[k] != c.removed && v[k] != c.kept && (after[k] - c.p).norm() > max_edge_) return false;
    return true;
  };
  for (Index g : fan_removed_)
    if (!triangle_ok(g / 3)) return false;
  if (kept_moves)
    for (Index g : fan_kept_)
      if (g / 3 != f0 && g / 3 != f1 && !triangle_ok(g / 3)) return false;
  if (worst_after < options_.min_triangle_quality && worst_after < worst_before) return false;

  // Deviation: the quadric bounds the largest plane distance; check plane by plane when it does not.
  if (options_.max_error < std::numeric_limits<double>::infinity() &&
      c.cost > options_.max_error * options_.max_error) {
    if (!same_position(c.p, pos_[c.removed]) && !within_error(c.removed, c.p)) return false;
    if (kept_moves && !within_error(c.kept, c.p)) return false;
  }
  return true;
}

void Decimator::collapse(const Candidate& c) {
  const Index h = c.h;
  const Index o = opp_[h];
  const Index f0 = h / 3;
  const Index f1 = o == kInvalidIndex ? kInvalidIndex : o / 3;
  const Index r = c.removed, kept = c.kept;
  // fan_removed_ and fan_kept_ still hold the fans from collapse_allowed.
  for (Index g : fan_removed_)
    if (g / 3 != f0 && g / 3 != f1) corner_[g] = kept;

  auto remove_face = [&](Index e) {
    // e is a half-edge of the collapsed edge; glue the two other edges of its face.
    const Index x = opp_[next_halfedge(e)];
    const Index y = opp_[prev_halfedge(e)];
    if (x != kInvalidIndex) opp_[x] = y;
    if (y != kInvalidIndex) opp_[y] = x;
    face_alive_[e / 3] = 0;
    --alive_faces_;
    const Index apex = corner_[prev_halfedge(e)];
    normalise_start(apex, x != kInvalidIndex ? x : next_halfedge(y));
  };
  remove_face(h);
  if (o != kInvalidIndex) remove_face(o);

  Index start = kInvalidIndex;
  for (const auto* fan : {&fan_kept_, &fan_removed_})
    for (Index g : *fan)
      if (start == kInvalidIndex && g / 3 != f0 && g / 3 != f1) start = g;
  if (start == kInvalidIndex) {
    vertex_alive_[kept] = 0;
  } else {
    normalise_start(kept, start);
  }
  vertex_alive_[r] = 0;
  if (!same_position(c.p, pos_[kept])) moved_[kept] = 1;
  pos_[kept] = c.p;
  quadric_[kept] += quadric_[r];
  normal_sum_[kept] += normal_sum_[r];
  if (region_head_[r] != kInvalidIndex) {
    if (region_head_[kept] == kInvalidIndex) region_head_[kept] = region_head_[r];
    else region_next_[region_tail_[kept]] = region_head_[r];
    region_tail_[kept] = region_tail_[r];
  }
  stamp_[kept] = ++stamp_counter_;
  stamp_[r] = ++stamp_counter_;
  ++collapses_;
}

void Decimator::push_edge(Index h) {
  Candidate c;
  if (!plan(h, c)) return;
  const double len2 = (pos_[to(h)] - pos_[from(h)]).squaredNorm();
  queue_.push(c.cost + kLengthWeight * len2, {h, std::max(stamp_[from(h)], stamp_[to(h)])});
}

void Decimator::push_vertex_edges(Index v) {
  if (!vertex_alive_[v]) return;
  collect_fan(v, fan_kept_);
  for (Index g : fan_kept_) push_edge(g);
  if (is_border(v)) push_edge(prev_halfedge(fan_kept_.back()));
}

DecimateResult Decimator::run() {
  for (int pass = 0; pass < kMaxPasses; ++pass) {
    const std::size_t before = collapses_;
    queue_.clear();
    for (Index h = 0; h < corner_.size(); ++h)
      if (face_alive_[h / 3] && (opp_[h] == kInvalidIndex || opp_[h] > h)) push_edge(h);
    QueueEntry e;
    while (alive_faces_ > 4 && queue_.pop(e)) {
      if (!face_alive_[e.h / 3] || std::max(stamp_[from(e.h)], stamp_[to(e.h)]) != e.stamp) continue;
      Candidate c;
      if (!plan(e.h, c) || !collapse_allowed(c)) continue;
      collapse(c);
      push_vertex_edges(c.kept);
    }
    // Another pass only while it pays.
    if (collapses_ - before <= kRepassFraction * static_cast<double>(alive_faces_)) break;
  }
  return extract();
}

DecimateResult Decimator::extract() const {
  DecimateResult result;
  result.collapses = collapses_;
  std::vector<Index> remap(pos_.size(), kInvalidIndex);
  result.mesh.triangles.reserve(alive_faces_);
  for (Index f = 0; f < face_alive_.size(); ++f) {
    if (!face_alive_[f]) continue;
    Triangle t{};
    for (int k = 0; k < 3; ++k) {
      const Index v = corner_[3 * f + k];
      if (remap[v] == kInvalidIndex) {
        remap[v] = static_cast<Index>(result.mesh.positions.size());
        result.mesh.positions.push_back(pos_[v]);
        result.vertex_source.push_back(moved_[v] ? kInvalidIndex : v);
      }
      t[k] = remap[v];
    }
    result.mesh.triangles.push_back(t);
  }
  for (Index f = 0; f < result.mesh.face_count(); ++f)
    if (triangle_normal(result.mesh, f).squaredNorm() == 0.0) ++result.degenerate_left;
  return result;
}

} // namespace

DecimateResult decimate(const TriangleMesh& mesh, const DecimateOptions& options) {
  check_mesh(mesh, "decimate");
  if (!(options.max_error >= 0.0))
    throw InvalidInput("decimate: max_error must be >= 0, got " + detail::number(options.max_error));
  if (!(options.target_edge_length >= 0.0) || std::isinf(options.target_edge_length))
    throw InvalidInput("decimate: target_edge_length must be finite and >= 0, got " +
                       detail::number(options.target_edge_length));
  if (!(options.min_triangle_quality >= 0.0 && options.min_triangle_quality <= 1.0))
    throw InvalidInput("decimate: min_triangle_quality must be in [0, 1], got " +
                       detail::number(options.min_triangle_quality));
  if (!(options.max_normal_change_deg > 0.0 && options.max_normal_change_deg <= 180.0))
    throw InvalidInput("decimate: max_normal_change_deg must be in (0, 180], got " +
                       detail::number(options.max_normal_change_deg));
  if (mesh.triangles.size() >= kInvalidIndex / 3)
    throw InvalidInput("decimate: too many triangles (" + std::to_string(mesh.triangles.size()) + ")");
  return Decimator(mesh, options).run();
}

} // namespace st
