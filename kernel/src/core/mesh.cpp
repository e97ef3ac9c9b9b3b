#include "st/core/mesh.h"

#include "st/core/errors.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace st {

BoundingBox bounding_box(const TriangleMesh& mesh) {
  BoundingBox box;
  for (const Vec3& p : mesh.positions) box.extend(p);
  return box;
}

double surface_area(const TriangleMesh& mesh) {
  double area = 0.0;
  for (Index f = 0; f < mesh.face_count(); ++f) area += triangle_normal(mesh, f).norm();
  return 0.5 * area;
}

double signed_volume(const TriangleMesh& mesh) {
  // Relative to the box centre, for accuracy far from the origin.
  const Vec3 c = bounding_box(mesh).center();
  double volume = 0.0;
  for (const Triangle& t : mesh.triangles) {
    const Vec3 a = mesh.positions[t[0]] - c;
    const Vec3 b = mesh.positions[t[1]] - c;
    const Vec3 d = mesh.positions[t[2]] - c;
    volume += a.dot(b.cross(d));
  }
  return volume / 6.0;
}

double mean_edge_length(const TriangleMesh& mesh) {
  if (mesh.empty()) return 0.0;
  double sum = 0.0;
  for (const Triangle& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) sum += (mesh.positions[t[(k + 1) % 3]] - mesh.positions[t[k]]).norm();
  return sum / (3.0 * static_cast<double>(mesh.triangles.size()));
}

std::vector<Vec3> vertex_normals(const TriangleMesh& mesh) {
  std::vector<Vec3> normals(mesh.positions.size(), Vec3::Zero());
  for (Index f = 0; f < mesh.face_count(); ++f) {
    const Vec3 n = triangle_normal(mesh, f);
    for (Index v : mesh.triangles[f]) normals[v] += n;
  }
  for (Vec3& n : normals) {
    const double len = n.norm();
    if (len > 0.0) n /= len;
  }
  return normals;
}

std::vector<Index> faces_meeting_box(const TriangleMesh& mesh, const BoundingBox& box) {
  return faces_meeting_boxes(mesh, std::span<const BoundingBox>(&box, 1));
}

namespace {

// The faces not beyond one side of at least one of `count` boxes, ascending, where code(i, p) gives the
// sides of box i that point p lies beyond (bit 2k below its lower side along axis k, 2k + 1 above its
// upper side). Five boxes to a pass, six bits each in a vertex's code: a face is beyond box i when
// bits 6i .. 6i + 5 of its corners' common bits are not all clear; folded onto bit 6i, a set bit there
// marks that.
template <class Code>
std::vector<Index> faces_not_beyond(const TriangleMesh& mesh, std::size_t count, const Code& code) {
  std::vector<Index> faces;
  if (count == 0) return faces;
  constexpr std::size_t kPerPass = 5;
  std::vector<std::uint32_t> beyond(mesh.vertex_count());
  std::vector<std::uint8_t> meets(count > kPerPass ? mesh.face_count() : 0, 0);
  for (std::size_t first = 0; first < count; first += kPerPass) {
    const std::size_t here = std::min(kPerPass, count - first);
    std::uint32_t all_beyond = 0;
    for (std::size_t i = 0; i < here; ++i) all_beyond |= 1u << (6 * i);
    for (Index v = 0; v < mesh.vertex_count(); ++v) {
      std::uint32_t c = 0;
      for (std::size_t i = 0; i < here; ++i) c |= code(first + i, mesh.positions[v]) << (6 * i);
      beyond[v] = c;
    }
    for (Index f = 0; f < mesh.face_count(); ++f) {
      const Triangle& t = mesh.triangles[f];
      std::uint32_t c = beyond[t[0]] & beyond[t[1]] & beyond[t[2]];
      c |= c >> 1;
      c |= c >> 2;
      c |= c >> 2;
      if ((c & all_beyond) == all_beyond) continue;
      if (meets.empty()) faces.push_back(f);
      else meets[f] = 1;
    }
  }
  if (!meets.empty())
    for (Index f = 0; f < mesh.face_count(); ++f)
      if (meets[f]) faces.push_back(f);
  return faces;
}

// The sides of [lo, hi] that the coordinates q lie beyond, as faces_not_beyond codes them.
template <class Q, class L, class H> std::uint32_t sides_beyond(const Q& q, const L& lo, const H& hi) {
  std::uint32_t c = 0;
  for (int k = 0; k < 3; ++k) c |= ((q[k] < lo[k] ? 1u : 0u) | (q[k] > hi[k] ? 2u : 0u)) << (2 * k);
  return c;
}

} // namespace

std::vector<Index> faces_meeting_boxes(const TriangleMesh& mesh, std::span<const BoundingBox> boxes) {
  std::vector<BoundingBox> valid;
  for (const BoundingBox& b : boxes)
    if (b.valid()) valid.push_back(b);
  return faces_not_beyond(mesh, valid.size(),
                          [&](std::size_t i, const Vec3& p) { return sides_beyond(p, valid[i].min, valid[i].max); });
}

std::vector<Index> faces_near_framed_boxes(const TriangleMesh& mesh, std::span<const FramedBox> boxes) {
  return faces_not_beyond(mesh, boxes.size(), [&](std::size_t i, const Vec3& p) {
    const FramedBox& b = boxes[i];
    const Vec3 q = b.axes * (p - b.centre);
    return sides_beyond(q, -b.half, b.half);
  });
}

TriangleMesh submesh(const TriangleMesh& mesh, const std::vector<Index>& faces, std::vector<Index>* vertex_map) {
  TriangleMesh out;
  std::vector<Index> inverse;
  out.triangles.reserve(faces.size());
  // Vertices numbered in the order the faces first use them; a table over all of the mesh's vertices
  // when the faces are a good part of it, a hash map when they are a few.
  auto copy = [&](auto& remap, auto&& slot) {
    for (Index f : faces) {
      Triangle t{};
      for (int k = 0; k < 3; ++k) {
        const Index v = mesh.triangles[f][k];
        Index& to = slot(remap, v);
        if (to == kInvalidIndex) {
          to = static_cast<Index>(out.positions.size());
          out.positions.push_back(mesh.positions[v]);
          inverse.push_back(v);
        }
        t[k] = to;
      }
      out.triangles.push_back(t);
    }
  };
  if (16 * faces.size() >= mesh.vertex_count()) {
    std::vector<Index> remap(mesh.vertex_count(), kInvalidIndex);
    out.positions.reserve(std::min<std::size_t>(mesh.vertex_count(), 3 * faces.size()));
    copy(remap, [](std::vector<Index>& r, Index v) -> Index& { return r[v]; });
  } else {
    std::unordered_map<Index, Index> remap;
    remap.reserve(faces.size());
    copy(remap, [](std::unordered_map<Index, Index>& r, Index v) -> Index& {
      return r.try_emplace(v, kInvalidIndex).first->second;
    });
  }
  if (vertex_map) *vertex_map = std::move(inverse);
  return out;
}

void check_mesh(const TriangleMesh& mesh, const std::string& what) {
  for (Index v = 0; v < mesh.vertex_count(); ++v)
    if (!mesh.positions[v].allFinite())
      throw InvalidInput(what + ": vertex " + std::to_string(v) + " has a non-finite coordinate");
  for (Index f = 0; f < mesh.face_count(); ++f)
    for (Index v : mesh.triangles[f])
      if (v >= mesh.vertex_count())
        throw InvalidInput(what + ": triangle " + std::to_string(f) + " refers to vertex " + std::to_string(v) +
                           " but there are only " + std::to_string(mesh.vertex_count()) + " vertices");
}

} // namespace st
