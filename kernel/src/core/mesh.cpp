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

std::vector<Index> faces_meeting_boxes(const TriangleMesh& mesh, std::span<const BoundingBox> boxes) {
  std::vector<BoundingBox> valid;
  for (const BoundingBox& b : boxes)
    if (b.valid()) valid.push_back(b);
  std::vector<Index> faces;
  if (valid.empty()) return faces;
  // Five boxes to a pass, six bits each in a vertex's code. A face meets box i when bits 6i .. 6i + 5
  // of its corners' common bits are all clear: folded onto bit 6i, a set bit there marks a miss.
  constexpr std::size_t kPerPass = 5;
  std::vector<std::uint32_t> beyond(mesh.vertex_count());
  std::vector<std::uint8_t> meets(valid.size() > kPerPass ? mesh.face_count() : 0, 0);
  for (std::size_t first = 0; first < valid.size(); first += kPerPass) {
    const std::size_t count = std::min(kPerPass, valid.size() - first);
    std::uint32_t all_missed = 0;
    for (std::size_t i = 0; i < count; ++i) all_missed |= 1u << (6 * i);
    for (Index v = 0; v < mesh.vertex_count(); ++v) {
      const Vec3& p = mesh.positions[v];
      std::uint32_t c = 0;
      for (std::size_t i = 0; i < count; ++i) {
        const BoundingBox& box = valid[first + i];
        for (int k = 0; k < 3; ++k)
          c |= ((p[k] < box.min[k] ? 1u : 0u) << (2 * k) | (p[k] > box.max[k] ? 2u : 0u) << (2 * k)) << (6 * i);
      }
      beyond[v] = c;
    }
    for (Index f = 0; f < mesh.face_count(); ++f) {
      const Triangle& t = mesh.triangles[f];
      std::uint32_t c = beyond[t[0]] & beyond[t[1]] & beyond[t[2]];
      c |= c >> 1;
      c |= c >> 2;
      c |= c >> 2;
      if ((c & all_missed) == all_missed) continue;
      if (meets.empty()) faces.push_back(f);
      else meets[f] = 1;
    }
  }
  if (!meets.empty())
    for (Index f = 0; f < mesh.face_count(); ++f)
      if (meets[f]) faces.push_back(f);
  return faces;
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
