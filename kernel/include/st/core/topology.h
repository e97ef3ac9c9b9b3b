#pragma once
// Derived connectivity of a TriangleMesh.
//
// Half-edges are implicit: half-edge h = 3*f + k runs from triangles[f][k] to triangles[f][(k+1)%3].
// Only the vertex -> faces incidence is stored (compressed rows, built in O(#F)); the opposite of a
// half-edge is found on demand from it, so building a MeshTopology of a million-triangle mesh costs
// a few milliseconds and work stays proportional to the part of the mesh an algorithm visits.
//
// An edge is "manifold" when exactly two triangles use it, in opposite directions. Every other edge
// (border, non-manifold, or with inconsistent orientation, as found in raw CT isosurfaces) has no
// opposite: algorithms treat it as a border.

#include "st/core/mesh.h"

#include <functional>
#include <span>
#include <vector>

namespace st {

inline Index face_of(Index h) { return h / 3; }
inline Index next_halfedge(Index h) { return h - h % 3 + (h + 1) % 3; }
inline Index prev_halfedge(Index h) { return h - h % 3 + (h + 2) % 3; }

class MeshTopology {
public:
  /// Precondition: every index of `mesh` is < vertex_count (see check_mesh). Keeps a reference.
  explicit MeshTopology(const TriangleMesh& mesh);
  /// The same, with every half-edge's opposite found at once (all_opposites) and kept: for a mesh most
  /// of whose edges an algorithm walks (a cut keeping most of it).
  struct KeepOpposites {};
  MeshTopology(const TriangleMesh& mesh, KeepOpposites);
  /// Topology of a temporary mesh would outlive it.
  MeshTopology(TriangleMesh&&) = delete;
  MeshTopology(TriangleMesh&&, KeepOpposites) = delete;

  [[nodiscard]] const TriangleMesh& mesh() const { return mesh_; }
  [[nodiscard]] Index from_vertex(Index h) const { return mesh_.triangles[h / 3][h % 3]; }
  [[nodiscard]] Index to_vertex(Index h) const { return mesh_.triangles[h / 3][(h + 1) % 3]; }

  /// Faces using vertex v.
  [[nodiscard]] std::span<const Index> faces_of(Index v) const {
    return {face_list_.data() + offsets_[v], face_list_.data() + offsets_[v + 1]};
  }

  /// How the other faces around the edge of half-edge h use it: `reverse` of them run it the other way
  /// (`opposite` is the last one's half-edge), `same` run it the same way, and `lowest` is the smallest
  /// of their half-edges on it (kInvalidIndex when none). Faces for which skip(face) is true are left
  /// out.
  struct EdgeUses {
    int reverse = 0, same = 0;
    Index opposite = kInvalidIndex, lowest = kInvalidIndex;
  };
  template <class Skip> [[nodiscard]] EdgeUses edge_uses(Index h, Skip&& skip) const {
    const Index f = h / 3, a = from_vertex(h), b = to_vertex(h);
    EdgeUses uses;
    for (Index g : faces_of(b)) {
      if (g == f || skip(g)) continue;
      const Triangle& t = mesh_.triangles[g];
      // Where b sits in g; then b -> a follows it, or a -> b precedes it.
      const Index k = t[0] == b ? 0 : (t[1] == b ? 1 : 2);
      Index on_edge = kInvalidIndex;
      if (t[(k + 1) % 3] == a) {
        ++uses.reverse;
        uses.opposite = on_edge = 3 * g + k;
      } else if (t[(k + 2) % 3] == a) {
        ++uses.same;
        on_edge = 3 * g + (k + 2) % 3;
      }
      if (on_edge < uses.lowest) uses.lowest = on_edge;
    }
    return uses;
  }
  /// The opposite half-edge, or kInvalidIndex when the edge is not manifold (see above).
  [[nodiscard]] Index opposite(Index h) const { return opposites_.empty() ? find_opposite(h) : opposites_[h]; }

  /// Opposite of every half-edge (#F*3 entries), for meshes that are walked a lot: each vertex's
  /// faces read once for all the half-edges into it, on all threads.
  [[nodiscard]] std::vector<Index> all_opposites() const;

  /// The unit normal vertex_normals() gives vertex v, bit for bit (the same sum over the faces around
  /// v in ascending order), zero where they cancel: for the few vertices a bone-sized mesh is read at.
  [[nodiscard]] Vec3 vertex_normal(Index v) const;

private:
  friend class CornerTable;
  [[nodiscard]] Index find_opposite(Index h) const;
  const TriangleMesh& mesh_;
  std::vector<Index> offsets_;
  std::vector<Index> face_list_;
  std::vector<Index> opposites_; // kept by the KeepOpposites constructor, else empty
};

/// MeshTopology::edge_uses(h, skip) for meshes whose every edge is asked about (a solid check): per
/// entry of each vertex's faces, the vertex's half-edge out of the face and the corners after and
/// before it there (none in a face `skip` leaves out), made once on all threads, so that an edge is
/// found among its end's entries without reading their faces again. Keeps a reference.
class CornerTable {
public:
  CornerTable(const MeshTopology& topology, const std::function<bool(Index)>& skip);
  CornerTable(MeshTopology&&, const std::function<bool(Index)>&) = delete;

  /// The same as topology.edge_uses(h, skip), for h in a face skip does not leave out.
  [[nodiscard]] MeshTopology::EdgeUses edge_uses(Index h) const;

private:
  struct Corner {
    Index out, next, prev;
  };
  const MeshTopology& topology_;
  std::vector<Corner> corners_; // parallel to the topology's face rows
};

/// Border loops of a mesh whose borders are simple (each border vertex has one outgoing border
/// half-edge); each loop lists vertex indices in half-edge order, so the mesh lies to the left of
/// the loop seen from the normal side. Throws GeometryError naming the vertex when a border vertex
/// is not simple (two border fans meet there).
std::vector<std::vector<Index>> border_loops(const TriangleMesh& mesh, const std::vector<Index>& opposites);

/// Number of edge-connected components (faces joined across manifold edges).
std::size_t component_count(const TriangleMesh& mesh, const std::vector<Index>& opposites);

} // namespace st
