#pragma once
// Removal check: whether a finished guide, moved off the bone against its insertion direction d by up
// to a distance L (20 mm), meets the bone on the way.
//
// Method. The guide G moving by t * (-d) meets the bone B for some t in (0, L] exactly when the solid
// swept by one of G's triangles meets one of B's, and two triangles in translation first meet
// vertex-on-face or edge-on-edge. So three families of exact segment tests, each after a box filter
// on an AABB tree:
//   - every guide vertex's path, the segment from it along -d by L, against the bone's triangles;
//   - every bone vertex near the guide, along +d by L (the guide's motion seen from the bone), against
//     the guide's triangles;
//   - every bone edge near a guide edge against the parallelogram that guide edge sweeps (its two
//     triangles).
// Of a guide moving as a whole (SweepStart::shrunk) only the edges where its surface turns from facing
// the way off to facing back (within 1e-6 rad; and every border edge) sweep the boundary of the solid it
// sweeps; an edge between two faces facing the same way sweeps inside it, as the surface there is a
// height field across the way. The boundary is then the guide at the start, the guide at the end of the
// way (of a closed guide, its faces facing the way off), those edges' parallelograms and the paths of
// their ends, so a fourth family replaces the other edges: the guide's faces at the end of the way
// against the bone's triangles (exact triangle-triangle tests); and the first family keeps only the
// vertices where the surface turns (a vertex with every face around it facing one way moves inside the
// solid). A bone triangle the guide sweeps over crosses that boundary (family 3 or 4, or a path of
// family 1) or lies inside (family 2). The block-out's per-face question (SweepStart::raised) keeps
// every edge and every vertex, so that each face answers for its own prism.
// Boxes cull before the tests: only the corners and edges of guide faces whose box, swept by L off
// the bone (and grown by the lifts), meets a bone triangle's box; only bone vertices of faces whose box,
// swept by L towards the guide, meets a guide triangle's box; and a bone edge only when its box meets
// the box of the parallelogram. A culled feature's path lies outside every box it could meet. Per
// face, the guide's faces and vertex paths read the bone's boxes in the frame of the way off, from a
// grid of columns along it over the bone's faces in the box the guide sweeps: a path is then a point
// of the plane across the way, and the bone's faces it can cross are those of one cell (most paths
// start on the bone, where an axis-aligned tree's boxes rise across them). A guide moving as a whole
// has few such paths, none from where it rests on the bone: they, and its faces' boxes, read the
// bone's tree.
// A segment crosses a triangle when its ends lie strictly on either side of the triangle's plane
// (orient3d, not zero) and the line meets the closed triangle (three orient3d of one sign).
// Contact is not blocking: the bone is first shrunk by a lift along its vertex normals (1 um, or
// 2^-20 of its largest coordinate when that is more) and the guide starts a lift along its way off,
// so a guide resting on the bone, or sliding along a wall parallel to d, is separated from it; what
// the exact tests then find reaches deeper than the lift. A bone vertex the guide copies (zero
// clearance; a rim through a bone vertex) touches the guide there and is left to the other families,
// as are bone edges from such a vertex against the guide edges from it. The lift is far below what a
// printer resolves (25-100 um) and above the rounding of the files read and written (float32: 2^-24
// of a coordinate, 0.012 um at 200 mm), and above the fraction of a micrometre by which scanned bone
// beyond the rim can lean over the guide's last face. Blocking places are reported on the guide.

#include "st/core/aabb_tree.h"
#include "st/core/mesh.h"
#include "st/core/topology.h"

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace st {

struct RemovalReport {
  bool removable = true;
  double distance = 0.0;                   ///< how far the guide was moved, mm
  std::size_t blocked_features = 0;        ///< guide vertices, bone vertices and edge pairs that meet
  std::vector<Vec3> blocking;              ///< where the guide meets the bone (at most 20 places, 2 mm apart)
  std::vector<std::uint8_t> blocked_faces; ///< per guide face: 1 where it meets the bone on the way off
};

/// How the moving mesh starts: a guide starts a lift along its way off (it may rest on the bone); a
/// part of the bone's own surface is also raised by the lift along its normals (to ask which of its faces the bone
/// hides along the direction: the block-out's exact visibility, blockout.h).
enum class SweepStart { shrunk, raised };

/// The removal check's tests against one bone, prepared once (the bone shrunk by the lift) for
/// many meshes: the block-out asks it about each fill it makes.
class SweepTest {
public:
  /// Keeps a reference to the tree and to `topology`, the bone's faces around each vertex (built here
  /// when null).
  explicit SweepTest(const AabbTree& bone, const MeshTopology* topology = nullptr);
  /// check_removal(bone, mesh, direction, distance, start) with the bone prepared; `mesh_tree`, a
  /// tree over all of mesh's faces when the caller has one (built here when null).
  RemovalReport operator()(const TriangleMesh& mesh, const Vec3& direction, double distance,
                           SweepStart start = SweepStart::shrunk, const AabbTree* mesh_tree = nullptr) const;

private:
  /// Bone vertex v shrunk by the lift along its normal: made the first time a test reads it (on any
  /// thread), so that a sweep costs what it reaches of the bone, not the whole bone.
  const Vec3& shrunk(Index v) const;

  const AabbTree& bone_;
  std::optional<MeshTopology> own_topology_;
  const MeshTopology& topology_;
  std::unique_ptr<Vec3[]> shrunk_;                     // valid where state_ says made
  std::unique_ptr<std::atomic<std::uint8_t>[]> state_; // per vertex: not made, being made, made
  double lift_ = 0.0;
};

/// Moves `guide` along -`direction` (the insertion direction, onto the bone; need not be unit) by up
/// to `distance` mm and reports where it meets `bone`. Throws InvalidInput for a zero direction or a
/// distance that is not > 0.
RemovalReport check_removal(const AabbTree& bone, const TriangleMesh& guide, const Vec3& direction,
                            double distance = 20.0, SweepStart start = SweepStart::shrunk);

} // namespace st
