#include "st/core/aabb_tree.h"

#include "st/core/closest_point.h"
#include "st/core/ray_triangle.h"
#include "detail/parallel.h"

#include <algorithm>
#include <array>
#include <numeric>
#include <optional>
#include <system_error>
#include <thread>
#include <utility>

namespace st {

namespace {

double box_distance_squared(const BoundingBox& b, const Vec3& p) {
  const Vec3 d = (b.min - p).cwiseMax(p - b.max).cwiseMax(Vec3::Zero());
  return d.squaredNorm();
}

bool ray_hits_box(const BoundingBox& b, const Vec3& o, const Vec3& inv_dir, double t0, double t1) {
  for (int k = 0; k < 3; ++k) {
    double ta = (b.min[k] - o[k]) * inv_dir[k];
    double tb = (b.max[k] - o[k]) * inv_dir[k];
    if (ta > tb) std::swap(ta, tb);
    if (std::isnan(ta) || std::isnan(tb)) continue; // ray parallel and on the slab border
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

} // namespace

AabbTree::AabbTree(const TriangleMesh& mesh, std::vector<Index> faces) : mesh_(mesh), faces_(std::move(faces)) {
  if (faces_.empty()) {
    faces_.resize(mesh.face_count());
    std::iota(faces_.begin(), faces_.end(), Index{0});
  }
  if (faces_.empty()) return;
  std::vector<Item> items(faces_.size());
  detail::parallel_for(items.size(), 8192, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      items[i].box = triangle_box(mesh, faces_[i]);
      items[i].face = faces_[i];
    }
  });
  const auto n = static_cast<Index>(items.size());
  nodes_.resize(node_count(n));
  int spawn = 0; // levels whose two halves are built on two threads
  while ((2u << spawn) <= detail::thread_count()) ++spawn;
  build(items, 0, n, 0, spawn);
  face_boxes_.resize(items.size());
  for (std::size_t i = 0; i < items.size(); ++i) {
    faces_[i] = items[i].face;
    face_boxes_[i] = items[i].box;
  }
}

Index AabbTree::node_count(Index n) {
  // The ranges at one depth hold s or s + 1 items (a and b of them): the halves of s are s/2 and
  // s - s/2, those of s + 1 are (s+1)/2 and s + 1 - (s+1)/2, all s/2 or s/2 + 1.
  Index total = 0;
  Index s = n;
  Index a = 1, b = 0;
  while (a + b > 0) {
    total += a + b;
    const Index split_a = s > kLeafSize ? a : 0;
    const Index split_b = s + 1 > kLeafSize ? b : 0;
    const bool even = s % 2 == 0;
    a = even ? 2 * split_a + split_b : split_a;
    b = even ? split_b : split_a + 2 * split_b;
    s /= 2;
  }
  return total;
}

Index AabbTree::build(std::vector<Item>& items, Index begin, Index end, Index id, int spawn) {
  // Nodes in pre-order: the left child follows its parent, the right child follows the left subtree
  // (node_count of its range), so the layout is the same whichever thread builds which half.
  BoundingBox box;
  for (Index i = begin; i < end; ++i) box.extend(items[i].box);
  nodes_[id].box = box;
  if (end - begin <= kLeafSize) {
    nodes_[id].begin = begin;
    nodes_[id].end = end;
    return 1;
  }
  int axis = 0;
  box.size().maxCoeff(&axis);
  const Index mid = begin + (end - begin) / 2;
  std::nth_element(items.begin() + begin, items.begin() + mid, items.begin() + end,
                   [axis](const Item& x, const Item& y) { // by centre: (min + max) / 2, halving exact
                     return x.box.min[axis] + x.box.max[axis] < y.box.min[axis] + y.box.max[axis];
                   });
  const Index left = id + 1;
  Index right = kInvalidIndex;
  Index count = 0;
  if (spawn > 0 && end - begin > 16384) {
    right = left + node_count(mid - begin);
    count = node_count(end - begin);
    std::optional<std::thread> other;
    try {
      other.emplace([&, right] { build(items, mid, end, right, spawn - 1); });
    } catch (const std::system_error&) {
      build(items, mid, end, right, spawn - 1); // no second thread: this one builds both halves
    }
    build(items, begin, mid, left, spawn - 1);
    if (other) other->join();
  } else {
    const Index left_count = build(items, begin, mid, left, 0);
    right = left + left_count;
    count = 1 + left_count + build(items, mid, end, right, 0);
  }
  nodes_[id].left = left;
  nodes_[id].right = right;
  return count;
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

template <class Beyond>
std::optional<ClosestPoint> AabbTree::nearest(const Vec3& p, double max_distance, const Beyond& beyond) const {
  if (nodes_.empty()) return std::nullopt;
  double best = max_distance * max_distance;
  ClosestPoint result;
  bool found = false;
  // Depth-first, nearer child first.
  Index stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[stack[--top]];
    if (box_distance_squared(n.box, p) > best) continue;
    if (n.left == kInvalidIndex) {
      for (Index i = n.begin; i < n.end; ++i) {
        if (beyond(faces_[i], best)) continue;
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
    const double dl = box_distance_squared(nodes_[n.left].box, p);
    const double dr = box_distance_squared(nodes_[n.right].box, p);
    if (dl < dr) {
      stack[top++] = n.right;
      stack[top++] = n.left;
    } else {
      stack[top++] = n.left;
      stack[top++] = n.right;
    }
  }
  if (!found) return std::nullopt;
  result.distance = std::sqrt(best);
  return result;
}

std::optional<ClosestPoint> AabbTree::closest_point(const Vec3& p, double max_distance) const {
  return nearest(p, max_distance, [](Index, double) { return false; });
}

std::optional<ClosestPoint> AabbTree::closest_point(const Vec3& p, double max_distance,
                                                    const std::function<bool(Index, double)>& beyond) const {
  return nearest(p, max_distance, beyond);
}

template <class Leaf> bool AabbTree::along(const Vec3& origin, const Vec3& direction, double t_min, const double& t_max,
                                           double pad, Leaf&& leaf) const {
  if (nodes_.empty()) return false;
  const Vec3 inv = direction.cwiseInverse();
  Index stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[stack[--top]];
    if (!ray_hits_box(pad > 0.0 ? n.box.inflated(pad) : n.box, origin, inv, t_min, t_max)) continue;
    if (n.left == kInvalidIndex) {
      for (Index i = n.begin; i < n.end; ++i)
        if (leaf(faces_[i])) return true;
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

void AabbTree::self_pairs(Index a, Index b, const std::function<void(Index, Index)>& visit) const {
  std::array<std::pair<Index, Index>, 3> children;
  const int count = split_pair(a, b, children);
  if (count == 0) { // two leaves
    const Node& na = nodes_[a];
    const Node& nb = nodes_[b];
    for (Index i = na.begin; i < na.end; ++i)
      for (Index j = (a == b ? i + 1 : nb.begin); j < nb.end; ++j)
        if (face_boxes_[i].overlaps(face_boxes_[j])) visit(faces_[i], faces_[j]);
  }
  for (int k = 0; k < count; ++k) self_pairs(children[k].first, children[k].second, visit);
}

void AabbTree::for_each_overlapping_pair(const std::function<void(Index, Index)>& visit) const {
  if (!nodes_.empty()) self_pairs(0, 0, visit);
}

std::vector<std::pair<Index, Index>> AabbTree::overlapping_pairs() const {
  if (nodes_.empty()) return {};
  // The first levels of self_pairs' recursion, expanded into node pairs (tasks), then each task's
  // pairs on its own thread, gathered in task order.
  std::vector<std::pair<Index, Index>> tasks{{0, 0}};
  for (int level = 0; level < 6 && tasks.size() < 256; ++level) {
    std::vector<std::pair<Index, Index>> next;
    for (const auto& [a, b] : tasks) {
      std::array<std::pair<Index, Index>, 3> children;
      const int count = split_pair(a, b, children);
      if (count == 0) next.emplace_back(a, b); // two leaves: a task of its own
      next.insert(next.end(), children.begin(), children.begin() + std::max(count, 0));
    }
    tasks = std::move(next);
  }
  std::vector<std::vector<std::pair<Index, Index>>> found(tasks.size());
  detail::parallel_for(tasks.size(), 1, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      self_pairs(tasks[i].first, tasks[i].second, [&](Index x, Index y) { found[i].emplace_back(x, y); });
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
