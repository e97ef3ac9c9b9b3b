#pragma once
// The Boolean operation's working parts (private to st/boolean/boolean.h): one corefinement of two
// closed meshes (corefinement.cpp; its short curve edges collapsed in collapse.cpp) and the regions
// of the operands it looks at (operand_regions.cpp).

#include "st/boolean/boolean.h"
#include "st/boolean/face_split.h"
#include "st/core/mesh.h"

#include <Eigen/Core>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <array>
#include <chrono>
#include <cmath>
#include <numeric>
#include <optional>
#include <unordered_map>
#include <unordered_set>

namespace st::boolean_detail {

// Thrown inside an attempt when a contact is not in general position (or rounding made it so): the
// attempt is repeated with the second operand moved.
struct Degenerate {
  std::string why;
};

inline std::uint64_t edge_key(Index u, Index v) {
  return u < v ? (std::uint64_t{u} << 32) | v : (std::uint64_t{v} << 32) | u;
}

struct PointKey {
  std::uint64_t edge; // the crossing edge, as its (sorted) vertex pair in the shared id space
  Index face;         // the crossed face, in the shared face id space (B faces after A's)
  bool operator==(const PointKey&) const = default;
};
struct PointKeyHash {
  std::size_t operator()(const PointKey& k) const {
    return std::hash<std::uint64_t>()(k.edge * 0x9E3779B97F4A7C15ull ^ k.face);
  }
};

struct FaceWork {
  std::vector<FacePoint> points;
  std::vector<std::pair<Index, Index>> segments;
  CutCorner cut; // a corner the curve cuts off closer than the coordinates resolve
};

struct SeamSegment {
  Index p, q;   // shared point ids
  Index fa, fb; // the faces of A and B that meet along it
};

struct Piece {
  Triangle t;   // shared vertex ids
  Index source; // face of its operand
};

// What is known about one component of an operand's pieces.
struct Verdict {
  double inside_confidence = 0.0;  // largest side-test margin voting "inside the other operand"
  double outside_confidence = 0.0; // ... voting "outside"
  bool exterior = false;           // joined to faces far from the other operand: outside
  bool on_seat_curve = false;      // bounded by curves on seat faces
  bool on_other_curve = false;     // bounded by curves on other faces
  bool all_seat = true;            // every piece lies on a seat face
  bool seat_keep = false;          // first operand, inside the second, kept as the seat (union)
  bool seat_drop = false;          // second operand, outside the first, dropped beyond the seat (union)
  int inside = -1;                 // decision: 1 inside, 0 outside
};

// An oriented box around one connected component (operand_regions.cpp).
// axis-aligned box for a quick first test. A tilted cylinder's oriented box is tight where its
// axis-aligned box is mostly empty, so far fewer faces of the other operand count as near.
struct OrientedBox {
  BoundingBox world;
  Eigen::Matrix3d axes; // rows: unit axes
  Vec3 centre = Vec3::Zero();
  Vec3 half = Vec3::Zero();

  bool overlaps(const std::array<Vec3, 3>& t, double margin) const {
    Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
    for (const Vec3& p : t) {
      const Vec3 q = axes * (p - centre);
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
    return (lo.array() <= half.array() + margin).all() && (hi.array() >= -half.array() - margin).all();
  }
};

/// The oriented boxes of the connected components of `mesh`.
std::vector<OrientedBox> component_boxes(const TriangleMesh& mesh);

/// The faces of `mesh` that may meet one of the boxes.
std::vector<Index> faces_near(const TriangleMesh& mesh, const std::vector<OrientedBox>& boxes);

/// Appends the faces of `m` far from the other operand (kept whole: their `near_slot` is kInvalidIndex)
/// to the result, from_b and source_face alongside, their corners numbered through `map` (one entry per
/// vertex of m: kInvalidIndex until the vertex is added, its id in the result after), in reverse
/// orientation when asked.
void append_far_faces(const TriangleMesh& m, const std::vector<Index>& near_slot, Index* map, bool reverse,
                      std::uint8_t from_b, BooleanResult& result);

/// Across an edge of the intersection curve an operand's surface passes from inside the other operand
/// to outside (the contacts are in general position): a component no side test decided, such as a
/// strip between two curves whose corners are all curve points, takes the other side from a decided
/// neighbour. `across` holds the components on the two sides of each curve edge.
void decide_across_curve(const std::vector<std::pair<Index, Index>>& across, std::vector<Verdict>& verdicts);

/// Parity of ray crossings from p against a closed mesh; tries other directions when a ray grazes an
/// edge (throws Degenerate when every one does). Used only for pieces no intersection curve reaches.
bool inside_by_rays(const Vec3& p, const TriangleMesh& mesh);

/// Throws Degenerate unless every edge of the `fresh` and `unchanged` faces of the assembled result
/// meets exactly one face across it, the other way round (a piece, or a face far from the other
/// operand beside the pieces): verdicts that disagree across a curve leave a hole or a doubled sheet.
void check_closed_at_curve(const TriangleMesh& out, const std::vector<Index>& fresh,
                           const std::vector<Index>& unchanged);

/// Where a vertex of an assembled result comes from: an operand's vertex, or a point of the
/// intersection curve where an edge of the first (second) operand crosses a face of the other.
enum class VertexOrigin : std::uint8_t { first, second, curve_on_first_edge, curve_on_second_edge };

/// Collapses the edges of `fresh` faces shorter than `min_length` that end at a curve point
/// (collapse.cpp); faces it moves join `fresh` (and leave `unchanged`) so that the final check sees
/// them. Returns the number of edges collapsed.
std::size_t collapse_short_edges(BooleanResult& r, const std::vector<VertexOrigin>& origin, double min_length,
                                 std::vector<Index>& fresh, std::vector<Index>& unchanged);

/// After rounding (and collapsing), the `fresh` faces of an assembled result must still be proper
/// triangles that cross neither each other nor the `unchanged` faces around them: throws Degenerate
/// when they do (with `debug`, the two faces to stderr). In collapse.cpp.
void check_fresh(const TriangleMesh& out, const std::vector<Index>& fresh, const std::vector<Index>& unchanged,
                 bool debug);

/// One corefinement of `a` and `b` (points closer than `short_edge` on the curve merged); `a_box` is
/// a's bounding box (the caller has it: a large operand is not gone through again for it). Throws
/// Degenerate when a contact is not in general position. With options.round_to_float the operands'
/// coordinates are float32 already (mesh_boolean rounds them): only the new points are rounded here.
BooleanResult corefine(const TriangleMesh& a, const BoundingBox& a_box, const TriangleMesh& b, BooleanOp op,
                       const BooleanOptions& options, double short_edge);

} // namespace st::boolean_detail
