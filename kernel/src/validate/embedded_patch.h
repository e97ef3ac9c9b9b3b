#pragma once
// Patches of a mesh that cannot cross themselves (private to check_solid, st/validate/validate.h): the
// self-intersection check passes over the pairs of faces within such a patch instead of testing them.
//
// A patch whose faces all turn the same way when projected along one axis, and whose border (its
// half-edges without a partner in the patch) is a set of closed loops that project to simple polygons
// apart from each other, projects one to one onto that axis plane when, just right of each loop, the
// loops wind 0 times in sum: over a point off the projected edges, the number of its faces is the
// winding number of the projected border about the point (every face counts +1); it is 1 just left of
// a border edge (a face lies there), one more than just right of it, so 0 on every right side leaves 0
// or 1 everywhere. Two of its faces therefore meet only where they share a corner or an edge. (Volino
// and Magnenat-Thalmann's normal-cone test for self-collision, made exact: the turns, the polygons'
// crossings and the windings are decided by orient2d on coordinates dropped, not rounded.) A sheet
// with holes (a template's inner or outer surface around its bores) is one such patch.

#include "st/core/mesh.h"

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace st::validate_detail {

/// Per face, the axis projections in which it turns one way: bit 2k when its corners, projected along
/// axis k (coordinates k+1 and k+2, in that order), turn counterclockwise, bit 2k+1 when clockwise.
/// A face that projects to a segment along every axis, or with a corner that is not finite, has none.
std::vector<std::uint8_t> projection_turns(const TriangleMesh& mesh);

/// Whole patches: from each face not yet in one, the faces reached across partnered edges whose faces
/// turn by less than 60 degrees and that turn the way it turns most (along the axis of its normal's
/// largest coordinate; seeds within about 25 degrees of an axis first), kept when their border is as
/// described above (a smooth surface's sheets around their holes, the halves of a tube). Per face, its
/// patch (kInvalidIndex for none). `opposite` and `turns` as for Patches.
std::vector<Index> whole_patches(const TriangleMesh& mesh, const std::vector<Index>& opposite,
                                 const std::vector<std::uint8_t>& turns);

/// The patches of a mesh that are ranges of `order` (the faces of a tree, in its order), for
/// check_solid to ask about its tree's nodes and pairs of nodes: within one whole patch, or a node's
/// own faces.
class Patches {
public:
  /// `opposite`: per half-edge 3f+k, its partner (kInvalidIndex for none); `turns`:
  /// projection_turns(mesh); `whole`: whole_patches(mesh, opposite, turns). Keeps references to the
  /// mesh, `opposite` and `order`.
  Patches(const TriangleMesh& mesh, const std::vector<Index>& opposite, const std::vector<std::uint8_t>& turns,
          const std::vector<Index>& whole, std::span<const Index> order);

  /// Whether no two of the faces order[a_begin, a_end) and order[b_begin, b_end) (or, for the same
  /// range twice, of its faces) meet but where they share a corner or an edge: all of them in one
  /// whole patch, or one range alone of at most kMaxLocal faces a patch. False says nothing.
  [[nodiscard]] bool apart(Index a_begin, Index a_end, Index b_begin, Index b_end) const;
  static constexpr Index kMaxLocal = 8192;

private:
  /// Whether the faces order[begin, end) form a patch as described above.
  [[nodiscard]] bool embedded(Index begin, Index end) const;

  const TriangleMesh& mesh_;
  const std::vector<Index>& opposite_;
  std::span<const Index> order_;
  std::vector<Index> position_; // per face, its place in order
  // Per place i in order and turn bit b, the first place at or after i whose face lacks bit b
  // (order.size() for none): a range of order turns one way in b when the range ends before it.
  std::vector<std::array<Index, 6>> runs_;
  // Per place i in order, the whole patch of its face (kInvalidIndex for none), and the first place
  // at or after i whose face is in another or none.
  std::vector<Index> whole_, whole_run_;
};

} // namespace st::validate_detail
