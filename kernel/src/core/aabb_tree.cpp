#include "st/core/aabb_tree.h"

#include "st/core/closest_point.h"
#include "st/core/ray_triangle.h"
#include "detail/morton.h"
#include "detail/parallel.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <limits>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <utility>

namespace st {

AabbTree::FloatBox AabbTree::FloatBox::around(const BoundingBox& b) {
  FloatBox f;
  for (int k = 0; k < 3; ++k) {
    f.min[k] = static_cast<float>(b.min[k]);
    if (double(f.min[k]) > b.min[k]) f.min[k] = std::nextafter(f.min[k], -std::numeric_limits<float>::infinity());
    f.max[k] = static_cast<float>(b.max[k]);
    if (double(f.max[k]) < b.max[k]) f.max[k] = std::nextafter(f.max[k], std::numeric_limits<float>::infinity());
  }
  return f;
}

namespace {

using Corner = std::array<float, 3>;

double box_distance_squared(const Corner& min, const Corner& max, const Vec3& p) {
  const Vec3 lo(min[0], min[1], min[2]), hi(max[0], max[1], max[2]);
  return (lo - p).cwiseMax(p - hi).cwiseMax(0.0).squaredNorm();
}

// Whether the ray meets the box grown by `pad` for t in [t0, t1].
bool ray_hits_box(const Corner& min, const Corner& max, double pad, const Vec3& o, const Vec3& inv_dir, double t0,
                  double t1) {
  for (int k = 0; k < 3; ++k) {
    double ta = (double(min[k]) - pad - o[k]) * inv_dir[k];
    double tb = (double(max[k]) + pad - o[k]) * inv_dir[k];
    if (ta > tb) std::swap(ta, tb);
    if (std::isnan(ta) || std::isnan(tb)) continue; // ray parallel and on the slab border
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

// Whether faces a and b of `mesh` have a corner in common.
bool share_corner(const TriangleMesh& mesh, Index a, Index b) {
  const Triangle &ta = mesh.triangles[a], &tb = mesh.triangles[b];
  for (const Index u : ta)
    if (u == tb[0] || u == tb[1] || u == tb[2]) return true;
  return false;
}

} // namespace

AabbTree::AabbTree(const TriangleMesh& mesh, std::vector<Index> faces) : mesh_(mesh), faces_(std::move(faces)) {
  if (faces_.empty()) {
    faces_.resize(mesh.face_count());
    std::iota(faces_.begin(), faces_.end(), Index{0});
  }
  if (faces_.empty()) return;
  const std::size_t n = faces_.size();
  // Morton codes of the boxes' centres on a grid of 2^21 cells a side over the centres' bounding cube.
  // The boxes are recomputed where needed rather than kept (48 bytes a face, first touched: on a
  // virtual machine that costs more than the arithmetic).
  constexpr std::size_t kGrain = 8192;
  std::vector<BoundingBox> chunk_centres((n + kGrain - 1) / kGrain);
  detail::parallel_for(n, kGrain, [&](std::size_t, std::size_t begin, std::size_t end) {
    BoundingBox& c = chunk_centres[begin / kGrain];
    for (std::size_t i = begin; i < end; ++i)
      if (const Vec3 centre = triangle_box(mesh, faces_[i]).center(); centre.allFinite()) c.extend(centre);
  });
  BoundingBox centres;
  for (const BoundingBox& c : chunk_centres)
    if (c.valid()) {
      centres.extend(c.min);
      centres.extend(c.max);
    }
  const double extent = centres.valid() ? centres.size().maxCoeff() : 0.0;
  const double scale = extent > 0.0 ? detail::kMortonCells / extent : 0.0;
  std::vector<detail::MortonKeyed> keyed(n);
  detail::parallel_for(n, kGrain, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      keyed[i] = {detail::morton_code(triangle_box(mesh, faces_[i]).center(), centres.min, scale), i};
    }
  });
  detail::sort_by_code(keyed);
  std::vector<Index> sorted_faces(n);
  face_boxes_.resize(n);
  std::vector<std::uint64_t> codes(n);
  detail::parallel_for(n, kGrain, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      sorted_faces[i] = faces_[keyed[i].item];
      face_boxes_[i] = FloatBox::around(triangle_box(mesh, sorted_faces[i]));
      codes[i] = keyed[i].code;
    }
  });
  faces_ = std::move(sorted_faces);
  nodes_.reserve(2 * n);
  build(codes, 0, static_cast<Index>(n));
}

Index AabbTree::build(const std::vector<std::uint64_t>& codes, Index begin, Index end) {
  // Nodes in pre-order: the left child follows its parent. A range splits where its codes' highest
  // differing bit turns from 0 to 1 (a plane of the Morton grid), or in the middle when its codes are
  // all the same.
  const auto id = static_cast<Index>(nodes_.size());
  nodes_.emplace_back();
  if (end - begin <= kLeafSize) {
    FloatBox box = face_boxes_[begin];
    for (Index i = begin + 1; i < end; ++i) box.extend(face_boxes_[i]);
    nodes_[id].box = box;
    nodes_[id].begin = begin;
    nodes_[id].end = end;
    return id;
  }
  const std::uint64_t differ = codes[begin] ^ codes[end - 1];
  Index mid = begin + (end - begin) / 2;
  if (differ != 0) {
    const std::uint64_t bit = std::uint64_t{1} << (63 - std::countl_zero(differ));
    mid = static_cast<Index>(std::partition_point(codes.begin() + begin, codes.begin() + end,
                                                  [bit](std::uint64_t c) { return !(c & bit); }) -
                             codes.begin());
  }
  const Index left = build(codes, begin, mid);
  const Index right = build(codes, mid, end);
  Node& node = nodes_[id];
  node.box = nodes_[left].box;
  node.box.extend(nodes_[right].box);
  node.left = left;
  node.right = right;
  node.begin = begin; // the range under it, for slabs()
  node.end = end;
  return id;
}

namespace {

// The slab about `centre` that holds `faces` of `mesh`: across their summed normal; invalid when the
// normals cancel (or are not numbers).
AabbTree::Slab slab_of(const TriangleMesh& mesh, std::span<const Index> faces, const Vec3& centre) {
  AabbTree::Slab slab;
  Vec3 sum = Vec3::Zero();
  for (const Index f : faces) {
    const Triangle& t = mesh.triangles[f];
    sum += (mesh.positions[t[1]] - mesh.positions[t[0]]).cross(mesh.positions[t[2]] - mesh.positions[t[0]]);
  }
  const double length = sum.stableNorm(); // a unit normal even where the squares would underflow
  if (!(length > 0.0) || !std::isfinite(length)) return slab;
  slab.normal = sum / length;
  slab.centre = centre;
  double height = 0.0, radius2 = 0.0;
  for (const Index f : faces)
    for (const Index v : mesh.triangles[f]) {
      const Vec3 d = mesh.positions[v] - centre;
      const double h = slab.normal.dot(d), across2 = d.squaredNorm() - h * h;
      if (!std::isfinite(h) || !std::isfinite(across2)) return AabbTree::Slab{}; // overflow: the box bounds them
      height = std::max(height, std::abs(h));
      radius2 = std::max(radius2, across2);
    }
  // Grown a little so that rounding never puts a corner outside it. Growing finite numbers overflows
  // at most to infinity, a slab that never passes over anything.
  slab.half_thickness = height * (1.0 + 1e-9) + 1e-12;
  slab.radius = std::sqrt(std::max(radius2, 0.0)) * (1.0 + 1e-9) + 1e-12;
  slab.valid = true;
  return slab;
}

} // namespace

AabbTree::Slabs AabbTree::slabs() const {
  Slabs out;
  out.tree = this;
  out.per_node.resize(nodes_.size());
  out.parent.assign(nodes_.size(), kInvalidIndex);
  out.per_face.resize(faces_.size());
  out.leaf_of.assign(mesh_.face_count(), kInvalidIndex);
  const std::span<const Index> faces = faces_;
  detail::parallel_for(nodes_.size(), 4096, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t id = begin; id < end; ++id) {
      const Node& n = nodes_[id];
      if (n.left != kInvalidIndex) {
        out.parent[n.left] = out.parent[n.right] = static_cast<Index>(id);
      } else {
        for (Index i = n.begin; i < n.end; ++i) {
          out.leaf_of[faces_[i]] = static_cast<Index>(id);
          const Triangle& t = mesh_.triangles[faces_[i]];
          const Vec3 centroid = (mesh_.positions[t[0]] + mesh_.positions[t[1]] + mesh_.positions[t[2]]) / 3.0;
          out.per_face[i] = slab_of(mesh_, faces.subspan(i, 1), centroid);
        }
      }
      if (n.end - n.begin > Slabs::kMaxFaces) continue; // the box alone bounds it
      const Vec3 centre(0.5 * (double(n.box.min[0]) + double(n.box.max[0])),
                        0.5 * (double(n.box.min[1]) + double(n.box.max[1])),
                        0.5 * (double(n.box.min[2]) + double(n.box.max[2])));
      out.per_node[id] = slab_of(mesh_, faces.subspan(n.begin, n.end - n.begin), centre);
    }
  });
  return out;
}

AabbTree::AreaNormal AabbTree::area_normal_near(const Vec3& p, double radius) const {
  AreaNormal out;
  BoundingBox box;
  box.extend(p);
  for_each_in_box(box.inflated(radius), [&](Index f) {
    const Triangle& t = mesh_.triangles[f];
    const Vec3 &a = mesh_.positions[t[0]], &b = mesh_.positions[t[1]], &c = mesh_.positions[t[2]];
    if ((closest_point_on_triangle(p, a, b, c) - p).norm() > radius) return;
    const Vec3 n = 0.5 * (b - a).cross(c - a);
    out.sum += n;
    out.area += n.norm();
  });
  return out;
}

std::optional<ClosestPoint> AabbTree::nearest(const Vec3& p, double max_distance, const Slabs* slabs,
                                              Index near_face) const {
  if (nodes_.empty()) return std::nullopt;
  double best = max_distance * max_distance;
  ClosestPoint result;
  bool found = false;
  // Depth-first from `root`, nearer child first.
  auto search = [&](Index root) {
    Index stack[128];
    int top = 0;
    stack[top++] = root;
    while (top > 0) {
      const Index id = stack[--top];
      const Node& n = nodes_[id];
      if (box_distance_squared(n.box.min, n.box.max, p) > best) continue;
      if (slabs && slabs->per_node[id].beyond(p, best)) continue;
      if (n.left == kInvalidIndex) {
        for (Index i = n.begin; i < n.end; ++i) {
          if (slabs && slabs->per_face[i].beyond(p, best)) continue;
          const Triangle& t = mesh_.triangles[faces_[i]];
          const Vec3 q =
              closest_point_on_triangle(p, mesh_.positions[t[0]], mesh_.positions[t[1]], mesh_.positions[t[2]]);
          const double d2 = (q - p).squaredNorm();
          if (d2 <= best) {
            best = d2;
            result.face = faces_[i];
            result.point = q;
            found = true;
          }
        }
        continue;
      }
      const double dl = box_distance_squared(nodes_[n.left].box.min, nodes_[n.left].box.max, p);
      const double dr = box_distance_squared(nodes_[n.right].box.min, nodes_[n.right].box.max, p);
      if (dl < dr) {
        stack[top++] = n.right;
        stack[top++] = n.left;
      } else {
        stack[top++] = n.left;
        stack[top++] = n.right;
      }
    }
  };
  Index node = slabs && near_face < slabs->leaf_of.size() ? slabs->leaf_of[near_face] : kInvalidIndex;
  if (node == kInvalidIndex) {
    search(0);
  } else { // near_face's leaf, then the sibling of each node on the way up: every node once
    search(node);
    for (Index up = slabs->parent[node]; up != kInvalidIndex; node = up, up = slabs->parent[up])
      search(nodes_[up].left == node ? nodes_[up].right : nodes_[up].left);
  }
  if (!found) return std::nullopt;
  result.distance = std::sqrt(best);
  return result;
}

std::optional<ClosestPoint> AabbTree::closest_point(const Vec3& p, double max_distance) const {
  return nearest(p, max_distance, nullptr, kInvalidIndex);
}

std::optional<ClosestPoint> AabbTree::closest_point(const Vec3& p, double max_distance, const Slabs& slabs,
                                                    Index near_face) const {
  if (slabs.tree != this) throw std::logic_error("AabbTree: slabs of another tree");
  return nearest(p, max_distance, &slabs, near_face);
}

template <class Leaf> bool AabbTree::along(const Vec3& origin, const Vec3& direction, double t_min, const double& t_max,
                                           double pad, Leaf&& leaf) const {
  if (nodes_.empty()) return false;
  const Vec3 inv = direction.cwiseInverse();
  // With a pad, each face's own box is tested too before the caller's test: the pad, wider than the
  // rounding of a box test, keeps the filter from passing over a face the segment meets.
  const bool per_face = pad > 0.0;
  Index stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[stack[--top]];
    if (!ray_hits_box(n.box.min, n.box.max, std::max(pad, 0.0), origin, inv, t_min, t_max)) continue;
    if (n.left == kInvalidIndex) {
      for (Index i = n.begin; i < n.end; ++i) {
        if (per_face && !ray_hits_box(face_boxes_[i].min, face_boxes_[i].max, pad, origin, inv, t_min, t_max)) continue;
        if (leaf(faces_[i])) return true;
      }
      continue;
    }
    stack[top++] = n.left;
    stack[top++] = n.right;
  }
  return false;
}

bool AabbTree::any_along(const Vec3& origin, const Vec3& direction, double t_max, double pad,
                         const std::function<bool(Index)>& visit) const {
  return along(origin, direction, 0.0, t_max, pad, visit);
}

std::optional<RayHit> AabbTree::first_hit(const Vec3& origin, const Vec3& direction, double t_min, double t_max) const {
  RayHit hit;
  bool found = false;
  along(origin, direction, t_min, t_max, 0.0, [&](Index f) {
    const Triangle& t = mesh_.triangles[f];
    const auto s = ray_triangle(origin, direction, mesh_.positions[t[0]], mesh_.positions[t[1]], mesh_.positions[t[2]]);
    if (s && s->t >= t_min && s->t <= t_max) {
      t_max = s->t; // nearer nodes only from now on
      hit.face = f;
      hit.t = s->t;
      found = true;
    }
    return false;
  });
  if (!found) return std::nullopt;
  hit.point = origin + hit.t * direction;
  return hit;
}

template <class Leaf> bool AabbTree::in_box(const BoundingBox& box, Leaf&& leaf) const {
  if (nodes_.empty()) return false;
  Index stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[stack[--top]];
    if (!n.box.overlaps(box)) continue;
    if (n.left == kInvalidIndex) {
      for (Index i = n.begin; i < n.end; ++i)
        if (face_boxes_[i].overlaps(box) && leaf(faces_[i])) return true;
      continue;
    }
    stack[top++] = n.left;
    stack[top++] = n.right;
  }
  return false;
}

void AabbTree::for_each_in_box(const BoundingBox& box, const std::function<void(Index)>& visit) const {
  in_box(box, [&](Index f) {
    visit(f);
    return false;
  });
}

bool AabbTree::any_in_box(const BoundingBox& box) const {
  return in_box(box, [](Index) { return true; });
}

int AabbTree::split_pair(Index a, Index b, std::array<std::pair<Index, Index>, 3>& into) const {
  const Node& na = nodes_[a];
  const Node& nb = nodes_[b];
  if (a != b && !na.box.overlaps(nb.box)) return -1;
  const bool la = na.left == kInvalidIndex, lb = nb.left == kInvalidIndex;
  if (la && lb) return 0;
  if (a == b) {
    into = {{{na.left, na.left}, {na.right, na.right}, {na.left, na.right}}};
    return 3;
  }
  if (lb || (!la && na.box.diagonal() >= nb.box.diagonal())) {
    into[0] = {na.left, b};
    into[1] = {na.right, b};
  } else {
    into[0] = {a, nb.left};
    into[1] = {a, nb.right};
  }
  return 2;
}

double AabbTree::plane_margin() const {
  double largest = 0.0;
  for (const Vec3& p : mesh_.positions) {
    if (!p.allFinite()) return 0.0;
    largest = std::max(largest, p.cwiseAbs().maxCoeff());
  }
  return largest <= 1e60 ? 1e-12 * largest + 1e-300 : 0.0;
}

bool AabbTree::apart_by_planes(Index a, Index b, double margin) const {
  const Triangle &ta = mesh_.triangles[a], &tb = mesh_.triangles[b];
  const std::array<const Vec3*, 3> pa{&mesh_.positions[ta[0]], &mesh_.positions[ta[1]], &mesh_.positions[ta[2]]};
  const std::array<const Vec3*, 3> pb{&mesh_.positions[tb[0]], &mesh_.positions[tb[1]], &mesh_.positions[tb[2]]};
  // The corners of `other` all off the plane of `own`, widened: a dot product rounds by less than
  // 4e-16 of the largest coordinate times the normal's 1-norm, the spread by twice that; the margin
  // is over a thousand times the sum.
  auto off = [&](const std::array<const Vec3*, 3>& own, const std::array<const Vec3*, 3>& other) {
    const Vec3 normal = (*own[1] - *own[0]).cross(*own[2] - *own[0]);
    const double at = normal.dot(*own[0]);
    const double widen =
        std::max(std::abs(normal.dot(*own[1]) - at), std::abs(normal.dot(*own[2]) - at)) + margin * normal.lpNorm<1>();
    const double h0 = normal.dot(*other[0]) - at, h1 = normal.dot(*other[1]) - at, h2 = normal.dot(*other[2]) - at;
    return (h0 > widen && h1 > widen && h2 > widen) || (h0 < -widen && h1 < -widen && h2 < -widen); // NaN: not off
  };
  return off(pa, pb) || off(pb, pa);
}

template <class Visit>
void AabbTree::self_pairs(Index a, Index b, Visit& visit, const Apart* apart, double plane_margin) const {
  std::array<std::pair<Index, Index>, 3> children;
  const int count = split_pair(a, b, children);
  if (count < 0) return;
  const Node& na = nodes_[a];
  const Node& nb = nodes_[b];
  if (apart && (*apart)(na.begin, na.end, nb.begin, nb.end)) return;
  if (count == 0) { // two leaves
    for (Index i = na.begin; i < na.end; ++i)
      for (Index j = (a == b ? i + 1 : nb.begin); j < nb.end; ++j)
        if (face_boxes_[i].overlaps(face_boxes_[j]) &&
            !(plane_margin > 0.0 && !share_corner(mesh_, faces_[i], faces_[j]) &&
              apart_by_planes(faces_[i], faces_[j], plane_margin)))
          visit(faces_[i], faces_[j]);
  }
  for (int k = 0; k < count; ++k) self_pairs(children[k].first, children[k].second, visit, apart, plane_margin);
}

void AabbTree::for_each_overlapping_pair(const std::function<void(Index, Index)>& visit) const {
  if (!nodes_.empty()) self_pairs(0, 0, visit);
}

std::vector<std::pair<Index, Index>> AabbTree::overlapping_pairs() const {
  return overlapping_pairs([](Index, Index) { return true; });
}

std::vector<std::pair<Index, Index>> AabbTree::overlapping_pairs(const std::function<bool(Index, Index)>& keep) const {
  return overlapping_pairs(keep, nullptr);
}

std::vector<std::pair<Index, Index>> AabbTree::overlapping_pairs(const std::function<bool(Index, Index)>& keep,
                                                                 const Apart& apart) const {
  if (nodes_.empty()) return {};
  const Apart* const passing = apart ? &apart : nullptr;
  const double margin = apart ? plane_margin() : 0.0;
  // The first levels of self_pairs' recursion, expanded into node pairs (tasks), then each task's
  // pairs on its own thread, gathered in task order.
  std::vector<std::pair<Index, Index>> tasks{{0, 0}};
  for (int level = 0; level < 6 && tasks.size() < 256; ++level) {
    std::vector<std::pair<Index, Index>> next;
    for (const auto& [a, b] : tasks) {
      if (passing && a == b && nodes_[a].end - nodes_[a].begin <= kMaxApart) { // asked on its thread
        next.emplace_back(a, b);
        continue;
      }
      std::array<std::pair<Index, Index>, 3> children;
      const int count = split_pair(a, b, children);
      if (count == 0) next.emplace_back(a, b); // two leaves: a task of its own
      next.insert(next.end(), children.begin(), children.begin() + std::max(count, 0));
    }
    tasks = std::move(next);
  }
  std::vector<std::vector<std::pair<Index, Index>>> found(tasks.size());
  detail::parallel_for(tasks.size(), 1, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      std::vector<std::pair<Index, Index>>& into = found[i];
      auto visit = [&](Index x, Index y) {
        if (keep(x, y)) into.emplace_back(x, y);
      };
      self_pairs(tasks[i].first, tasks[i].second, visit, passing, margin);
    }
  });
  std::size_t total = 0;
  for (const auto& f : found) total += f.size();
  std::vector<std::pair<Index, Index>> pairs;
  pairs.reserve(total);
  for (const auto& f : found) pairs.insert(pairs.end(), f.begin(), f.end());
  return pairs;
}

void AabbTree::cross_pairs(Index a, const AabbTree& other, Index b,
                           const std::function<void(Index, Index)>& visit) const {
  const Node& na = nodes_[a];
  const Node& nb = other.nodes_[b];
  if (!na.box.overlaps(nb.box)) return;
  const bool la = na.left == kInvalidIndex, lb = nb.left == kInvalidIndex;
  if (la && lb) {
    for (Index i = na.begin; i < na.end; ++i)
      for (Index j = nb.begin; j < nb.end; ++j)
        if (face_boxes_[i].overlaps(other.face_boxes_[j])) visit(faces_[i], other.faces_[j]);
    return;
  }
  if (lb || (!la && na.box.diagonal() >= nb.box.diagonal())) {
    cross_pairs(na.left, other, b, visit);
    cross_pairs(na.right, other, b, visit);
  } else {
    cross_pairs(a, other, nb.left, visit);
    cross_pairs(a, other, nb.right, visit);
  }
}

void AabbTree::for_each_overlapping_pair(const AabbTree& other, const std::function<void(Index, Index)>& visit) const {
  if (!nodes_.empty() && !other.nodes_.empty()) cross_pairs(0, other, 0, visit);
}

} // namespace st
