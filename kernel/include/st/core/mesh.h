#pragma once
// The flat indexed triangle mesh used for I/O, bindings and as the input and output of every
// algorithm: positions (#V by 3, double, mm) and triangles (#F by 3, 32-bit vertex indices,
// counter-clockwise seen from outside). Topology (adjacency, boundary loops) is derived from it on
// demand, see topology.h.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

namespace st {

using Vec3 = Eigen::Vector3d;
using Index = std::uint32_t;
inline constexpr Index kInvalidIndex = std::numeric_limits<Index>::max();
using Triangle = std::array<Index, 3>;

struct TriangleMesh {
  std::vector<Vec3> positions;
  std::vector<Triangle> triangles;

  [[nodiscard]] Index vertex_count() const { return static_cast<Index>(positions.size()); }
  [[nodiscard]] Index face_count() const { return static_cast<Index>(triangles.size()); }
  [[nodiscard]] bool empty() const { return triangles.empty(); }
};

struct BoundingBox {
  Vec3 min = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 max = Vec3::Constant(-std::numeric_limits<double>::infinity());

  void extend(const Vec3& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  void extend(const BoundingBox& b) {
    min = min.cwiseMin(b.min);
    max = max.cwiseMax(b.max);
  }
  [[nodiscard]] bool valid() const { return (min.array() <= max.array()).all(); }
  [[nodiscard]] Vec3 size() const { return max - min; }
  [[nodiscard]] Vec3 center() const { return 0.5 * (min + max); }
  [[nodiscard]] double diagonal() const { return valid() ? size().norm() : 0.0; }
  [[nodiscard]] BoundingBox inflated(double d) const { return {min - Vec3::Constant(d), max + Vec3::Constant(d)}; }
  [[nodiscard]] bool contains(const Vec3& p) const {
    return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
  }
  [[nodiscard]] bool overlaps(const BoundingBox& b) const {
    return (min.array() <= b.max.array()).all() && (b.min.array() <= max.array()).all();
  }
};

/// Bounding box of all positions (also the unused ones).
BoundingBox bounding_box(const TriangleMesh& mesh);

/// The faces whose boxes meet `box` (sides included), ascending; none when `box` is empty. Each vertex
/// gets the sides of `box` it lies beyond (bit 2k below box.min[k], bit 2k + 1 above box.max[k]); a face's
/// box misses `box` exactly when its three corners' codes share a bit, so a pass over the faces reads three
/// codes each (the faces near a part of a large mesh).
std::vector<Index> faces_meeting_box(const TriangleMesh& mesh, const BoundingBox& box);

/// The faces whose boxes meet at least one of `boxes` (sides included), ascending; the empty boxes meet
/// none. The same codes, six bits a box, five boxes to a vertex's 32 bits and to a pass: for parts spread over a
/// large mesh, where the box around them all would hold most of its faces.
std::vector<Index> faces_meeting_boxes(const TriangleMesh& mesh, std::span<const BoundingBox> boxes);

/// A box in a frame of its own: the points p with |axes.row(k) . (p - centre)| <= half[k], k = 0, 1, 2.
struct FramedBox {
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity(); ///< rows: orthonormal axes
  Vec3 centre = Vec3::Zero();
  Vec3 half = Vec3::Zero();
};

/// The faces whose corners, in the frame of at least one of `boxes`, do not all lie beyond one side of
/// it, ascending (the same codes): every face that meets one of them is among them, but for one whose
/// corners' coordinates in the frame round across a side (grow the boxes a little for that). For a
/// long tilted part, whose axis-aligned box holds far more of a mesh than the part comes near.
std::vector<Index> faces_near_framed_boxes(const TriangleMesh& mesh, std::span<const FramedBox> boxes);

/// Bounding box of the three corners of triangle `f`.
inline BoundingBox triangle_box(const TriangleMesh& mesh, Index f) {
  BoundingBox box;
  for (Index v : mesh.triangles[f]) box.extend(mesh.positions[v]);
  return box;
}

/// Unnormalised normal (twice the area times the unit normal) of triangle `f`.
inline Vec3 triangle_normal(const TriangleMesh& mesh, Index f) {
  const Triangle& t = mesh.triangles[f];
  const Vec3& a = mesh.positions[t[0]];
  return (mesh.positions[t[1]] - a).cross(mesh.positions[t[2]] - a);
}

/// Sum of triangle areas, mm^2.
double surface_area(const TriangleMesh& mesh);

/// Signed enclosed volume, mm^3 (positive for a closed, outward-oriented mesh).
double signed_volume(const TriangleMesh& mesh);

/// Mean edge length, mm (0 for an empty mesh).
double mean_edge_length(const TriangleMesh& mesh);

/// Area-weighted vertex normals, unit length (zero for unused vertices).
std::vector<Vec3> vertex_normals(const TriangleMesh& mesh);

/// The sub-mesh made of the listed faces, with only the vertices they use (in first-use order).
/// `vertex_map`, when given, receives for each new vertex its index in `mesh`.
TriangleMesh submesh(const TriangleMesh& mesh, const std::vector<Index>& faces,
                     std::vector<Index>* vertex_map = nullptr);

/// Throws InvalidInput naming the first non-finite coordinate or out-of-range index.
void check_mesh(const TriangleMesh& mesh, const std::string& what);

} // namespace st
