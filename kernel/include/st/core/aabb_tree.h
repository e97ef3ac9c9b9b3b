#pragma once
// Axis-aligned bounding-box tree over (a subset of) the triangles of a mesh, built once and queried
// many times: closest point, first ray hit, boxes, and overlapping triangle pairs (for collision and
// self-intersection tests). A linear BVH: the triangles in the Morton order of their boxes' centres,
// each node split where its cells divide, leaves of up to 16 triangles.

#include "st/core/closest_point.h"
#include "st/core/mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <utility>
#include <vector>

namespace st {

struct ClosestPoint {
  Index face = kInvalidIndex; // mesh face index
  Vec3 point = Vec3::Zero();
  double distance = 0.0;
};

struct RayHit {
  Index face = kInvalidIndex;
  Vec3 point = Vec3::Zero();
  double t = 0.0; // hit = origin + t * direction
};

class AabbTree {
public:
  /// Tree over all triangles of `mesh`, or only over `faces` (distinct) when given. Keeps a reference
  /// to mesh.
  explicit AabbTree(const TriangleMesh& mesh, std::vector<Index> faces = {});
  /// A tree over a temporary mesh would outlive it.
  AabbTree(TriangleMesh&&, std::vector<Index> = {}) = delete;

  [[nodiscard]] bool empty() const { return faces_.empty(); }
  [[nodiscard]] const TriangleMesh& mesh() const { return mesh_; }
  /// Whether it is a tree over all of `mesh`'s faces (built on that very object): what a caller
  /// handing its tree to a function about `mesh` must give.
  [[nodiscard]] bool holds_all_of(const TriangleMesh& mesh) const {
    return &mesh_ == &mesh && faces_.size() == mesh.face_count();
  }

  /// Closest point on the indexed triangles; nullopt when the tree is empty or nothing lies within
  /// `max_distance`.
  [[nodiscard]] std::optional<ClosestPoint>
  closest_point(const Vec3& p, double max_distance = std::numeric_limits<double>::infinity()) const;

  /// Per node of up to Slabs::kMaxFaces triangles, the slab that holds them: a plane through the
  /// node's box centre across their summed normal, their greatest height over it and distance along
  /// it. A point at height h over the plane and at l from the centre along it lies at least
  /// sqrt(max(0, |h| - thickness)^2 + max(0, l - radius)^2) from them: over a finely tessellated
  /// surface tilted against the axes, far tighter than the node's box, so that a closest-point search
  /// from a distance opens a few nodes instead of a hundred. Made once for many searches.
  struct Slab {
    Vec3 centre = Vec3::Zero();
    Vec3 normal = Vec3::Zero(); // unit
    double half_thickness = 0.0;
    double radius = 0.0;
    bool valid = false; // none (a node too large, normals that cancel, coordinates that overflow): never beyond
    /// Whether every point of the slab lies farther than sqrt(best) from p (less a margin for rounding).
    [[nodiscard]] bool beyond(const Vec3& p, double best) const {
      if (!valid) return false;
      const Vec3 v = p - centre;
      const double h = normal.dot(v);
      const double across = std::max(0.0, std::abs(h) - half_thickness);
      const double along = std::max(0.0, std::sqrt(std::max(0.0, v.squaredNorm() - h * h)) - radius);
      return (across * across + along * along) * (1.0 - 1e-9) > best;
    }
  };
  /// The slabs, and what a search that starts near a face needs: each node's parent and each face's
  /// leaf. A face's own slab is its plane and the disc about its centroid that holds it (two dozen
  /// flops against an exact closest-point test's hundred: a point T over a finely tessellated surface
  /// meets dozens of faces in the leaves it opens, and the discs rule out all but those right under it).
  struct Slabs {
    static constexpr Index kMaxFaces = 32;
    const AabbTree* tree = nullptr; // the tree they were made for
    std::vector<Slab> per_node;
    std::vector<Slab> per_face; // in the tree's order (ordered_faces())
    std::vector<Index> parent;  // per node; kInvalidIndex for the root
    std::vector<Index> leaf_of; // per face of the mesh; kInvalidIndex for a face the tree does not hold
  };
  [[nodiscard]] Slabs slabs() const;

  /// closest_point(p, max_distance), passing over the nodes and faces whose slab lies beyond the best
  /// found: the same distance. Given `near_face` (a face near p: the closest of a point nearby), the
  /// search starts at its leaf and climbs, opening each sibling on the way: the nodes near the top,
  /// whose boxes hold p's ball, are then passed without a test. `slabs` must be this tree's. Of two
  /// faces equally near, either may be reported.
  [[nodiscard]] std::optional<ClosestPoint> closest_point(const Vec3& p, double max_distance, const Slabs& slabs,
                                                          Index near_face = kInvalidIndex) const;

  /// First intersection of the ray origin + t*direction, t in [t_min, t_max].
  [[nodiscard]] std::optional<RayHit> first_hit(const Vec3& origin, const Vec3& direction, double t_min = 0.0,
                                                double t_max = std::numeric_limits<double>::infinity()) const;

  /// Calls visit(face) for the triangles whose boxes, grown by `pad`, the segment origin + t *
  /// direction, t in [0, t_max], may pass through (a filter for exact tests), until visit returns
  /// true; returns whether it did.
  bool any_along(const Vec3& origin, const Vec3& direction, double t_max, double pad,
                 const std::function<bool(Index)>& visit) const;

  /// Calls visit(face) for every triangle whose box overlaps `box`.
  void for_each_in_box(const BoundingBox& box, const std::function<void(Index)>& visit) const;

  /// Whether the box of any indexed triangle overlaps `box`.
  [[nodiscard]] bool any_in_box(const BoundingBox& box) const;

  /// Calls visit(fa, fb) once for every pair of distinct triangles of this tree whose boxes overlap.
  void for_each_overlapping_pair(const std::function<void(Index, Index)>& visit) const;

  /// The pairs for_each_overlapping_pair visits, found on all threads; the same pairs in the same
  /// order whatever the number of threads.
  [[nodiscard]] std::vector<std::pair<Index, Index>> overlapping_pairs() const;

  /// The same pairs, only those for which keep(fa, fb) is true, tested on the threads that find them
  /// (keep must be safe to call from several threads): a costly test over many pairs without storing
  /// them all. The same pairs in the same order whatever the number of threads.
  [[nodiscard]] std::vector<std::pair<Index, Index>>
  overlapping_pairs(const std::function<bool(Index, Index)>& keep) const;

  /// The same pairs, passing over those within a node, or between two nodes, for which apart(a_begin,
  /// a_end, b_begin, b_end) is true (the same range twice for one node): a caller that can show that
  /// no two of the nodes' triangles, ordered_faces()[a_begin, a_end) and [b_begin, b_end), meet but
  /// where they share corners or edges. Asked from the top down for the pairs of nodes the search
  /// reaches whose boxes overlap, on the threads that find the pairs (apart must be safe to call from
  /// several; the first levels are split into tasks for them without asking, but for a node of at
  /// most kMaxApart triangles alone); the same pairs in the same order whatever the number of threads. Also passed
  /// over: the pairs of triangles that cannot meet because the corners of one lie on one side of the other's plane
  /// (decided with a margin far wider than the rounding, so never wrongly): a long sliver, whose box spans hundreds of
  /// small triangles', reaches the caller's test only with the few its plane passes through.
  using Apart = std::function<bool(Index, Index, Index, Index)>;
  [[nodiscard]] std::vector<std::pair<Index, Index>> overlapping_pairs(const std::function<bool(Index, Index)>& keep,
                                                                       const Apart& apart) const;
  static constexpr Index kMaxApart = 8192;

  /// The triangles in the tree's order: a node's are a range of it.
  [[nodiscard]] std::span<const Index> ordered_faces() const { return faces_; }

  /// Calls visit(fa, fb) for every triangle fa of this tree and fb of `other` whose boxes overlap.
  void for_each_overlapping_pair(const AabbTree& other, const std::function<void(Index, Index)>& visit) const;

  /// The area-weighted normal of the surface within `radius` of `p`: the sum of the (area-scaled,
  /// outward) normals of the triangles that come within `radius`, and their total area.
  struct AreaNormal {
    Vec3 sum = Vec3::Zero();
    double area = 0.0;
  };
  [[nodiscard]] AreaNormal area_normal_near(const Vec3& p, double radius) const;

private:
  /// A box in single precision rounded outwards, so that it holds the double box it was made from:
  /// half the memory of a BoundingBox (more of the tree in cache), and only ever a filter before the
  /// callers' exact tests, which decide.
  struct FloatBox {
    std::array<float, 3> min, max;
    static FloatBox around(const BoundingBox& b);
    void extend(const FloatBox& o) {
      for (int k = 0; k < 3; ++k) {
        min[k] = std::min(min[k], o.min[k]);
        max[k] = std::max(max[k], o.max[k]);
      }
    }
    [[nodiscard]] bool overlaps(const FloatBox& o) const {
      return min[0] <= o.max[0] && o.min[0] <= max[0] && min[1] <= o.max[1] && o.min[1] <= max[1] &&
             min[2] <= o.max[2] && o.min[2] <= max[2];
    }
    [[nodiscard]] bool overlaps(const BoundingBox& o) const {
      for (int k = 0; k < 3; ++k)
        if (!(double(min[k]) <= o.max[k] && o.min[k] <= double(max[k]))) return false;
      return true;
    }
    [[nodiscard]] double diagonal() const {
      double s = 0.0;
      for (int k = 0; k < 3; ++k) s += (double(max[k]) - double(min[k])) * (double(max[k]) - double(min[k]));
      return std::sqrt(s);
    }
  };
  struct Node {
    FloatBox box;
    Index left = kInvalidIndex; // child nodes, or kInvalidIndex for a leaf
    Index right = kInvalidIndex;
    Index begin = 0; // the range in faces_ under it
    Index end = 0;
  };
  static constexpr Index kLeafSize = 16;
  /// Whether the corners of face b all lie strictly on one side of face a's plane, or a's of b's: the
  /// two triangles do not meet. Each plane as computed, widened by its spread over its own corners
  /// and by `margin` times its normal's 1-norm (see plane_margin). False whenever a corner is not a
  /// number.
  [[nodiscard]] bool apart_by_planes(Index a, Index b, double margin) const;
  /// The margin apart_by_planes needs: 1e-12 of the mesh's largest coordinate (plus 1e-300 for
  /// products that underflow), over a thousand times the rounding of a dot product of a computed
  /// normal with a corner; 0 (nothing is then passed over) when a coordinate is not finite or
  /// exceeds 1e60.
  [[nodiscard]] double plane_margin() const;
  /// Appends the subtree over faces_[begin, end) (their Morton codes sorted in `codes`); returns its root.
  Index build(const std::vector<std::uint64_t>& codes, Index begin, Index end);
  /// closest_point's search, over the slabs when given, from near_face's leaf up when it is one of the
  /// tree's (and there are slabs). Defined in aabb_tree.cpp.
  [[nodiscard]] std::optional<ClosestPoint> nearest(const Vec3& p, double max_distance, const Slabs* slabs,
                                                    Index near_face) const;
  /// Calls leaf(face) for the triangles in the nodes whose boxes, grown by `pad`, the ray meets for t
  /// in [t_min, t_max] (t_max read at every node: a leaf may shorten it), until leaf returns true;
  /// returns whether it did. Defined in aabb_tree.cpp, used there only.
  template <class Leaf> bool along(const Vec3& origin, const Vec3& direction, double t_min, const double& t_max,
                                   double pad, Leaf&& leaf) const;
  /// Calls leaf(face) for the triangles whose boxes overlap `box` until it returns true; returns
  /// whether it did. Defined in aabb_tree.cpp, used there only.
  template <class Leaf> bool in_box(const BoundingBox& box, Leaf&& leaf) const;
  /// The node pairs self_pairs(a, b) recurses into (into[0..count)): -1 when the boxes miss, 0 for two
  /// leaves (their triangles are compared), else 2 or 3.
  int split_pair(Index a, Index b, std::array<std::pair<Index, Index>, 3>& into) const;
  /// Calls visit(fa, fb) for the pairs of triangles under nodes a and b whose boxes overlap, but those
  /// within or between nodes apart passes over (apart may be null). Defined in aabb_tree.cpp, used
  /// there only (the visitor inlined: a self-intersection check visits a million pairs).
  /// With a `plane_margin` above 0, also passing over the pairs of triangles without a common corner
  /// that apart_by_planes tells apart.
  template <class Visit>
  void self_pairs(Index a, Index b, Visit& visit, const Apart* apart = nullptr, double plane_margin = 0.0) const;
  void cross_pairs(Index a, const AabbTree& other, Index b, const std::function<void(Index, Index)>& visit) const;

  const TriangleMesh& mesh_;
  std::vector<Index> faces_;
  std::vector<FloatBox> face_boxes_; // parallel to faces_
  std::vector<Node> nodes_;
};

} // namespace st
