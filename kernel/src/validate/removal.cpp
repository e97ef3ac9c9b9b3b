#include "st/validate/removal.h"

#include "detail/format.h"
#include "detail/parallel.h"
#include "st/core/errors.h"
#include "st/core/predicates.h"
#include "st/core/ray_triangle.h"
#include "st/boolean/triangle_intersection.h"
#include "sweep_columns.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <span>

namespace st {

namespace {

/// Closer than this, the guide touches the bone without being blocked (see removal.h).
constexpr double kContact_mm = 1e-3;

/// Whether the segment [p, q] passes from one side of the plane of (a, b, c) to the other through the
/// closed triangle (see removal.h).
bool crosses(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  const int sp = orient3d(a, b, c, p), sq = orient3d(a, b, c, q);
  if (sp == 0 || sq == 0 || sp == sq) return false;
  const int s1 = orient3d(p, q, a, b), s2 = orient3d(p, q, b, c), s3 = orient3d(p, q, c, a);
  return (s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0);
}

/// A bijective mix of 64 bits (splitmix64's finaliser).
std::uint64_t mix(std::uint64_t x) {
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

/// A face within this angle (radians) of lying along the way off counts as facing both ways.
constexpr double kAcross = 1e-6;
constexpr std::uint8_t kFront = 1, kBack = 2, kSilhouette = 4, kOpen = 8;

/// Per vertex: kFront when every face around it faces the way off `w` (beyond kAcross), kBack when
/// every one faces back, else kSilhouette, with kOpen when the fan around it is not closed (a border or
/// a non-manifold fan). An edge with a kFront or kBack end joins two faces that face the same way.
std::vector<std::uint8_t> sweeping_vertices(const TriangleMesh& mesh, const Vec3& w) {
  // A fan is closed when each neighbour appears in two of its faces: the XOR of a bijective hash of
  // the neighbours over the faces is then 0 (a border's two ends leave their hashes, never 0).
  std::vector<std::uint64_t> fan(mesh.vertex_count(), 0);
  std::vector<std::uint8_t> flags(mesh.vertex_count(), 0);
  for (Index f = 0; f < mesh.face_count(); ++f) {
    const Triangle& t = mesh.triangles[f];
    const Vec3 n = triangle_normal(mesh, f);
    const double c = n.dot(w), margin = kAcross * n.norm();
    const std::uint8_t facing = c > margin ? kFront : c < -margin ? kBack : kSilhouette;
    for (int k = 0; k < 3; ++k) {
      flags[t[k]] |= facing;
      fan[t[k]] ^= mix(t[(k + 1) % 3]) ^ mix(t[(k + 2) % 3]);
    }
  }
  for (Index v = 0; v < mesh.vertex_count(); ++v) {
    if (fan[v] != 0) flags[v] = kSilhouette | kOpen;
    else if (flags[v] != kFront && flags[v] != kBack) flags[v] = kSilhouette;
  }
  return flags;
}

struct Hit {
  Vec3 place;
  Index face; // a guide face at the place
};

class Collector {
public:
  void add(const Hit& hit) {
    const std::lock_guard<std::mutex> lock(mutex_);
    hits_.push_back(hit);
  }
  std::vector<Hit> take() { return std::move(hits_); }

private:
  std::mutex mutex_;
  std::vector<Hit> hits_;
};

} // namespace

SweepTest::SweepTest(const AabbTree& bone, const MeshTopology* topology)
    : bone_(bone), topology_(topology ? *topology : own_topology_.emplace(bone.mesh())) {
  const TriangleMesh& mesh = bone.mesh();
  if (&topology_.mesh() != &mesh) throw InvalidInput("removal check: the topology is not the bone's");
  const BoundingBox box = bounding_box(mesh);
  const double magnitude = mesh.empty() ? 1.0 : std::max(box.min.cwiseAbs().maxCoeff(), box.max.cwiseAbs().maxCoeff());
  lift_ = std::max(kContact_mm, std::ldexp(std::max(magnitude, 1.0), -20));
  shrunk_.reset(new Vec3[mesh.vertex_count()]); // left unwritten (untouched pages) until a vertex is read
  state_ = std::make_unique<std::atomic<std::uint8_t>[]>(mesh.vertex_count());
}

const Vec3& SweepTest::shrunk(Index v) const {
  constexpr std::uint8_t kMaking = 1, kMade = 2;
  std::atomic<std::uint8_t>& state = state_[v];
  if (state.load(std::memory_order_acquire) == kMade) return shrunk_[v];
  std::uint8_t expected = 0;
  if (state.compare_exchange_strong(expected, kMaking, std::memory_order_acquire)) {
    Vec3 p = bone_.mesh().positions[v];
    p -= lift_ * topology_.vertex_normal(v);
    shrunk_[v] = p;
    state.store(kMade, std::memory_order_release);
  } else {
    while (state.load(std::memory_order_acquire) != kMade) {
    } // another thread is making it (a few hundred nanoseconds)
  }
  return shrunk_[v];
}

RemovalReport check_removal(const AabbTree& bone, const TriangleMesh& guide, const Vec3& direction, double distance,
                            SweepStart start) {
  return SweepTest(bone)(guide, direction, distance, start);
}

RemovalReport SweepTest::operator()(const TriangleMesh& guide, const Vec3& direction, double distance, SweepStart start,
                                    const AabbTree* guide_tree_given) const {
  const double norm = direction.norm();
  if (!std::isfinite(norm) || !(norm > 0.0))
    throw InvalidInput("removal check: the direction must be a non-zero vector");
  if (!std::isfinite(distance) || !(distance > 0.0))
    throw InvalidInput("removal check: the distance must be > 0 mm, got " + detail::number(distance));
  const Vec3 d = direction / norm; // onto the bone
  const Vec3 w = -d;               // off the bone
  const double L = distance;
  const AabbTree& bone = bone_;
  const TriangleMesh& bmesh = bone.mesh();
  const BoundingBox gbox = bounding_box(guide);
  RemovalReport report;
  report.distance = L;
  report.blocked_faces.assign(guide.face_count(), 0);
  if (guide.empty() || bone.empty()) return report;
  // The bone shrunk by `lift` along its vertex normals (see removal.h).
  const double lift = lift_;
  std::vector<Vec3> g_at = guide.positions;
  {
    // The guide starts a lift along its way off; a part of the bone's surface is also raised off it.
    const std::vector<Vec3> gn = start == SweepStart::raised ? vertex_normals(guide) : std::vector<Vec3>{};
    for (std::size_t i = 0; i < g_at.size(); ++i)
      g_at[i] += lift * w + (gn.empty() ? Vec3::Zero() : Vec3(lift * gn[i]));
  }
  auto bone_corner = [&](Index f, int k) -> const Vec3& { return shrunk(bmesh.triangles[f][k]); };

  // Box culling: a guide face whose box, swept by L off the bone and grown by the lifts, meets no box of
  // a bone face cannot meet the bone on the way off, nor can its corners and edges (their paths lie in
  // that box; an edge's in the swept box of each of its two faces). Only the corners and edges of the
  // faces that pass are tested exactly, and only bone faces whose boxes, swept by L towards the guide,
  // meet a guide face's box give bone vertices to test. The bone's faces that can meet the guide at all
  // are those in the box it sweeps (grown).
  const double pad = 4.0 * lift;
  auto swept = [&](BoundingBox b, const Vec3& by) {
    b.extend(b.min + by);
    b.extend(b.max + by);
    return b.inflated(pad);
  };
  BoundingBox reach = gbox;
  reach.extend(gbox.min + L * w);
  reach.extend(gbox.max + L * w);
  std::vector<Index> near_faces;
  bone.for_each_in_box(reach.inflated(1.0 + pad), [&](Index f) { near_faces.push_back(f); });
  // Of a guide moving as a whole, only the paths of the vertices where its surface turns (kSilhouette)
  // are edges of the boundary of the solid it sweeps (removal.h): only those are followed, and a face
  // is culled only when a family asks about it (it has such a corner, or the fourth family tests it at
  // the end of the way). Those few paths and boxes read the bone's tree. Per face every vertex's path
  // counts, most of them from a guide resting on the bone, where the tree's boxes rise across the
  // paths: they read the bone's faces in the box the guide sweeps by their columns along the way
  // (sweep_columns.h).
  const bool per_face = start == SweepStart::raised;
  const std::vector<std::uint8_t> sweeps = per_face ? std::vector<std::uint8_t>{} : sweeping_vertices(guide, w);
  const bool closed = std::none_of(sweeps.begin(), sweeps.end(), [](std::uint8_t v) { return (v & kOpen) != 0; });
  auto at_end = [&](Index f) {
    const Triangle& t = guide.triangles[f];
    return std::array<Vec3, 3>{g_at[t[0]] + L * w, g_at[t[1]] + L * w, g_at[t[2]] + L * w};
  };
  auto passed_at_end = [&](const std::array<Vec3, 3>& p) { // a closed guide's face facing back
    const Vec3 n = (p[1] - p[0]).cross(p[2] - p[0]);
    return closed && n.dot(w) < -kAcross * n.norm();
  };
  auto asked = [&](Index f) { // whether a family tests a corner, an edge or the face itself
    if (per_face) return true;
    const Triangle& t = guide.triangles[f];
    return ((sweeps[t[0]] | sweeps[t[1]] | sweeps[t[2]]) & kSilhouette) || !passed_at_end(at_end(f));
  };
  std::optional<AabbTree> own_tree;
  const AabbTree& guide_tree = guide_tree_given ? *guide_tree_given : own_tree.emplace(guide);
  if (!guide_tree.holds_all_of(guide)) throw InvalidInput("removal check: the tree given is not over all of the guide");
  validate_detail::SweepColumns bone_columns(w);
  std::vector<std::uint8_t> near_guide(guide.face_count(), 0);
  if (per_face) {
    bone_columns.build(bmesh, &near_faces, pad);
    detail::parallel_for(guide.face_count(), 1024, [&](std::size_t, std::size_t begin, std::size_t end) {
      for (std::size_t f = begin; f < end; ++f) {
        validate_detail::FrameBox b = bone_columns.box_of(guide, static_cast<Index>(f));
        b.hi[2] += L;
        near_guide[f] = bone_columns.any_in(b) ? 1 : 0;
      }
    });
  } else {
    // Runs of faces in the guide tree's order (near each other): one box for a run whose swept boxes
    // together meet no bone box, as along the outer surface, which the way takes away from the bone.
    const std::span<const Index> order = guide_tree.ordered_faces();
    constexpr std::size_t kRun = 16;
    detail::parallel_for((order.size() + kRun - 1) / kRun, 64, [&](std::size_t, std::size_t begin, std::size_t end) {
      for (std::size_t r = begin; r < end; ++r) {
        const std::span<const Index> run = order.subspan(r * kRun, std::min(kRun, order.size() - r * kRun));
        BoundingBox together;
        for (const Index f : run)
          if (asked(f)) together.extend(triangle_box(guide, f));
        if (!together.valid() || !bone.any_in_box(swept(together, L * w))) continue;
        for (const Index f : run)
          if (asked(f)) near_guide[f] = bone.any_in_box(swept(triangle_box(guide, f), L * w)) ? 1 : 0;
      }
    });
  }
  std::vector<Index> first_face(guide.vertex_count(), kInvalidIndex);
  for (Index f = 0; f < guide.face_count(); ++f)
    if (near_guide[f])
      for (Index v : guide.triangles[f]) first_face[v] = f;

  Collector collector;
  // 1. Guide vertices along -d against the bone.
  detail::parallel_for(guide.vertex_count(), 512, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      if (first_face[i] == kInvalidIndex || !(per_face || (sweeps[i] & kSilhouette))) continue;
      const Vec3 &p = g_at[i], q = p + L * w;
      auto crossed = [&](Index f) { return crosses(p, q, bone_corner(f, 0), bone_corner(f, 1), bone_corner(f, 2)); };
      bool hit = false;
      if (per_face) {
        const Vec3 at = bone_columns.frame(p);
        hit = bone_columns.any_along(at[0], at[1], at[2], at[2] + L, crossed);
      } else {
        hit = bone.any_along(p, w, L, 2.0 * lift, crossed);
      }
      if (hit) collector.add({guide.positions[i], first_face[i]});
    }
  });
  // 2. Bone vertices near the guide along +d against the guide.
  // A bone vertex the guide copies (zero clearance, a rim through a bone vertex) touches the guide
  // there; the faces and edges around it are tested by the other two families. The guide's vertices,
  // in a table by a hash of their coordinates' bits (equal hashes compared exactly), tell those apart
  // first: a face whose corners the guide all copies is passed before its (costlier) box test.
  const std::size_t slots = std::bit_ceil(2 * static_cast<std::size_t>(guide.vertex_count()) + 16);
  std::vector<Index> table(slots, kInvalidIndex);
  auto hash = [&](const Vec3& p) {
    std::uint64_t h = 0;
    for (int k = 0; k < 3; ++k) h = mix(h ^ std::bit_cast<std::uint64_t>(p[k] == 0.0 ? 0.0 : p[k])); // -0 as 0
    return static_cast<std::size_t>(h) & (slots - 1);
  };
  auto slot_of = [&](const Vec3& p) {
    std::size_t s = hash(p);
    while (table[s] != kInvalidIndex && guide.positions[table[s]] != p) s = (s + 1) & (slots - 1);
    return s;
  };
  for (Index v = 0; v < guide.vertex_count(); ++v)
    if (std::size_t s = slot_of(guide.positions[v]); table[s] == kInvalidIndex) table[s] = v;
  // Asked once per bone vertex (a vertex has half a dozen faces): 1 copied, 2 not, 0 not yet asked.
  const auto known = std::make_unique<std::atomic<std::uint8_t>[]>(bmesh.vertex_count());
  auto copied = [&](Index v) {
    std::uint8_t k = known[v].load(std::memory_order_relaxed);
    if (k == 0) {
      k = table[slot_of(bmesh.positions[v])] != kInvalidIndex ? 1 : 2;
      known[v].store(k, std::memory_order_relaxed);
    }
    return k == 1;
  };
  std::vector<std::uint8_t> meets(near_faces.size(), 0);
  detail::parallel_for(near_faces.size(), 1024, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const Triangle& t = bmesh.triangles[near_faces[i]];
      if (copied(t[0]) && copied(t[1]) && copied(t[2])) continue;
      meets[i] = guide_tree.any_in_box(swept(triangle_box(bmesh, near_faces[i]), L * d)) ? 1 : 0;
    }
  });
  std::vector<Index> near;
  for (std::size_t i = 0; i < near_faces.size(); ++i)
    if (meets[i])
      for (Index v : bmesh.triangles[near_faces[i]])
        if (!copied(v)) near.push_back(v);
  std::sort(near.begin(), near.end());
  near.erase(std::unique(near.begin(), near.end()), near.end());
  detail::parallel_for(near.size(), 512, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const Vec3 &p = shrunk(near[i]), q = p + L * d;
      Index face = kInvalidIndex;
      guide_tree.any_along(p, d, L, 2.0 * lift, [&](Index f) {
        const Triangle& t = guide.triangles[f];
        if (!crosses(p, q, g_at[t[0]], g_at[t[1]], g_at[t[2]])) return false;
        face = f;
        return true;
      });
      if (face != kInvalidIndex) {
        const Triangle& t = guide.triangles[face];
        const auto h = ray_triangle(p, d, g_at[t[0]], g_at[t[1]], g_at[t[2]], 1e-6);
        collector.add({h ? Vec3(p + h->t * d) : p, face});
      }
    }
  });
  // 3. Bone edges against the parallelograms guide edges sweep (each edge once, from its first face),
  //    only for the edges where the guide's surface turns from facing the way off to facing back (see
  //    removal.h): an edge between two faces that both face the same way sweeps inside the solid.
  //    Per face (the block-out's question, SweepStart::raised) every edge counts.
  detail::parallel_for(guide.face_count(), 256, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f) {
      if (!near_guide[f]) continue;
      const Triangle& t = guide.triangles[f];
      for (int k = 0; k < 3; ++k) {
        const Index i0 = t[k], i1 = t[(k + 1) % 3];
        if (per_face) {
          if (i0 > i1) continue; // the other face of a closed mesh's edge takes it
        } else {
          if (!(sweeps[i0] & sweeps[i1] & kSilhouette)) continue;
          if (i0 > i1 && !(sweeps[i0] & sweeps[i1] & kOpen)) continue; // the edge's other face takes it
        }
        const Vec3 &g0 = g_at[i0], &g1 = g_at[i1];
        const Vec3 h0 = g0 + L * w, h1 = g1 + L * w;
        const Vec3 mid = 0.5 * (g0 + g1);
        BoundingBox sweep; // of the parallelogram, grown by the lifts: a bone edge outside it misses
        for (const Vec3* x : {&g0, &g1, &h0, &h1}) sweep.extend(*x);
        sweep = sweep.inflated(pad);
        Vec3 place = mid;
        const bool hit = bone.any_along(mid, w, L, 0.5 * (g1 - g0).norm() + 2.0 * lift, [&](Index bf) {
          for (int e = 0; e < 3; ++e) {
            // A bone edge from a vertex this guide edge copies meets its parallelogram only there.
            const Vec3 &o0 = bmesh.positions[bmesh.triangles[bf][e]],
                       &o1 = bmesh.positions[bmesh.triangles[bf][(e + 1) % 3]];
            if (o0 == guide.positions[i0] || o0 == guide.positions[i1] || o1 == guide.positions[i0] ||
                o1 == guide.positions[i1])
              continue;
            const Vec3 &b0 = bone_corner(bf, e), &b1 = bone_corner(bf, (e + 1) % 3);
            BoundingBox edge;
            edge.extend(b0);
            edge.extend(b1);
            if (!edge.overlaps(sweep)) continue;
            if (!crosses(b0, b1, g0, g1, h1) && !crosses(b0, b1, g0, h1, h0)) continue;
            // Where on the guide edge: the crossing moved back along the path.
            const Vec3 n = (g1 - g0).cross(w);
            const double den = n.dot(b1 - b0);
            const Vec3 x = den != 0.0 ? Vec3(b0 + (n.dot(g0 - b0) / den) * (b1 - b0)) : b0;
            place = x - (x - g0).dot(w) * w;
            return true;
          }
          return false;
        });
        if (hit) collector.add({place, static_cast<Index>(f)});
      }
    }
  });

  // 4. The guide's faces at the end of the way against the bone (exact triangle tests): of a closed
  //    guide only those that face the way off or across it (the others lie inside what it swept).
  if (!per_face)
    detail::parallel_for(guide.face_count(), 512, [&](std::size_t, std::size_t begin, std::size_t end) {
      for (std::size_t f = begin; f < end; ++f) {
        if (!near_guide[f]) continue;
        const Triangle& t = guide.triangles[f];
        const std::array<Vec3, 3> p = at_end(static_cast<Index>(f));
        if (passed_at_end(p)) continue;
        BoundingBox box;
        for (const Vec3& x : p) box.extend(x);
        bool meets = false;
        bone.for_each_in_box(box.inflated(pad), [&](Index bf) {
          meets = meets ||
                  triangles_intersect(p[0], p[1], p[2], bone_corner(bf, 0), bone_corner(bf, 1), bone_corner(bf, 2));
        });
        if (meets)
          collector.add(
              {(guide.positions[t[0]] + guide.positions[t[1]] + guide.positions[t[2]]) / 3.0, static_cast<Index>(f)});
      }
    });

  std::vector<Hit> hits = collector.take();
  // The same order whatever the threads did.
  std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) {
    return std::lexicographical_compare(a.place.data(), a.place.data() + 3, b.place.data(), b.place.data() + 3);
  });
  report.blocked_features = hits.size();
  report.removable = hits.empty();
  for (const Hit& h : hits) {
    report.blocked_faces[h.face] = 1;
    const bool far = std::all_of(report.blocking.begin(), report.blocking.end(),
                                 [&](const Vec3& p) { return (p - h.place).norm() > 2.0; });
    if (far && report.blocking.size() < 20) report.blocking.push_back(h.place);
  }
  return report;
}

} // namespace st
