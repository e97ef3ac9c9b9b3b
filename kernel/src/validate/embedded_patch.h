#pragma once
// Patches of a mesh that cannot cross themselves (private to check_solid, st/validate/validate.h): the
// self-intersection check passes over the pairs of faces within such a patch instead of testing them.
//
// A patch whose faces all turn the same way when projected along one axis, and whose border (its
// half-edges without a partner in the patch) is one closed loop that projects to a simple polygon,
// projects one to one onto that axis plane: over a point off the projected edges, the number of its
// faces is the winding number of the projected border about the point (every face counts +1), and a
// simple polygon winds 0 or 1 times. Two of its faces therefore meet only where they share a corner or
// an edge. (Volino and Magnenat-Thalmann's normal-cone test for self-collision, made exact: the turns
// and the polygon's crossings are decided by orient2d on coordinates dropped, not rounded.)

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

/// The patches of a mesh that are ranges of `order` (the faces of a tree, in its order), for
/// check_solid to ask about its tree's nodes.
class Patches {
public:
  /// `opposite`: per half-edge 3f+k, its partner (kInvalidIndex for none); `turns`:
  /// projection_turns(mesh). Keeps references to all four.
  Patches(const TriangleMesh& mesh, const std::vector<Index>& opposite, const std::vector<std::uint8_t>& turns,
          std::span<const Index> order);

  /// Whether the faces order[begin, end) form a patch as described above: no two of them meet but
  /// where they share a corner or an edge. False says nothing.
  [[nodiscard]] bool embedded(Index begin, Index end) const;

private:
  const TriangleMesh& mesh_;
  const std::vector<Index>& opposite_;
  std::span<const Index> order_;
  std::vector<Index> position_; // per face, its place in order
  // Per place i in order and turn bit b, the first place at or after i whose face lacks bit b
  // (order.size() for none): a range of order turns one way in b when the range ends before it.
  std::vector<std::array<Index, 6>> runs_;
};

} // namespace st::validate_detail
