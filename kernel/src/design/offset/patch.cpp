#include "design/offset/patch.h"
#include "design/offset/sparse_grid.h"

#include "detail/parallel.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

namespace st::offset_detail {

Patch build_patch(const TriangleMesh& mesh, bool with_pseudo_normals) {
  Patch patch;
  patch.mesh = &mesh;
  const std::size_t nf = mesh.triangles.size();
  patch.triangles.resize(nf);
  patch.face_normals.resize(nf);
  patch.side_normals.assign(nf, {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()});
  patch.edge_of.resize(3 * nf);
  // Each triangle on its own (on all threads); the area summed in triangle order.
  std::vector<double> areas(nf);
  detail::parallel_for(nf, 4096, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t t = begin; t < end; ++t) {
      const Triangle& tri = mesh.triangles[t];
      PatchTriangle& g = patch.triangles[t];
      static_cast<TriangleGeometry&>(g) =
          triangle_geometry(mesh.positions[tri[0]], mesh.positions[tri[1]], mesh.positions[tri[2]]);
      const Vec3 n = g.ab.cross(g.ac);
      const double gram = n.squaredNorm();
      g.normal = g.degenerate ? Vec3::Zero() : Vec3(n / std::sqrt(gram));
      g.plane = g.normal.dot(g.a);
      patch.face_normals[t] = g.normal;
      if (!g.degenerate) {
        const std::array<Vec3, 3> q = {g.a, g.a + g.ab, g.a + g.ac};
        for (int k = 0; k < 3; ++k) patch.side_normals[t][k] = (q[(k + 1) % 3] - q[k]).cross(g.normal).normalized();
      }
      areas[t] = 0.5 * std::sqrt(gram);
    }
  });
  for (const double a : areas) patch.area += a;

  // Compressed rows: vertex -> triangles, edge -> triangles.
  auto build_rows = [nf](std::size_t rows, auto&& row_of, std::vector<Index>& offsets, std::vector<Index>& items) {
    offsets.assign(rows + 1, 0);
    for (std::size_t c = 0; c < 3 * nf; ++c) ++offsets[row_of(c) + 1];
    for (std::size_t r = 0; r < rows; ++r) offsets[r + 1] += offsets[r];
    items.resize(offsets[rows]);
    std::vector<Index> fill(offsets.begin(), offsets.end() - 1);
    for (std::size_t c = 0; c < 3 * nf; ++c) items[fill[row_of(c)]++] = static_cast<Index>(c / 3);
  };

  build_rows(
      mesh.positions.size(), [&](std::size_t c) { return mesh.triangles[c / 3][c % 3]; }, patch.vertex_face_offsets,
      patch.vertex_faces);

  // Edges numbered in order of first use over (triangle, corner), as a hash of their keys would: the
  // first use of each half-edge's edge is found among the triangles around its lower vertex (on all
  // threads), then the edges are numbered in one pass.
  std::vector<Index> first_use(3 * nf);
  detail::parallel_for(nf, 4096, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t t = begin; t < end; ++t)
      for (int k = 0; k < 3; ++k) {
        const Index u = mesh.triangles[t][k], v = mesh.triangles[t][(k + 1) % 3];
        const Index lo = std::min(u, v), hi = std::max(u, v);
        Index first = static_cast<Index>(3 * t + k);
        for (Index j = patch.vertex_face_offsets[lo]; j < patch.vertex_face_offsets[lo + 1] && first == 3 * t + k;
             ++j) {
          const Index g = patch.vertex_faces[j];
          if (g > t) break;
          const Triangle& o = mesh.triangles[g];
          for (int kk = 0; kk < 3; ++kk)
            if (std::min(o[kk], o[(kk + 1) % 3]) == lo && std::max(o[kk], o[(kk + 1) % 3]) == hi) {
              first = 3 * g + kk;
              break;
            }
        }
        first_use[3 * t + k] = first;
      }
  });
  std::vector<std::int32_t> edge_uses;
  std::vector<double> edge_length;
  for (std::size_t c = 0; c < 3 * nf; ++c) {
    std::int32_t id = 0;
    if (first_use[c] == c) {
      id = static_cast<std::int32_t>(edge_uses.size());
      const Triangle& tri = mesh.triangles[c / 3];
      edge_uses.push_back(0);
      edge_length.push_back((mesh.positions[tri[c % 3]] - mesh.positions[tri[(c % 3 + 1) % 3]]).norm());
    } else {
      id = patch.edge_of[first_use[c]];
    }
    ++edge_uses[id];
    patch.edge_of[c] = id;
  }
  patch.border_edge.assign(edge_uses.size(), 0);
  patch.border_vertex.assign(mesh.positions.size(), 0);
  for (std::size_t e = 0; e < edge_uses.size(); ++e)
    if (edge_uses[e] == 1) {
      patch.border_length += edge_length[e];
      patch.border_edge[e] = 1;
    }
  for (std::size_t c = 0; c < 3 * nf; ++c)
    if (patch.border_edge[patch.edge_of[c]]) {
      patch.border_vertex[mesh.triangles[c / 3][c % 3]] = 1;
      patch.border_vertex[mesh.triangles[c / 3][(c + 1) % 3]] = 1;
    }

  build_rows(
      edge_uses.size(), [&](std::size_t c) { return static_cast<Index>(patch.edge_of[c]); }, patch.edge_face_offsets,
      patch.edge_faces);

  patch.side_slack.assign(nf, {1.0f, 1.0f, 1.0f});
  detail::parallel_for(nf, 4096, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t t = begin; t < end; ++t) {
      if (patch.triangles[t].degenerate) continue;
      const Vec3& n = patch.face_normals[t];
      std::array<double, 3> lowest{}; // smallest cosine to a normal around each corner
      for (int k = 0; k < 3; ++k) {
        const Index v = mesh.triangles[t][k];
        double c = 1.0;
        for (Index j = patch.vertex_face_offsets[v]; j < patch.vertex_face_offsets[v + 1]; ++j)
          if (!patch.triangles[patch.vertex_faces[j]].degenerate)
            c = std::min(c, n.dot(patch.face_normals[patch.vertex_faces[j]]));
        lowest[k] = c;
      }
      for (int k = 0; k < 3; ++k) {
        if (patch.border_edge[patch.edge_of[3 * t + k]]) continue;
        const double c = std::min(lowest[k], lowest[(k + 1) % 3]);
        patch.side_slack[t][k] = c <= 0.0 ? 1.0f : static_cast<float>(std::sqrt(std::max(0.0, 1.0 - c * c)));
      }
    }
  });

  if (with_pseudo_normals) {
    // Gathered per edge and per vertex from their rows (triangles in ascending order, as a pass over
    // the triangles would add them): on all threads.
    patch.edge_normals.assign(edge_uses.size(), Vec3::Zero());
    patch.vertex_normals.assign(mesh.positions.size(), Vec3::Zero());
    detail::parallel_for(edge_uses.size(), 8192, [&](std::size_t, std::size_t begin, std::size_t end) {
      for (std::size_t e = begin; e < end; ++e) {
        Vec3& sum = patch.edge_normals[e];
        for (Index j = patch.edge_face_offsets[e]; j < patch.edge_face_offsets[e + 1]; ++j)
          if (!patch.triangles[patch.edge_faces[j]].degenerate) sum += patch.face_normals[patch.edge_faces[j]];
        sum = sum.squaredNorm() > 0.0 ? Vec3(sum.normalized()) : sum;
      }
    });
    detail::parallel_for(mesh.positions.size(), 8192, [&](std::size_t, std::size_t begin, std::size_t end) {
      for (std::size_t v = begin; v < end; ++v) {
        Vec3& sum = patch.vertex_normals[v];
        for (Index j = patch.vertex_face_offsets[v]; j < patch.vertex_face_offsets[v + 1]; ++j) {
          const Index t = patch.vertex_faces[j];
          if (patch.triangles[t].degenerate) continue;
          const Triangle& tri = mesh.triangles[t];
          const int k = tri[0] == v ? 0 : tri[1] == v ? 1 : 2;
          const Vec3 e1 = (mesh.positions[tri[(k + 1) % 3]] - mesh.positions[tri[k]]).normalized();
          const Vec3 e2 = (mesh.positions[tri[(k + 2) % 3]] - mesh.positions[tri[k]]).normalized();
          const double angle = std::acos(std::clamp(e1.dot(e2), -1.0, 1.0));
          sum += angle * patch.face_normals[t];
        }
        sum = sum.squaredNorm() > 0.0 ? Vec3(sum.normalized()) : sum;
      }
    });
  }
  return patch;
}

} // namespace st::offset_detail
