#pragma once
// Fixtures built in code and assertion helpers for the kernel tests.

#include "st/io/case_file.h"
#include "st/core/errors.h"
#ifdef ST_HAVE_OCCT
#include "st/occt/occt_text.h"
#endif
#include "st/core/aabb_tree.h"
#include "st/core/mesh.h"
#include "st/validate/validate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>
#include <map>
#include <string>

namespace st::test {

/// Icosphere of the given radius: an icosahedron subdivided `levels` times (20 * 4^levels triangles).
inline TriangleMesh make_icosphere(double radius, int levels, const Vec3& centre = Vec3::Zero()) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  TriangleMesh m;
  m.positions = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                 {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  m.triangles = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                 {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<Index, Index>, Index> mid;
    auto midpoint = [&](Index a, Index b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      m.positions.push_back(0.5 * (m.positions[a] + m.positions[b]));
      return mid[key] = static_cast<Index>(m.positions.size() - 1);
    };
    std::vector<Triangle> next;
    for (const Triangle& tri : m.triangles) {
      const Index a = midpoint(tri[0], tri[1]), b = midpoint(tri[1], tri[2]), c = midpoint(tri[2], tri[0]);
      next.push_back({tri[0], a, c});
      next.push_back({tri[1], b, a});
      next.push_back({tri[2], c, b});
      next.push_back({a, b, c});
    }
    m.triangles = std::move(next);
  }
  for (Vec3& p : m.positions) p = centre + radius * p.normalized();
  return m;
}

/// A patch over the parameter square [u0, u1] x [v0, v1], n x n quads with alternating diagonals,
/// two triangles each, counter-clockwise in (u, v): the normal is d/du x d/dv.
inline TriangleMesh make_grid_patch(int n, double u0, double u1, double v0, double v1,
                                    const std::function<Vec3(double, double)>& map) {
  TriangleMesh mesh;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) mesh.positions.push_back(map(u0 + (u1 - u0) * i / n, v0 + (v1 - v0) * j / n));
  auto id = [n](int i, int j) { return static_cast<Index>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if ((i + j) % 2 == 0) {
        mesh.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
        mesh.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      } else {
        mesh.triangles.push_back({id(i, j), id(i + 1, j), id(i, j + 1)});
        mesh.triangles.push_back({id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
      }
    }
  return mesh;
}

/// Height field z = f(x, y) over [x0, x1] x [y0, y1], n x n quads split in two, normals up.
template <class F> TriangleMesh make_height_field(double x0, double x1, double y0, double y1, int n, F f) {
  TriangleMesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = x0 + (x1 - x0) * i / n, y = y0 + (y1 - y0) * j / n;
      m.positions.emplace_back(x, y, f(x, y));
    }
  auto id = [&](int i, int j) { return static_cast<Index>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return m;
}

/// The faces of `mesh` whose centres pass `keep`, as a mesh (all positions kept).
inline TriangleMesh faces_where(const TriangleMesh& mesh, const std::function<bool(const Vec3&)>& keep) {
  TriangleMesh out;
  out.positions = mesh.positions;
  for (const Triangle& t : mesh.triangles)
    if (keep((mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) / 3.0)) out.triangles.push_back(t);
  return out;
}

/// The project's examples folder (cases, meshes, plans).
inline std::string examples_dir() { return ST_EXAMPLES_DIR; }

/// The options of a case file with its labels' outlines from the font (OpenCASCADE); a build without
/// OpenCASCADE leaves the labels out.
inline TemplateOptions case_options(const CaseFile& c) {
  TemplateOptions o = template_options(c);
#ifdef ST_HAVE_OCCT
  fill_label_outlines(o.labels);
#else
  o.labels.clear();
#endif
  return o;
}

/// The build's test-output folder (made if missing), for files tests write and CI keeps.
inline std::string output_dir() {
  std::filesystem::create_directories(ST_TEST_OUTPUT_DIR);
  return ST_TEST_OUTPUT_DIR;
}

/// A fresh folder of a test's own: <output>/<group>/<name>, emptied.
inline std::filesystem::path scratch_dir(const std::string& group, const std::string& name) {
  const std::filesystem::path dir = std::filesystem::path(output_dir()) / group / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

/// Writes `text` to `path` as it is; returns the path.
inline std::string write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
  return path.string();
}

/// The message of the exception of type E that `f` throws (a failure when it throws none).
template <class E, class F> std::string message_of(F&& f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  }
  ADD_FAILURE() << "no exception of the expected type thrown";
  return "";
}

/// The message of the InvalidInput `f` throws (a failure when it throws none).
template <class F> std::string invalid_input_of(F&& f) { return message_of<InvalidInput>(std::forward<F>(f)); }

/// How deep the deepest vertex of the flagged faces of `guide` lies behind the bone's surface (mm,
/// 0 when none does); `report(point, depth)` hears each vertex deeper than `loud`.
inline double deepest_in_bone(const TriangleMesh& guide, const std::vector<std::uint8_t>& flagged,
                              const TriangleMesh& bone, const AabbTree& bone_tree,
                              const std::function<void(const Vec3&, double)>& report = {}, double loud = 1e-3) {
  double deepest = 0.0;
  for (Index f = 0; f < guide.face_count(); ++f) {
    if (!flagged[f]) continue;
    for (Index w : guide.triangles[f]) {
      const Vec3& p = guide.positions[w];
      const auto cp = bone_tree.closest_point(p, 1.0);
      if (!cp || (p - cp->point).dot(triangle_normal(bone, cp->face)) >= 0.0) continue;
      if (report && cp->distance > loud) report(p, cp->distance);
      deepest = std::max(deepest, cp->distance);
    }
  }
  return deepest;
}

/// Generalised winding number: 1 inside a closed outward mesh, 0 outside.
inline double winding_number(const TriangleMesh& mesh, const Vec3& p) {
  double sum = 0.0;
  for (const Triangle& t : mesh.triangles) {
    const Vec3 a = mesh.positions[t[0]] - p, b = mesh.positions[t[1]] - p, c = mesh.positions[t[2]] - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    sum += 2.0 * std::atan2(num, den);
  }
  return sum / (4.0 * std::numbers::pi);
}

/// Meshes whose edges are not all shared by two faces: an icosphere with a hole, a turned face, a
/// doubled face, a face over another the other way round, and faces with a repeated corner; an open
/// grid patch, and the patch with its faces shuffled (each vertex's faces then not in the order of
/// their corners) and one doubled.
inline std::vector<TriangleMesh> awkward_meshes() {
  std::vector<TriangleMesh> meshes(5, make_icosphere(10.0, 3));
  meshes[0].triangles.erase(meshes[0].triangles.begin() + 7);
  std::swap(meshes[1].triangles[11][1], meshes[1].triangles[11][2]);
  meshes[2].triangles.push_back(meshes[2].triangles[5]);
  meshes[3].triangles.push_back({meshes[3].triangles[5][0], meshes[3].triangles[5][2], meshes[3].triangles[5][1]});
  meshes[4].triangles.push_back({meshes[4].triangles[5][0], meshes[4].triangles[5][0], meshes[4].triangles[5][1]});
  meshes[4].triangles[9][2] = meshes[4].triangles[9][1];
  meshes[4].triangles.push_back({meshes[4].triangles[20][1], meshes[4].triangles[20][1], meshes[4].triangles[20][1]});
  TriangleMesh grid = make_grid_patch(12, 0.0, 1.0, 0.0, 1.0,
                                      [](double u, double v) { return Vec3(u, v, 0.1 * std::sin(3.0 * u + v)); });
  meshes.push_back(grid);
  for (std::size_t f = 0; f < grid.triangles.size(); ++f)
    std::swap(grid.triangles[f], grid.triangles[(f * 7919) % grid.triangles.size()]);
  grid.triangles.push_back(grid.triangles[3]);
  meshes.push_back(grid);
  return meshes;
}

inline void expect_valid_solid(const TriangleMesh& mesh) {
  const SolidReport r = check_solid(mesh);
  EXPECT_TRUE(r.closed()) << r.summary();
  EXPECT_TRUE(r.manifold()) << r.summary();
  EXPECT_TRUE(r.oriented()) << r.summary();
  EXPECT_EQ(r.self_intersections, 0u) << r.summary();
  EXPECT_EQ(r.degenerate_triangles, 0u) << r.summary();
}

} // namespace st::test
