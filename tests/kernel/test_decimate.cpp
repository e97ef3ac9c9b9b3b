// Tests of decimate: reduction, planarity, untouched border loop, 2-manifoldness, orientation,
// deviation from the input (both ways, brute force), volume, edge length, no flipped or degenerate
// triangles, sliver-rich marching-tetrahedra input, option checks, and a timing on 200k triangles.

#include "helpers.h"

#include "st/design/decimate.h"
#include "st/core/errors.h"
#include "st/core/mesh.h"
#include "st/core/topology.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <random>
#include <unordered_map>
#include <utility>
#include <vector>

namespace {

using st::Index;
using st::TriangleMesh;
using st::Vec3;

// ---- fixtures --------------------------------------------------------------------------------------

/// n x n quads over [0, n*h]^2 mapped through `map`, alternating diagonals, normal d/du x d/dv.
TriangleMesh grid_patch(int n, double h, const std::function<Vec3(double, double)>& map) {
  return st::test::make_grid_patch(n, 0.0, n * h, 0.0, n * h, map);
}

TriangleMesh icosphere(double radius, int levels) { return st::test::make_icosphere(radius, levels); }

/// Open spherical cap of the given radius over the polar angles [0, max_angle]: a gnomonic-free polar
/// triangulation with rings of nearly equal spacing (one border loop, normals outward).
TriangleMesh sphere_cap(double radius, double max_angle, int rings) {
  TriangleMesh m;
  m.positions.push_back({0, 0, radius});
  std::vector<Index> prev{0};
  for (int r = 1; r <= rings; ++r) {
    const double theta = max_angle * r / rings;
    const int count = 6 * r;
    std::vector<Index> ring;
    for (int k = 0; k < count; ++k) {
      const double phi = 2.0 * std::numbers::pi * k / count;
      ring.push_back(static_cast<Index>(m.positions.size()));
      m.positions.push_back(radius *
                            Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)));
    }
    // Stitch the previous ring (6(r-1) vertices) to this one (6r) by merging in angle order.
    const int np = static_cast<int>(prev.size()), nc = count;
    int i = r == 1 ? np : 0, j = 0;
    while (i < np || j < nc) {
      const double ai = r == 1 ? 1e9 : (i + 0.5) / np, aj = (j + 0.5) / nc;
      if (j < nc && (i >= np || aj <= ai)) {
        m.triangles.push_back({prev[i % np], ring[j], ring[(j + 1) % nc]});
        ++j;
      } else {
        m.triangles.push_back({prev[i % np], ring[(j) % nc], prev[(i + 1) % np]});
        ++i;
      }
    }
    prev = std::move(ring);
  }
  return m;
}

/// Marching tetrahedra (cubes split into 6 tetrahedra along the main diagonal) of the zero level of
/// `f` on the grid of n^3 cells of size h from `lo`: many slivers and needles. Normals point towards
/// positive values.
TriangleMesh marching_tetrahedra(const std::function<double(const Vec3&)>& f, const Vec3& lo, double h, int n) {
  const int m = n + 1;
  auto node = [m](int i, int j, int k) { return static_cast<std::int64_t>((k * m + j) * m + i); };
  std::vector<double> value(static_cast<std::size_t>(m) * m * m);
  std::vector<Vec3> point(value.size());
  for (int k = 0; k < m; ++k)
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i) {
        const Vec3 p = lo + h * Vec3(i, j, k);
        double v = f(p);
        if (std::abs(v) < 1e-9) v = 1e-9;
        value[node(i, j, k)] = v;
        point[node(i, j, k)] = p;
      }
  TriangleMesh mesh;
  std::unordered_map<std::int64_t, Index> edge_vertex;
  auto cut = [&](std::int64_t a, std::int64_t b) {
    if (a > b) std::swap(a, b);
    const std::int64_t key = a * static_cast<std::int64_t>(value.size()) + b;
    auto [it, inserted] = edge_vertex.try_emplace(key, mesh.vertex_count());
    if (inserted) {
      const double t = value[a] / (value[a] - value[b]);
      mesh.positions.push_back(point[a] + t * (point[b] - point[a]));
    }
    return it->second;
  };
  auto emit = [&](Index a, Index b, Index c, const Vec3& ma, const Vec3& mb, const Vec3& mc, const Vec3& towards) {
    // Orientation decided on edge midpoints (never degenerate), applied to the cut points.
    if ((mb - ma).cross(mc - ma).dot(towards) > 0) mesh.triangles.push_back({a, b, c});
    else mesh.triangles.push_back({a, c, b});
  };
  const std::array<std::array<int, 3>, 6> perms{{{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        for (const auto& perm : perms) {
          std::array<int, 3> c{i, j, k};
          std::array<std::int64_t, 4> t{};
          t[0] = node(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[perm[s]];
            t[s + 1] = node(c[0], c[1], c[2]);
          }
          std::vector<std::int64_t> pos, neg;
          for (std::int64_t v : t) (value[v] > 0 ? pos : neg).push_back(v);
          auto mid = [&](std::int64_t a, std::int64_t b) { return 0.5 * (point[a] + point[b]); };
          if (pos.size() == 1 || neg.size() == 1) {
            const bool lone_pos = pos.size() == 1;
            const std::int64_t l = lone_pos ? pos[0] : neg[0];
            const auto& o = lone_pos ? neg : pos;
            const Vec3 centre = (mid(l, o[0]) + mid(l, o[1]) + mid(l, o[2])) / 3.0;
            const Vec3 towards = lone_pos ? Vec3(point[l] - centre) : Vec3(centre - point[l]);
            emit(cut(l, o[0]), cut(l, o[1]), cut(l, o[2]), mid(l, o[0]), mid(l, o[1]), mid(l, o[2]), towards);
          } else if (pos.size() == 2) {
            const std::int64_t a = pos[0], b = pos[1], c0 = neg[0], d = neg[1];
            const Vec3 towards = 0.5 * (point[a] + point[b]) - 0.5 * (point[c0] + point[d]);
            // Quad ac, ad, bd, bc.
            emit(cut(a, c0), cut(a, d), cut(b, d), mid(a, c0), mid(a, d), mid(b, d), towards);
            emit(cut(a, c0), cut(b, d), cut(b, c0), mid(a, c0), mid(b, d), mid(b, c0), towards);
          }
        }
  return mesh;
}

// ---- helpers ---------------------------------------------------------------------------------------

std::uint64_t edge_key(Index a, Index b) { return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b); }

struct EdgeReport {
  std::size_t border = 0, nonmanifold = 0, misoriented = 0, nonmanifold_vertices = 0;
  [[nodiscard]] bool manifold() const { return nonmanifold == 0 && misoriented == 0 && nonmanifold_vertices == 0; }
};

/// Every edge used once (border) or twice in opposite directions; every vertex's link is one path
/// or one cycle.
EdgeReport edge_report(const TriangleMesh& mesh) {
  EdgeReport r;
  std::unordered_map<std::uint64_t, std::pair<int, int>> uses;
  for (const st::Triangle& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      const Index a = t[k], b = t[(k + 1) % 3];
      auto& u = uses[edge_key(a, b)];
      (a < b ? u.first : u.second)++;
    }
  for (const auto& [key, u] : uses) {
    const int total = u.first + u.second;
    if (total == 1) ++r.border;
    else if (total > 2) ++r.nonmanifold;
    else if (u.first != 1) ++r.misoriented;
  }
  // Links: for each vertex, the opposite edges of its faces must form one connected path/cycle.
  std::vector<std::vector<std::pair<Index, Index>>> link(mesh.vertex_count());
  for (const st::Triangle& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) link[t[k]].push_back({t[(k + 1) % 3], t[(k + 2) % 3]});
  for (auto& l : link) {
    if (l.empty()) continue;
    std::map<Index, std::vector<Index>> adj;
    for (auto [a, b] : l) {
      adj[a].push_back(b);
      adj[b].push_back(a);
    }
    std::map<Index, bool> seen;
    std::vector<Index> stack{l[0].first};
    seen[l[0].first] = true;
    while (!stack.empty()) {
      const Index v = stack.back();
      stack.pop_back();
      for (Index w : adj[v])
        if (!seen[w]) {
          seen[w] = true;
          stack.push_back(w);
        }
    }
    bool ok = seen.size() == adj.size();
    for (const auto& [v, a] : adj) ok = ok && a.size() <= 2;
    if (!ok) ++r.nonmanifold_vertices;
  }
  return r;
}

std::size_t degenerate_count(const TriangleMesh& mesh) {
  std::size_t count = 0;
  for (Index f = 0; f < mesh.face_count(); ++f) {
    const st::Triangle& t = mesh.triangles[f];
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0] || st::triangle_normal(mesh, f).squaredNorm() == 0.0) ++count;
  }
  return count;
}

std::vector<std::vector<Index>> loops_of(const TriangleMesh& mesh) {
  return st::border_loops(mesh, st::MeshTopology(mesh).all_opposites());
}

/// The loop's positions, rotated to start at its lexicographically smallest point.
std::vector<Vec3> canonical_loop(const TriangleMesh& mesh, const std::vector<Index>& loop) {
  std::vector<Vec3> p;
  for (Index v : loop) p.push_back(mesh.positions[v]);
  auto less = [](const Vec3& a, const Vec3& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  };
  std::rotate(p.begin(), std::min_element(p.begin(), p.end(), less), p.end());
  return p;
}

void expect_same_border(const TriangleMesh& before, const TriangleMesh& after) {
  const auto loops_before = loops_of(before);
  const auto loops_after = loops_of(after);
  ASSERT_EQ(loops_before.size(), loops_after.size());
  ASSERT_EQ(loops_before.size(), 1u);
  const auto a = canonical_loop(before, loops_before[0]);
  const auto b = canonical_loop(after, loops_after[0]);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    // Bit-identical positions in the same cyclic order.
    EXPECT_TRUE(a[i].x() == b[i].x() && a[i].y() == b[i].y() && a[i].z() == b[i].z()) << "border vertex " << i;
  }
}

/// Distance from p to triangle abc (Ericson, Real-Time Collision Detection 5.1.5).
double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return (p - a).norm();
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return (p - b).norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + d1 / (d1 - d3) * ab)).norm();
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return (p - c).norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + d2 / (d2 - d6) * ac)).norm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return (p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))).norm();
  const double denom = 1.0 / (va + vb + vc);
  return (p - (a + ab * (vb * denom) + ac * (vc * denom))).norm();
}

double distance_to_mesh(const Vec3& p, const TriangleMesh& mesh) {
  double best = std::numeric_limits<double>::infinity();
  for (const st::Triangle& t : mesh.triangles)
    best = std::min(best, point_triangle_distance(p, mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]));
  return best;
}

double median_seconds(std::vector<double> t) {
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

TriangleMesh sliver_square(int n, double h, unsigned seed) {
  TriangleMesh mesh = grid_patch(n, h, [](double u, double v) { return Vec3(u, v, 0.0); });
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.2 * h, 0.2 * h);
  for (int j = 1; j < n; ++j)
    for (int i = 1; i < n; ++i) {
      Vec3& p = mesh.positions[j * (n + 1) + i];
      p.x() += jitter(rng);
      p.y() += jitter(rng);
    }
  return mesh;
}

// ---- tests -----------------------------------------------------------------------------------------

TEST(Decimate, FlatSquareWithSliversIsReducedPlanarAndKeepsItsBorder) {
  const TriangleMesh input = sliver_square(200, 0.5, 7);
  std::size_t flipped_input = 0;
  for (Index f = 0; f < input.face_count(); ++f) flipped_input += st::triangle_normal(input, f).z() <= 0.0;
  ASSERT_EQ(flipped_input, 0u) << "fixture must be a valid triangulation";

  const st::DecimateResult r = st::decimate(input);
  EXPECT_LT(r.mesh.face_count(), input.face_count() / 20) << r.mesh.face_count() << " of " << input.face_count();
  EXPECT_GT(r.collapses, 0u);
  for (const Vec3& p : r.mesh.positions) EXPECT_EQ(p.z(), 0.0);
  for (Index f = 0; f < r.mesh.face_count(); ++f) EXPECT_GT(st::triangle_normal(r.mesh, f).z(), 0.0);
  const double area_in = st::surface_area(input), area_out = st::surface_area(r.mesh);
  EXPECT_NEAR(area_out, area_in, 1e-9 * area_in);
  expect_same_border(input, r.mesh);
  EXPECT_TRUE(edge_report(r.mesh).manifold());
  EXPECT_EQ(degenerate_count(r.mesh), 0u);
  EXPECT_EQ(r.degenerate_left, 0u);
}

TEST(Decimate, VertexSourceFindsBorderVerticesOfTheInput) {
  const TriangleMesh input = sliver_square(40, 1.0, 3);
  const st::DecimateResult r = st::decimate(input);
  ASSERT_EQ(r.vertex_source.size(), r.mesh.positions.size());
  const auto loops = loops_of(r.mesh);
  ASSERT_EQ(loops.size(), 1u);
  for (Index v : loops[0]) {
    const Index s = r.vertex_source[v];
    ASSERT_NE(s, st::kInvalidIndex);
    EXPECT_TRUE(input.positions[s] == r.mesh.positions[v]);
  }
  for (Index v = 0; v < r.mesh.vertex_count(); ++v) {
    if (r.vertex_source[v] != st::kInvalidIndex) {
      EXPECT_TRUE(input.positions[r.vertex_source[v]] == r.mesh.positions[v]);
    }
  }
}

TEST(Decimate, HemisphereCapStaysWithinMaxErrorBothWays) {
  const double radius = 20.0;
  const TriangleMesh input = sphere_cap(radius, std::numbers::pi / 2, 80);
  ASSERT_EQ(loops_of(input).size(), 1u);
  ASSERT_TRUE(edge_report(input).manifold());
  st::DecimateOptions options;
  options.max_error = 0.05;
  const st::DecimateResult r = st::decimate(input, options);
  EXPECT_LT(r.mesh.face_count(), input.face_count() / 4) << r.mesh.face_count() << " of " << input.face_count();

  // Output vertices near the sphere (plus the input's own chord error, tiny here).
  double input_sag = 0.0;
  for (const st::Triangle& t : input.triangles)
    input_sag = std::max(input_sag,
                         radius - ((input.positions[t[0]] + input.positions[t[1]] + input.positions[t[2]]) / 3).norm());
  double worst_out = 0.0;
  for (const Vec3& p : r.mesh.positions) worst_out = std::max(worst_out, std::abs(p.norm() - radius));
  EXPECT_LE(worst_out, options.max_error + input_sag) << "input sag " << input_sag;

  // Input vertices near the output (subsample, brute force).
  double worst_in = 0.0;
  for (std::size_t v = 0; v < input.positions.size(); v += 7)
    worst_in = std::max(worst_in, distance_to_mesh(input.positions[v], r.mesh));
  EXPECT_LE(worst_in, 1.2 * options.max_error);
  std::printf("[          ] cap %u -> %u triangles, output->sphere %.4f mm, input->output %.4f mm\n",
              input.face_count(), r.mesh.face_count(), worst_out, worst_in);

  expect_same_border(input, r.mesh);
  const EdgeReport e = edge_report(r.mesh);
  EXPECT_TRUE(e.manifold());
  EXPECT_EQ(e.border, loops_of(input)[0].size());
  EXPECT_EQ(degenerate_count(r.mesh), 0u);
  for (Index f = 0; f < r.mesh.face_count(); ++f) {
    const st::Triangle& t = r.mesh.triangles[f];
    const Vec3 centre = (r.mesh.positions[t[0]] + r.mesh.positions[t[1]] + r.mesh.positions[t[2]]) / 3;
    EXPECT_GT(st::triangle_normal(r.mesh, f).dot(centre), 0.0) << "face " << f;
  }
}

TEST(Decimate, ClosedSphereStaysClosedManifoldWithItsVolume) {
  const TriangleMesh input = icosphere(20.0, 5);
  st::DecimateOptions options;
  options.max_error = 0.05;
  const st::DecimateResult r = st::decimate(input, options);
  EXPECT_LT(r.mesh.face_count(), input.face_count() / 3);
  const EdgeReport e = edge_report(r.mesh);
  EXPECT_EQ(e.border, 0u);
  EXPECT_TRUE(e.manifold());
  EXPECT_EQ(degenerate_count(r.mesh), 0u);
  const double v_in = st::signed_volume(input), v_out = st::signed_volume(r.mesh);
  EXPECT_NEAR(v_out, v_in, 0.01 * v_in);
}

TEST(Decimate, TargetEdgeLengthBoundsTheMeanEdgeLength) {
  const TriangleMesh input = icosphere(20.0, 5); // edges about 0.65 mm
  st::DecimateOptions options;
  options.max_error = 0.5;
  options.target_edge_length = 2.0;
  const st::DecimateResult r = st::decimate(input, options);
  const double mean = st::mean_edge_length(r.mesh);
  EXPECT_LT(mean, 1.5 * options.target_edge_length);
  EXPECT_GT(mean, 1.5 * st::mean_edge_length(input)) << "should still coarsen";
  EXPECT_TRUE(edge_report(r.mesh).manifold());
  EXPECT_EQ(edge_report(r.mesh).border, 0u);
}

TEST(Decimate, NoisyHeightFieldHasNoFlippedTriangles) {
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 0.03);
  TriangleMesh input =
      grid_patch(120, 0.4, [](double u, double v) { return Vec3(u, v, 1.5 * std::sin(u / 6.0) * std::cos(v / 9.0)); });
  for (Vec3& p : input.positions) p.z() += noise(rng);
  for (const double max_error : {0.05, 0.3}) {
    st::DecimateOptions options;
    options.max_error = max_error;
    const st::DecimateResult r = st::decimate(input, options);
    EXPECT_LT(r.mesh.face_count(), input.face_count());
    for (Index f = 0; f < r.mesh.face_count(); ++f) EXPECT_GT(st::triangle_normal(r.mesh, f).z(), 0.0) << "face " << f;
    EXPECT_TRUE(edge_report(r.mesh).manifold());
    EXPECT_EQ(degenerate_count(r.mesh), 0u);
    expect_same_border(input, r.mesh);
  }
}

TEST(Decimate, MarchingTetrahedraSliversSimplifyWithoutBreakingManifoldness) {
  const Vec3 centre(0.013, 0.027, -0.031);
  const TriangleMesh input =
      marching_tetrahedra([&](const Vec3& p) { return (p - centre).norm() - 10.0; }, Vec3::Constant(-12.0), 0.5, 48);
  const EdgeReport e_in = edge_report(input);
  ASSERT_TRUE(e_in.manifold());
  ASSERT_EQ(e_in.border, 0u);
  std::size_t slivers = 0;
  for (Index f = 0; f < input.face_count(); ++f) {
    const st::Triangle& t = input.triangles[f];
    const Vec3 &a = input.positions[t[0]], &b = input.positions[t[1]], &c = input.positions[t[2]];
    const double q = 2 * std::sqrt(3.0) * (b - a).cross(c - a).norm() /
                     ((b - a).squaredNorm() + (c - b).squaredNorm() + (a - c).squaredNorm());
    slivers += q < 0.1;
  }
  ASSERT_GT(slivers, input.face_count() / 50) << "fixture should contain slivers";

  st::DecimateOptions options;
  options.max_error = 0.05;
  const st::DecimateResult r = st::decimate(input, options);
  EXPECT_LT(r.mesh.face_count(), input.face_count() / 3);
  const EdgeReport e = edge_report(r.mesh);
  EXPECT_EQ(e.border, 0u);
  EXPECT_TRUE(e.manifold());
  EXPECT_EQ(degenerate_count(r.mesh), 0u);
  std::size_t slivers_out = 0;
  for (Index f = 0; f < r.mesh.face_count(); ++f) {
    const st::Triangle& t = r.mesh.triangles[f];
    const Vec3 &a = r.mesh.positions[t[0]], &b = r.mesh.positions[t[1]], &c = r.mesh.positions[t[2]];
    slivers_out += 2 * std::sqrt(3.0) * (b - a).cross(c - a).norm() /
                       ((b - a).squaredNorm() + (c - b).squaredNorm() + (a - c).squaredNorm()) <
                   0.1;
  }
  EXPECT_LT(slivers_out, slivers / 10) << slivers << " slivers in, " << slivers_out << " out";
  EXPECT_NEAR(st::signed_volume(r.mesh), st::signed_volume(input), 0.01 * st::signed_volume(input));
  for (const Vec3& p : r.mesh.positions) EXPECT_NEAR((p - centre).norm(), 10.0, 0.05 + 0.05);
}

TEST(Decimate, ZeroAreaInputTrianglesAreRemoved) {
  // "/" diagonals on an integer grid; moving vertex (i+1, j) exactly onto the midpoint of the
  // diagonal (i, j)-(i+1, j+1) makes triangle (i,j),(i+1,j),(i+1,j+1) zero-area, nothing flips.
  const int n = 20;
  TriangleMesh mesh;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) mesh.positions.emplace_back(i, j, 0.0);
  auto id = [](int i, int j) { return static_cast<Index>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      mesh.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      mesh.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  for (int j = 2; j < n - 2; j += 4)
    for (int i = 2; i < n - 2; i += 4) mesh.positions[id(i + 1, j)] = Vec3(i + 0.5, j + 0.5, 0.0);
  ASSERT_GT(degenerate_count(mesh), 10u);
  // Plus a triangle with a repeated corner, which is dropped.
  TriangleMesh with_repeat = mesh;
  with_repeat.triangles.push_back({id(5, 5), id(5, 5), id(6, 6)});
  for (const TriangleMesh* input : {&mesh, &with_repeat}) {
    st::DecimateOptions options;
    options.target_edge_length = 1.5; // hardly any other change
    const st::DecimateResult r = st::decimate(*input, options);
    EXPECT_EQ(degenerate_count(r.mesh), 0u);
    EXPECT_EQ(r.degenerate_left, 0u);
    EXPECT_TRUE(edge_report(r.mesh).manifold());
    EXPECT_NEAR(st::surface_area(r.mesh), n * n, 1e-9);
  }
}

TEST(Decimate, NonManifoldInputVerticesAreLeftAlone) {
  // Two fine squares sharing one corner vertex (a bow tie): that vertex must stay, the rest simplify.
  TriangleMesh a = grid_patch(20, 0.5, [](double u, double v) { return Vec3(u, v, 0.0); });
  const TriangleMesh b = grid_patch(20, 0.5, [](double u, double v) { return Vec3(-u, -v, 0.0); });
  const Index offset = a.vertex_count();
  for (Vec3 p : b.positions) a.positions.push_back(p);
  for (st::Triangle t : b.triangles) {
    for (Index& v : t) v = v == 0 ? 0 : v + offset; // share vertex (0, 0)
    a.triangles.push_back(t);
  }
  const st::DecimateResult r = st::decimate(a);
  EXPECT_LT(r.mesh.face_count(), a.face_count() / 2);
  EXPECT_EQ(r.mesh.positions.size(), r.vertex_source.size());
  EXPECT_EQ(std::count(r.vertex_source.begin(), r.vertex_source.end(), Index{0}), 1);
  EXPECT_NEAR(st::surface_area(r.mesh), st::surface_area(a), 1e-9 * st::surface_area(a));
}

TEST(Decimate, KeepBorderFalseMayCoarsenTheBorder) {
  const TriangleMesh input = grid_patch(40, 0.5, [](double u, double v) { return Vec3(u, v, 0.0); });
  st::DecimateOptions options;
  options.keep_border = false;
  const st::DecimateResult r = st::decimate(input, options);
  const auto loops = loops_of(r.mesh);
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_LT(loops[0].size(), loops_of(input)[0].size());
  EXPECT_TRUE(edge_report(r.mesh).manifold());
  EXPECT_NEAR(st::surface_area(r.mesh), st::surface_area(input), 1e-9 * st::surface_area(input));
}

TEST(Decimate, InvalidOptionsAndInputThrow) {
  const TriangleMesh mesh = grid_patch(4, 1.0, [](double u, double v) { return Vec3(u, v, 0.0); });
  st::DecimateOptions bad;
  bad.max_error = -1.0;
  EXPECT_THROW(st::decimate(mesh, bad), st::InvalidInput);
  bad = {};
  bad.min_triangle_quality = 2.0;
  EXPECT_THROW(st::decimate(mesh, bad), st::InvalidInput);
  bad = {};
  bad.max_normal_change_deg = 0.0;
  EXPECT_THROW(st::decimate(mesh, bad), st::InvalidInput);
  bad = {};
  bad.target_edge_length = std::nan("");
  EXPECT_THROW(st::decimate(mesh, bad), st::InvalidInput);
  TriangleMesh broken = mesh;
  broken.triangles.push_back({0, 1, 999});
  EXPECT_THROW(st::decimate(broken), st::InvalidInput);
  EXPECT_TRUE(st::decimate(TriangleMesh{}).mesh.empty());
}

} // namespace
