// The regions of the Boolean's operands: oriented boxes of components, the faces near them, the
// faces far from them copied into the result, the decision across the curve for components no side
// test decides, the ray-parity inside test, and the check that the pieces kept by their verdicts
// close up.

#include "boolean/corefinement.h"

#include "detail/format.h"
#include "st/core/ray_triangle.h"
#include "st/core/union_find.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <numeric>
#include <optional>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace st::boolean_detail {

std::vector<OrientedBox> component_boxes(const TriangleMesh& mesh) {
  UnionFind uf(mesh.vertex_count());
  for (const Triangle& t : mesh.triangles) {
    uf.join(t[0], t[1]);
    uf.join(t[1], t[2]);
  }
  std::unordered_map<Index, std::vector<Index>> members;
  std::vector<std::uint8_t> used(mesh.vertex_count(), 0);
  for (const Triangle& t : mesh.triangles)
    for (Index v : t)
      if (!used[v]) {
        used[v] = 1;
        members[uf.find(v)].push_back(v);
      }
  std::vector<OrientedBox> out;
  for (auto& [root, vertices] : members) {
    OrientedBox box;
    Vec3 mean = Vec3::Zero();
    for (Index v : vertices) {
      mean += mesh.positions[v];
      box.world.extend(mesh.positions[v]);
    }
    mean /= static_cast<double>(vertices.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (Index v : vertices) {
      const Vec3 d = mesh.positions[v] - mean;
      cov += d * d.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(cov);
    box.axes = eigen.eigenvectors().transpose();
    if (!box.axes.allFinite()) box.axes.setIdentity();
    Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
    for (Index v : vertices) {
      const Vec3 q = box.axes * (mesh.positions[v] - mean);
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
    box.centre = mean + box.axes.transpose() * (0.5 * (lo + hi));
    box.half = 0.5 * (hi - lo);
    out.push_back(box);
  }
  std::sort(out.begin(), out.end(), [](const OrientedBox& a, const OrientedBox& b) {
    return std::tie(a.world.min[0], a.world.min[1], a.world.min[2]) <
           std::tie(b.world.min[0], b.world.min[1], b.world.min[2]);
  });
  return out;
}

// Faces that meet one of `boxes`: every face that can cross or lie inside the other operand. The
// margin covers the rounding of the box's frame.
std::vector<Index> faces_near(const TriangleMesh& mesh, const std::vector<OrientedBox>& boxes) {
  BoundingBox all;
  double size = 0.0;
  for (const OrientedBox& b : boxes) {
    all.extend(b.world);
    size = std::max(size, b.world.diagonal());
  }
  const double margin = 1e-9 * (size + all.max.cwiseAbs().maxCoeff() + all.min.cwiseAbs().maxCoeff());
  std::vector<BoundingBox> grown; // each component's own: spread sleeves' box would hold most of a template
  for (const OrientedBox& b : boxes) grown.push_back(b.world.inflated(margin));
  std::vector<Index> out;
  for (Index f : faces_meeting_boxes(mesh, grown)) {
    const Triangle& t = mesh.triangles[f];
    const BoundingBox box = triangle_box(mesh, f);
    const std::array<Vec3, 3> corners = {mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]};
    for (std::size_t i = 0; i < boxes.size(); ++i)
      if (box.overlaps(grown[i]) && boxes[i].overlaps(corners, margin)) {
        out.push_back(f);
        break;
      }
  }
  return out;
}

void append_far_faces(const TriangleMesh& m, const std::vector<Index>& near_slot, Index* map, bool reverse,
                      std::uint8_t from_b, BooleanResult& result) {
  // Written through counters into arrays sized for every face (trimmed after): most of the result.
  TriangleMesh& out = result.mesh;
  Index vertices = out.vertex_count(), faces = out.face_count();
  out.positions.resize(vertices + m.vertex_count());
  out.triangles.resize(faces + m.face_count());
  result.source_face.resize(faces + m.face_count());
  for (Index f = 0; f < m.face_count(); ++f) {
    if (near_slot[f] != kInvalidIndex) continue;
    Triangle t = m.triangles[f];
    for (Index& v : t) {
      Index& to = map[v];
      if (to == kInvalidIndex) {
        to = vertices++;
        out.positions[to] = m.positions[v];
      }
      v = to;
    }
    if (reverse) std::swap(t[1], t[2]);
    out.triangles[faces] = t;
    result.source_face[faces++] = f;
  }
  out.positions.resize(vertices);
  out.triangles.resize(faces);
  result.source_face.resize(faces);
  result.from_b.resize(faces, from_b);
}

void decide_across_curve(const std::vector<std::pair<Index, Index>>& across, std::vector<Verdict>& verdicts) {
  std::vector<std::vector<Index>> neighbours(verdicts.size());
  for (const auto& [c0, c1] : across) {
    if (c0 == c1) continue;
    neighbours[c0].push_back(c1);
    neighbours[c1].push_back(c0);
  }
  std::vector<Index> decided;
  for (Index c = 0; c < verdicts.size(); ++c)
    if (verdicts[c].inside >= 0) decided.push_back(c);
  while (!decided.empty()) {
    const Index c = decided.back();
    decided.pop_back();
    for (Index d : neighbours[c])
      if (verdicts[d].inside < 0) {
        verdicts[d].inside = 1 - verdicts[c].inside;
        decided.push_back(d);
      }
  }
}

bool inside_by_rays(const Vec3& p, const TriangleMesh& mesh) {
  static const Vec3 directions[] = {Vec3(0.5773, 0.5774, 0.5775), Vec3(-0.3119, 0.8421, -0.4399),
                                    Vec3(0.7071, -0.1213, 0.6965), Vec3(-0.6213, -0.5524, 0.5557),
                                    Vec3(0.1234, -0.9321, -0.3402)};
  int votes_inside = 0, votes = 0;
  for (const Vec3& raw : directions) {
    const Vec3 d = raw.normalized();
    int crossings = 0;
    bool grazing = false;
    for (const Triangle& t : mesh.triangles) {
      const auto hit = ray_triangle(p, d, mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]], 1e-12);
      if (!hit || hit->t < -1e-12) continue;
      const auto [t_hit, u, v] = *hit;
      if (u < 1e-9 || v < 1e-9 || u + v > 1.0 - 1e-9 || std::abs(t_hit) < 1e-12) {
        grazing = true;
        break;
      }
      ++crossings;
    }
    if (grazing) continue;
    ++votes;
    votes_inside += crossings % 2;
    if (votes >= 3) break;
  }
  if (votes == 0) throw Degenerate{"every ray grazes an edge"};
  return 2 * votes_inside > votes;
}

void check_closed_at_curve(const TriangleMesh& out, const std::vector<Index>& fresh,
                           const std::vector<Index>& unchanged) {
  // The pieces' corners, numbered densely, and the half-edges between two of them of every face,
  // listed by their first corner: each edge's uses are then a scan of a handful.
  std::vector<Index> corner(out.vertex_count(), kInvalidIndex);
  Index corners = 0;
  for (const std::vector<Index>* list : {&fresh, &unchanged})
    for (Index f : *list)
      for (Index v : out.triangles[f])
        if (corner[v] == kInvalidIndex) corner[v] = corners++;
  std::vector<Index> start(corners + 1, 0);
  auto each_half_edge = [&](auto&& use) {
    for (const Triangle& t : out.triangles)
      for (int k = 0; k < 3; ++k) {
        const Index u = corner[t[k]], v = corner[t[(k + 1) % 3]];
        if (u != kInvalidIndex && v != kInvalidIndex) use(u, v);
      }
  };
  each_half_edge([&](Index u, Index) { ++start[u + 1]; });
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<Index> to(start.back());
  {
    std::vector<Index> fill(start.begin(), start.end() - 1);
    each_half_edge([&](Index u, Index v) { to[fill[u]++] = v; });
  }
  auto count = [&](Index u, Index v) { return std::count(to.begin() + start[u], to.begin() + start[u + 1], v); };
  for (const std::vector<Index>* list : {&fresh, &unchanged})
    for (Index f : *list) {
      const Triangle& t = out.triangles[f];
      for (int k = 0; k < 3; ++k) {
        const Index u = corner[t[k]], v = corner[t[(k + 1) % 3]];
        if (count(u, v) != 1 || count(v, u) != 1)
          throw Degenerate{"the result open or doubled at the intersection curve, near " +
                           detail::where(out.positions[t[k]])};
      }
    }
}

} // namespace st::boolean_detail
