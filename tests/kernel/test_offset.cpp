// Tests of offset_surface: closedness, manifold edges, orientation, distance of every vertex to the
// patch, enclosed volume against the analytic Minkowski sum, front-only behaviour, input checks.

#include "helpers.h"

#include "st/core/errors.h"
#include "st/core/mesh.h"
#include "st/design/offset.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <numeric>
#include <unordered_map>
#include <utility>
#include <vector>

namespace {

using st::Index;
using st::TriangleMesh;
using st::Vec3;

// ---- fixtures --------------------------------------------------------------------------------------

TriangleMesh grid_patch(int n, double u0, double u1, double v0, double v1,
                        const std::function<Vec3(double, double)>& map) {
  return st::test::make_grid_patch(n, u0, u1, v0, v1, map);
}

/// The square [-a/2, a/2]^2 in the plane z = 0, normal +z.
TriangleMesh square_patch(double a, int n) {
  return grid_patch(n, -a / 2, a / 2, -a / 2, a / 2, [](double u, double v) { return Vec3(u, v, 0.0); });
}

/// The part of the sphere of radius r around the origin seen from it through the square
/// [-s, s]^2 at z = 1 (gnomonic grid), normal outward.
TriangleMesh cap_patch(double r, double s, int n) {
  return grid_patch(n, -s, s, -s, s, [r](double u, double v) -> Vec3 { return Vec3(u, v, 1.0).normalized() * r; });
}

/// The patch rotated by angle ax about x, then ay about y.
TriangleMesh rotated(TriangleMesh mesh, double ax, double ay) {
  const Eigen::Matrix3d r =
      (Eigen::AngleAxisd(ax, Vec3::UnitX()) * Eigen::AngleAxisd(ay, Vec3::UnitY())).toRotationMatrix();
  for (Vec3& p : mesh.positions) p = r * p;
  return mesh;
}

/// z = 2 sin(x/3) cos(y/4) over [-a/2, a/2]^2.
TriangleMesh wavy_patch(double a, int n) {
  return grid_patch(n, -a / 2, a / 2, -a / 2, a / 2,
                    [](double x, double y) { return Vec3(x, y, 2.0 * std::sin(x / 3.0) * std::cos(y / 4.0)); });
}

// ---- reference geometry (written independently of the kernel) --------------------------------------

double segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

/// Distance of p to the triangle: to its plane when p projects inside, else to the nearest edge.
double triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const double n2 = n.squaredNorm();
  if (n2 > 0) {
    const Vec3 x = p - n * (n.dot(p - a) / n2);
    if (n.dot((b - a).cross(x - a)) >= 0 && n.dot((c - b).cross(x - b)) >= 0 && n.dot((a - c).cross(x - c)) >= 0)
      return std::abs(n.dot(p - a)) / std::sqrt(n2);
  }
  return std::min({segment_distance(p, a, b), segment_distance(p, b, c), segment_distance(p, c, a)});
}

double patch_distance(const TriangleMesh& mesh, const Vec3& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& t : mesh.triangles)
    best = std::min(best, triangle_distance(p, mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]));
  return best;
}

/// Largest |distance(v, patch) - T| over (every `stride`-th) vertex of the offset.
double max_distance_error(const TriangleMesh& offset, const TriangleMesh& patch, double distance,
                          std::size_t stride = 1) {
  double worst = 0.0;
  for (std::size_t v = 0; v < offset.positions.size(); v += stride)
    worst = std::max(worst, std::abs(patch_distance(patch, offset.positions[v]) - distance));
  return worst;
}

struct EdgeReport {
  std::size_t edges = 0;
  std::size_t border = 0;         // used by one triangle
  std::size_t non_manifold = 0;   // used by three or more triangles
  std::size_t same_direction = 0; // used twice in the same direction (inconsistent orientation)
  std::size_t degenerate = 0;     // triangles repeating a vertex
};

EdgeReport edge_report(const TriangleMesh& mesh) {
  // For each undirected edge: uses in the direction low -> high and high -> low.
  std::unordered_map<std::uint64_t, std::pair<int, int>> uses;
  EdgeReport r;
  for (const auto& t : mesh.triangles) {
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) ++r.degenerate;
    for (int k = 0; k < 3; ++k) {
      const Index a = t[k];
      const Index b = t[(k + 1) % 3];
      const std::uint64_t key = (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
      auto& u = uses[key];
      (a < b ? u.first : u.second)++;
    }
  }
  r.edges = uses.size();
  for (const auto& [key, u] : uses) {
    const int total = u.first + u.second;
    if (total == 1) ++r.border;
    if (total >= 3) ++r.non_manifold;
    if (total == 2 && u.first != 1) ++r.same_direction;
  }
  return r;
}

/// Number of vertex-connected components of the triangles.
std::size_t component_count(const TriangleMesh& mesh) {
  std::vector<Index> parent(mesh.positions.size());
  std::iota(parent.begin(), parent.end(), Index{0});
  std::function<Index(Index)> root = [&](Index i) { return parent[i] == i ? i : parent[i] = root(parent[i]); };
  for (const auto& t : mesh.triangles) {
    parent[root(t[1])] = root(t[0]);
    parent[root(t[2])] = root(t[0]);
  }
  std::vector<bool> used(mesh.positions.size(), false);
  for (const auto& t : mesh.triangles)
    for (Index v : t) used[v] = true;
  std::size_t count = 0;
  for (Index v = 0; v < mesh.positions.size(); ++v)
    if (used[v] && root(v) == v) ++count;
  return count;
}

bool segment_crosses_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const double dp = n.dot(p - a);
  const double dq = n.dot(q - a);
  if (dp * dq >= 0) return false;
  const Vec3 x = p + (dp / (dp - dq)) * (q - p);
  return n.dot((b - a).cross(x - a)) > 0 && n.dot((c - b).cross(x - b)) > 0 && n.dot((a - c).cross(x - c)) > 0;
}

/// Pairs of triangles that cross each other (an edge of one pierces the interior of the other),
/// ignoring pairs that share an edge; found through a uniform grid of cell `cell`.
std::size_t self_intersection_count(const TriangleMesh& mesh, double cell) {
  const st::BoundingBox box = st::bounding_box(mesh);
  std::map<std::array<long, 3>, std::vector<Index>> grid;
  std::vector<std::array<long, 6>> range(mesh.triangles.size());
  for (Index f = 0; f < mesh.face_count(); ++f) {
    const st::BoundingBox tb = st::triangle_box(mesh, f);
    for (int a = 0; a < 3; ++a) {
      range[f][a] = static_cast<long>(std::floor((tb.min[a] - box.min[a]) / cell));
      range[f][a + 3] = static_cast<long>(std::floor((tb.max[a] - box.min[a]) / cell));
    }
    for (long i = range[f][0]; i <= range[f][3]; ++i)
      for (long j = range[f][1]; j <= range[f][4]; ++j)
        for (long k = range[f][2]; k <= range[f][5]; ++k) grid[{i, j, k}].push_back(f);
  }
  std::size_t count = 0;
  for (const auto& [key, faces] : grid)
    for (std::size_t x = 0; x < faces.size(); ++x)
      for (std::size_t y = 0; y < x; ++y) {
        const Index f = faces[x];
        const Index g = faces[y];
        // Visit each pair once: in the cell holding the low corner of the overlap of their ranges.
        bool first = true;
        for (int a = 0; a < 3; ++a) first = first && key[a] == std::max(range[f][a], range[g][a]);
        if (!first) continue;
        const auto& tf = mesh.triangles[f];
        const auto& tg = mesh.triangles[g];
        int shared = 0;
        for (Index u : tf)
          for (Index v : tg) shared += u == v;
        if (shared >= 2) continue;
        auto crosses = [&](const st::Triangle& s, const st::Triangle& t) {
          for (int k = 0; k < 3; ++k) {
            const Index u = s[k];
            const Index v = s[(k + 1) % 3];
            if (shared == 1 &&
                (std::find(t.begin(), t.end(), u) != t.end() || std::find(t.begin(), t.end(), v) != t.end()))
              continue; // an edge through the shared vertex touches t there
            if (segment_crosses_triangle(mesh.positions[u], mesh.positions[v], mesh.positions[t[0]],
                                         mesh.positions[t[1]], mesh.positions[t[2]]))
              return true;
          }
          return false;
        };
        if (crosses(tf, tg) || crosses(tg, tf)) ++count;
      }
  return count;
}

void expect_closed_manifold(const TriangleMesh& mesh) {
  const EdgeReport r = edge_report(mesh);
  EXPECT_GT(r.edges, 0u);
  EXPECT_EQ(r.border, 0u);
  EXPECT_EQ(r.non_manifold, 0u);
  EXPECT_EQ(r.same_direction, 0u);
  EXPECT_EQ(r.degenerate, 0u);
}

void expect_manifold_with_border(const TriangleMesh& mesh) {
  const EdgeReport r = edge_report(mesh);
  EXPECT_GT(r.edges, 0u);
  EXPECT_EQ(r.non_manifold, 0u);
  EXPECT_EQ(r.same_direction, 0u);
  EXPECT_EQ(r.degenerate, 0u);
}

Vec3 face_normal(const TriangleMesh& mesh, Index f) { return st::triangle_normal(mesh, f).normalized(); }

Vec3 face_centre(const TriangleMesh& mesh, Index f) {
  const auto& t = mesh.triangles[f];
  return (mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) / 3.0;
}

// ---- (a) closed offset of a square ------------------------------------------------------------------

TEST(Offset, SquareFullOffsetIsClosedAtDistanceWithMinkowskiVolume) {
  const double a = 20.0;
  const TriangleMesh patch = square_patch(a, 10);
  st::OffsetOptions options;
  options.distance = 2.5;
  options.front_only = false;
  const st::OffsetResult result = st::offset_surface(patch, options);
  const double h = result.cell_size;
  const double T = options.distance;
  EXPECT_DOUBLE_EQ(h, T / 8); // automatic size on a coarse mesh
  EXPECT_GT(result.band_voxels, 0u);

  expect_closed_manifold(result.surface);
  EXPECT_EQ(component_count(result.surface), 1u);
  EXPECT_LE(max_distance_error(result.surface, patch, T), 0.5 * h);

  // Minkowski sum of the square with a ball of radius T: slab a^2 * 2T, a half cylinder along each
  // side (perimeter * pi T^2 / 2), and the four corner wedges, a quarter ball each: one ball.
  const double pi = std::numbers::pi;
  const double analytic = a * a * 2 * T + 4 * a * pi * T * T / 2 + 4.0 / 3.0 * pi * T * T * T;
  const double volume = st::signed_volume(result.surface);
  EXPECT_GT(volume, 0.0); // outward orientation
  EXPECT_NEAR(volume, analytic, 0.03 * analytic);
}

// ---- (b) front sheet only ---------------------------------------------------------------------------

TEST(Offset, SquareFrontOnlyHasFrontSheetAndRimButNoBackSheet) {
  const double a = 20.0;
  const TriangleMesh patch = square_patch(a, 10);
  st::OffsetOptions options;
  options.distance = 2.5;
  const st::OffsetResult result = st::offset_surface(patch, options);
  const TriangleMesh& s = result.surface;
  const double h = result.cell_size;
  const double T = options.distance;

  expect_manifold_with_border(s);
  EXPECT_GT(edge_report(s).border, 0u); // open below the rim
  EXPECT_EQ(component_count(s), 1u);    // front sheet and rim in one piece
  EXPECT_LE(max_distance_error(s, patch, T), 0.5 * h);

  std::size_t front = 0;
  double min_z = std::numeric_limits<double>::infinity();
  for (const Vec3& p : s.positions) {
    const bool above_square = std::abs(p.x()) < a / 2 && std::abs(p.y()) < a / 2;
    if (above_square) {
      EXPECT_GT(p.z(), 0.0) << "a vertex behind the patch: the back sheet must not be made";
      EXPECT_NEAR(p.z(), T, 0.5 * h);
      ++front;
    }
    min_z = std::min(min_z, p.z());
  }
  EXPECT_GT(front, 1000u);
  // The rim goes round the border down to about the margin T/2 below the plane (plus up to two
  // cells of band), not further.
  EXPECT_LT(min_z, -0.25 * T);
  EXPECT_GT(min_z, -(0.5 * T + 2 * std::sqrt(3.0) * h));

  // The front sheet faces away from the patch.
  for (Index f = 0; f < s.face_count(); ++f) {
    const Vec3 c = face_centre(s, f);
    if (std::abs(c.x()) < a / 2 - h && std::abs(c.y()) < a / 2 - h) {
      EXPECT_GT(face_normal(s, f).z(), 0.99);
    }
  }
}

TEST(Offset, FlippedPatchGivesTheSheetOnTheOtherSide) {
  TriangleMesh patch = square_patch(10.0, 6);
  for (auto& t : patch.triangles) std::swap(t[1], t[2]);
  st::OffsetOptions options;
  options.distance = 2.0;
  const st::OffsetResult result = st::offset_surface(patch, options);
  std::size_t below = 0;
  for (const Vec3& p : result.surface.positions)
    if (std::abs(p.x()) < 5 && std::abs(p.y()) < 5) {
      EXPECT_NEAR(p.z(), -2.0, 0.5 * result.cell_size);
      ++below;
    }
  EXPECT_GT(below, 100u);
  expect_manifold_with_border(result.surface);
}

// ---- (c) spherical cap -----------------------------------------------------------------------------

TEST(Offset, SphericalCapOffsetLiesOnTheLargerSphere) {
  const double r = 20.0;
  const double s = 0.6; // cap half-width in gnomonic coordinates, about 31 degrees
  const TriangleMesh patch = cap_patch(r, s, 30);
  st::OffsetOptions options;
  options.distance = 2.5;
  const st::OffsetResult result = st::offset_surface(patch, options);
  const TriangleMesh& out = result.surface;
  const double h = result.cell_size;
  const double T = options.distance;
  expect_manifold_with_border(out);
  EXPECT_EQ(component_count(out), 1u);

  // The patch is inscribed in the sphere: its faces lie up to the sagitta below it.
  double edge = 0.0;
  for (const auto& t : patch.triangles)
    for (int k = 0; k < 3; ++k) edge = std::max(edge, (patch.positions[t[k]] - patch.positions[t[(k + 1) % 3]]).norm());
  const double sagitta = edge * edge / (8 * r);

  std::size_t inside = 0;
  for (const Vec3& p : out.positions) {
    if (p.z() <= 0) continue;
    const double u = p.x() / p.z();
    const double v = p.y() / p.z();
    if (std::abs(u) < s - 0.05 && std::abs(v) < s - 0.05) {
      EXPECT_NEAR(p.norm(), r + T, 0.5 * h + sagitta);
      ++inside;
    }
  }
  EXPECT_GT(inside, 1000u);
  EXPECT_LE(max_distance_error(out, patch, T, 3), 0.5 * h);
  // Outward: every face over the cap interior faces away from the centre.
  for (Index f = 0; f < out.face_count(); ++f) {
    const Vec3 c = face_centre(out, f);
    if (c.z() > 0 && std::abs(c.x() / c.z()) < s - 0.05 && std::abs(c.y() / c.z()) < s - 0.05) {
      EXPECT_GT(face_normal(out, f).dot(c.normalized()), 0.9);
    }
  }
}

TEST(Offset, ConcaveCapCloserThanTheDistanceIsOffsetAtTheRightDistance) {
  // A cap of radius 2 < T seen from inside, tilted against the grid: the offsets of opposite parts
  // of the cap meet, and 26-neighbour layers reach some nodes from the farther part first (a
  // regression: before the repair step, vertices came out to 0.15 mm too close to the cap).
  TriangleMesh cap = cap_patch(2.0, 0.8, 30);
  for (auto& t : cap.triangles) std::swap(t[1], t[2]); // normals toward the centre
  const TriangleMesh patch = rotated(cap, 0.5, 0.3);
  st::OffsetOptions options;
  options.distance = 2.5;
  const st::OffsetResult result = st::offset_surface(patch, options);
  expect_manifold_with_border(result.surface);
  EXPECT_GT(result.surface.face_count(), 1000u);
  EXPECT_LE(max_distance_error(result.surface, patch, options.distance), 0.5 * result.cell_size);
}

TEST(Offset, PatchWithASmallHoleIsOffsetOverTheHole) {
  // An annulus (radii 1.2 and 10): over the hole the closest points lie on its border all around.
  const int n = 40;
  TriangleMesh patch = grid_patch(n, 0, 2 * std::numbers::pi, 1.2, 10,
                                  [](double a, double r) { return Vec3(r * std::cos(a), r * std::sin(a), 0.0); });
  for (auto& t : patch.triangles) // close the seam: the column at 2 pi is the column at 0
    for (Index& v : t)
      if (v % (n + 1) == static_cast<Index>(n)) v -= n;
  if (st::triangle_normal(patch, 0).z() < 0)
    for (auto& t : patch.triangles) std::swap(t[1], t[2]);
  st::OffsetOptions options;
  options.distance = 2.5;
  for (const bool front_only : {true, false}) {
    options.front_only = front_only;
    const st::OffsetResult result = st::offset_surface(patch, options);
    const TriangleMesh& out = result.surface;
    if (front_only) {
      expect_manifold_with_border(out);
    } else {
      expect_closed_manifold(out);
      EXPECT_GT(st::signed_volume(out), 0.0);
    }
    EXPECT_EQ(component_count(out), 1u);
    EXPECT_LE(max_distance_error(out, patch, options.distance, 7), 0.5 * result.cell_size);
    // Over the hole's centre the sheet is at height sqrt(T^2 - 1.2^2).
    double top = -1.0;
    for (const Vec3& p : out.positions)
      if (std::hypot(p.x(), p.y()) < 0.2) top = std::max(top, p.z());
    EXPECT_NEAR(top, std::sqrt(2.5 * 2.5 - 1.2 * 1.2), 0.5 * result.cell_size);
  }
}

// ---- (d) wavy patch: manifold, no self-intersections ---------------------------------------------------

TEST(Offset, WavyPatchFrontOnlyIsManifoldWithoutSelfIntersections) {
  const TriangleMesh patch = wavy_patch(16.0, 32);
  st::OffsetOptions options;
  options.distance = 2.0;
  options.cell_size = 0.25;
  const st::OffsetResult result = st::offset_surface(patch, options);
  const TriangleMesh& out = result.surface;
  EXPECT_DOUBLE_EQ(result.cell_size, 0.25);
  expect_manifold_with_border(out);
  EXPECT_EQ(component_count(out), 1u);
  EXPECT_EQ(self_intersection_count(out, 0.5), 0u);
  EXPECT_LE(max_distance_error(out, patch, options.distance, 7), 0.5 * result.cell_size);
}

TEST(Offset, WavyPatchFullOffsetIsClosedWithoutSelfIntersections) {
  const TriangleMesh patch = wavy_patch(12.0, 24);
  st::OffsetOptions options;
  options.distance = 2.0;
  options.cell_size = 0.3;
  options.front_only = false;
  const st::OffsetResult result = st::offset_surface(patch, options);
  expect_closed_manifold(result.surface);
  EXPECT_EQ(component_count(result.surface), 1u);
  EXPECT_GT(st::signed_volume(result.surface), 0.0);
  EXPECT_EQ(self_intersection_count(result.surface, 0.6), 0u);
  EXPECT_LE(max_distance_error(result.surface, patch, options.distance, 5), 0.5 * result.cell_size);
}

// ---- robustness and memory ---------------------------------------------------------------------------

TEST(Offset, DegenerateTrianglesDoNotBreakTheOffset) {
  TriangleMesh patch = square_patch(10.0, 5);
  // A zero-area sliver along an existing edge, a triangle repeating a vertex, and a needle.
  const Index n = patch.vertex_count();
  patch.positions.push_back(Vec3(1.0, 5.0, 0.0));
  patch.positions.push_back(Vec3(1.0 + 1e-9, 5.0 + 1e-12, 0.0));
  patch.triangles.push_back({0, 1, 1});
  patch.triangles.push_back({n, n + 1, 2});
  patch.triangles.push_back({3, 4, static_cast<Index>((3 + 4) / 2)});
  st::OffsetOptions options;
  options.distance = 1.5;
  options.front_only = false;
  const st::OffsetResult result = st::offset_surface(patch, options);
  expect_closed_manifold(result.surface);
  EXPECT_GT(st::signed_volume(result.surface), 0.0);
  EXPECT_LE(max_distance_error(result.surface, patch, options.distance, 3), 0.5 * result.cell_size);
}

TEST(Offset, BandIsSparse) {
  // A 40 mm square tilted by 45 degrees: its bounding box is mostly empty.
  const double a = 40.0;
  const TriangleMesh patch = grid_patch(10, -a / 2, a / 2, -a / 2, a / 2, [](double u, double v) {
    return Vec3(u / std::sqrt(2.0), v, u / std::sqrt(2.0));
  });
  st::OffsetOptions options;
  options.distance = 1.5;
  options.cell_size = 0.3;
  options.front_only = false;
  const st::OffsetResult result = st::offset_surface(patch, options);
  const double cell = std::pow(options.cell_size, 3);
  const double reach = options.distance + 4 * options.cell_size; // nodes lie within this distance
  const Vec3 box = st::bounding_box(patch).size().array() + 2 * reach;
  const double dense = box.prod() / cell;
  const double band = (a * a * 2 * reach + 4 * a * std::numbers::pi / 2 * reach * reach) / cell;
  const auto computed = static_cast<double>(result.band_voxels);
  EXPECT_LT(computed, 0.3 * dense);
  EXPECT_LT(computed, 1.2 * band);
  EXPECT_GT(computed, 0.5 * band);
  expect_closed_manifold(result.surface);
}

// ---- (e) bad input -------------------------------------------------------------------------------------

TEST(Offset, RejectsBadInput) {
  const TriangleMesh patch = square_patch(20.0, 4);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  auto with = [](auto change) {
    st::OffsetOptions o;
    change(o);
    return o;
  };
  EXPECT_THROW(st::offset_surface(patch, with([](auto& o) { o.distance = 0.0; })), st::InvalidInput);
  EXPECT_THROW(st::offset_surface(patch, with([](auto& o) { o.distance = -1.0; })), st::InvalidInput);
  EXPECT_THROW(st::offset_surface(patch, with([&](auto& o) { o.distance = nan; })), st::InvalidInput);
  EXPECT_THROW(st::offset_surface(patch, with([&](auto& o) { o.distance = inf; })), st::InvalidInput);
  EXPECT_THROW(st::offset_surface(patch, with([&](auto& o) { o.cell_size = nan; })), st::InvalidInput);
  EXPECT_THROW(st::offset_surface(patch, with([](auto& o) { o.cell_size = -0.1; })), st::InvalidInput);
  EXPECT_THROW(st::offset_surface(patch, with([](auto& o) { o.cell_size = 2.0; })), st::InvalidInput);
  EXPECT_THROW(st::offset_surface(patch, with([&](auto& o) { o.max_cells = nan; })), st::InvalidInput);

  EXPECT_THROW(st::offset_surface(TriangleMesh{}, {}), st::InvalidInput);
  TriangleMesh broken = patch;
  broken.positions[3].y() = nan;
  EXPECT_THROW(st::offset_surface(broken, {}), st::InvalidInput);
  broken = patch;
  broken.triangles[2][1] = 1000;
  EXPECT_THROW(st::offset_surface(broken, {}), st::InvalidInput);

  // 1 micrometre cells on a 20 mm square: refused by the estimate, before any allocation.
  try {
    st::offset_surface(patch, with([](auto& o) { o.cell_size = 0.001; }));
    FAIL() << "expected InvalidInput";
  } catch (const st::InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("over the budget"), std::string::npos) << e.what();
  }
  // The automatic cell size gets coarser to fit a small budget, and refuses when nothing fits.
  const st::OffsetResult coarse = st::offset_surface(patch, with([](auto& o) { o.max_cells = 5e4; }));
  EXPECT_GT(coarse.cell_size, 2.5 / 8);
  EXPECT_LE(static_cast<double>(coarse.band_voxels), 5e4);
  EXPECT_THROW(st::offset_surface(patch, with([](auto& o) { o.max_cells = 100.0; })), st::InvalidInput);
}

} // namespace
