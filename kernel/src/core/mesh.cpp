#include "st/core/mesh.h"

#include "st/core/errors.h"

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
  std::vector<Index> faces;
  if (!box.valid()) return faces;
  std::vector<std::uint8_t> beyond(mesh.vertex_count());
  for (Index v = 0; v < mesh.vertex_count(); ++v) {
    const Vec3& p = mesh.positions[v];
    unsigned c = 0;
    for (int k = 0; k < 3; ++k)
      c |= (p[k] < box.min[k] ? 1u : 0u) << (2 * k) | (p[k] > box.max[k] ? 2u : 0u) << (2 * k);
    beyond[v] = static_cast<std::uint8_t>(c);
  }
  for (Index f = 0; f < mesh.face_count(); ++f) {
    const Triangle& t = mesh.triangles[f];
    if (!(beyond[t[0]] & beyond[t[1]] & beyond[t[2]])) faces.push_back(f);
  }
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
