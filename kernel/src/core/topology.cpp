#include "st/core/topology.h"
#include "detail/format.h"
#include "detail/parallel.h"

#include "st/core/errors.h"

#include <numeric>
#include <string>

namespace st {

MeshTopology::MeshTopology(const TriangleMesh& mesh) : mesh_(mesh) {
  const Index nv = mesh.vertex_count();
  offsets_.assign(static_cast<std::size_t>(nv) + 1, 0);
  for (const Triangle& t : mesh.triangles)
    for (Index v : t) ++offsets_[v + 1];
  std::partial_sum(offsets_.begin(), offsets_.end(), offsets_.begin());
  face_list_.resize(offsets_.back());
  std::vector<Index> fill(offsets_.begin(), offsets_.end() - 1);
  for (Index f = 0; f < mesh.face_count(); ++f)
    for (Index v : mesh.triangles[f]) face_list_[fill[v]++] = f;
}

namespace {

/// v's corner in face g: v's half-edge out of g and the corners after and before it there (v's first
/// place in g, as MeshTopology::edge_uses takes it).
template <class Corner> Corner corner_at(const TriangleMesh& mesh, Index g, Index v) {
  const Triangle& t = mesh.triangles[g];
  const Index k = t[0] == v ? 0 : (t[1] == v ? 1 : 2);
  return {3 * g + k, t[(k + 1) % 3], t[(k + 2) % 3]};
}

/// MeshTopology::edge_uses' rule over the corners of b's faces [row, end), for the half-edge a -> b
/// of face f: the faces other than f that run the edge b -> a (b's half-edge out) or a -> b (the one
/// into b).
template <class Corner> MeshTopology::EdgeUses uses_among(const Corner* row, const Corner* end, Index f, Index a) {
  MeshTopology::EdgeUses uses;
  for (; row != end; ++row) {
    if (row->out / 3 == f) continue;
    Index on_edge = kInvalidIndex;
    if (row->next == a) {
      ++uses.reverse;
      uses.opposite = on_edge = row->out;
    } else if (row->prev == a) {
      ++uses.same;
      on_edge = prev_halfedge(row->out);
    }
    if (on_edge < uses.lowest) uses.lowest = on_edge;
  }
  return uses;
}

/// The opposite an edge's uses give a half-edge: the one other face that runs it the other way.
Index opposite_of(const MeshTopology::EdgeUses& uses) {
  return (uses.reverse == 1 && uses.same == 0) ? uses.opposite : kInvalidIndex;
}

} // namespace

CornerTable::CornerTable(const MeshTopology& topology, const std::function<bool(Index)>& skip)
    : topology_(topology), corners_(topology.face_list_.size()) {
  const TriangleMesh& mesh = topology.mesh_;
  detail::parallel_for(mesh.vertex_count(), 4096, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (Index v = static_cast<Index>(begin); v < end; ++v) {
      Corner* row = corners_.data() + topology.offsets_[v];
      for (const Index g : topology.faces_of(v)) {
        *row = corner_at<Corner>(mesh, g, v);
        if (skip(g)) row->next = row->prev = kInvalidIndex;
        ++row;
      }
    }
  });
}

MeshTopology::EdgeUses CornerTable::edge_uses(Index h) const {
  const Index b = topology_.to_vertex(h);
  return uses_among(corners_.data() + topology_.offsets_[b], corners_.data() + topology_.offsets_[b + 1], h / 3,
                    topology_.from_vertex(h));
}

MeshTopology::MeshTopology(const TriangleMesh& mesh, KeepOpposites) : MeshTopology(mesh) {
  opposites_ = all_opposites();
}

Index MeshTopology::find_opposite(Index h) const {
  return opposite_of(edge_uses(h, [](Index) { return false; }));
}

std::vector<Index> MeshTopology::all_opposites() const {
  if (!opposites_.empty()) return opposites_;
  std::vector<Index> opp(static_cast<std::size_t>(mesh_.face_count()) * 3, kInvalidIndex);
  // Per vertex b, its corners (as a CornerTable row, made here and kept only while b is answered), then
  // every half-edge a -> b into it by edge_uses' rule: in a face with b once, the half-edge from the
  // corner before b; a face with b twice (b is then its corner after or before b) is read again. Each
  // half-edge has one end: written once.
  struct Corner {
    Index out, next, prev;
  };
  detail::parallel_for(mesh_.vertex_count(), 4096, [&](std::size_t, std::size_t begin, std::size_t end) {
    std::vector<Corner> fan;
    for (auto b = static_cast<Index>(begin); b < end; ++b) {
      fan.clear();
      for (const Index g : faces_of(b)) fan.push_back(corner_at<Corner>(mesh_, g, b));
      auto answer = [&](Index h, Index a) {
        opp[h] = opposite_of(uses_among(fan.data(), fan.data() + fan.size(), h / 3, a));
      };
      Index last = kInvalidIndex;
      for (const Corner& c : fan) {
        const Index g = c.out / 3;
        if (g == last) continue; // a face with b twice is listed twice, one after the other
        last = g;
        if (c.next != b && c.prev != b) {
          answer(prev_halfedge(c.out), c.prev);
          continue;
        }
        const Triangle& t = mesh_.triangles[g];
        for (Index k = 0; k < 3; ++k)
          if (t[(k + 1) % 3] == b) answer(3 * g + k, t[k]);
      }
    }
  });
  return opp;
}

Vec3 MeshTopology::vertex_normal(Index v) const {
  Vec3 n = Vec3::Zero();
  for (Index f : faces_of(v)) n += triangle_normal(mesh_, f);
  if (const double len = n.norm(); len > 0.0) n /= len;
  return n;
}

std::vector<std::vector<Index>> border_loops(const TriangleMesh& mesh, const std::vector<Index>& opposites) {
  // Outgoing border half-edge per vertex.
  std::vector<Index> outgoing(mesh.vertex_count(), kInvalidIndex);
  for (Index h = 0; h < opposites.size(); ++h) {
    if (opposites[h] != kInvalidIndex) continue;
    const Index v = mesh.triangles[h / 3][h % 3];
    if (outgoing[v] != kInvalidIndex) {
      const Vec3& p = mesh.positions[v];
      throw GeometryError("mesh border is not simple at vertex " + std::to_string(v) + " (" + detail::number(p.x()) +
                          ", " + detail::number(p.y()) + ", " + detail::number(p.z()) +
                          "): two border fans meet there");
    }
    outgoing[v] = h;
  }
  std::vector<std::vector<Index>> loops;
  std::vector<char> used(opposites.size(), 0);
  for (Index h0 = 0; h0 < opposites.size(); ++h0) {
    if (opposites[h0] != kInvalidIndex || used[h0]) continue;
    std::vector<Index> loop;
    Index h = h0;
    while (!used[h]) {
      used[h] = 1;
      loop.push_back(mesh.triangles[h / 3][h % 3]);
      const Index to = mesh.triangles[h / 3][(h % 3 + 1) % 3];
      h = outgoing[to];
      if (h == kInvalidIndex) throw GeometryError("mesh border is broken at vertex " + std::to_string(to));
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

std::size_t component_count(const TriangleMesh& mesh, const std::vector<Index>& opposites) {
  std::vector<char> seen(mesh.face_count(), 0);
  std::vector<Index> stack;
  std::size_t count = 0;
  for (Index f0 = 0; f0 < mesh.face_count(); ++f0) {
    if (seen[f0]) continue;
    ++count;
    seen[f0] = 1;
    stack.push_back(f0);
    while (!stack.empty()) {
      const Index f = stack.back();
      stack.pop_back();
      for (int k = 0; k < 3; ++k) {
        const Index o = opposites[3 * f + k];
        if (o != kInvalidIndex && !seen[o / 3]) {
          seen[o / 3] = 1;
          stack.push_back(o / 3);
        }
      }
    }
  }
  return count;
}

} // namespace st
