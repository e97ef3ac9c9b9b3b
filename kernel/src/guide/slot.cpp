#include "st/guide/slot.h"

#include "detail/format.h"
#include "st/core/errors.h"
#include "st/core/tolerances.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

namespace st {

std::optional<TubeProblem> slot_problem(const SlotSpec& s) {
  using Problem = TubeProblem;
  if (!s.origin.allFinite()) return Problem{"origin", "must be finite"};
  if (!s.normal.allFinite() || !(s.normal.norm() > 1e-12))
    return Problem{"normal", "must be a finite, non-zero vector"};
  if (!s.auto_direction) {
    if (!s.direction.allFinite() || !(s.direction.norm() > 1e-12))
      return Problem{"direction", "must be a finite, non-zero vector"};
    const Vec3 n = s.normal.normalized(), d = s.direction.normalized();
    if ((d - d.dot(n) * n).norm() < 1e-6)
      return Problem{"direction", "must not be parallel to normal (the saw travels in the cut plane)"};
  }
  // The comparisons are written so that NaN fails each of them.
  if (!(s.blade > 0.0)) return Problem{"blade", "must be > 0"};
  if (!(s.clearance >= 0.0)) return Problem{"clearance", "must be >= 0"};
  if (!(s.length > 0.0)) return Problem{"length", "must be > 0"};
  if (!(s.height > 0.0)) return Problem{"height", "must be > 0"};
  if (!(s.wall > 0.0)) return Problem{"wall", "must be > 0"};
  const auto under = [](double limit) { return "is absurd (must be under " + detail::mm(limit) + ")"; };
  for (const auto& [key, value] :
       {std::pair{"blade", s.blade}, std::pair{"clearance", s.clearance}, std::pair{"wall", s.wall}})
    if (value >= tol::kMaxTubeRadius_mm) return Problem{key, under(tol::kMaxTubeRadius_mm)};
  for (const auto& [key, value] : {std::pair{"length", s.length}, std::pair{"height", s.height}})
    if (value >= tol::kMaxTubeLength_mm) return Problem{key, under(tol::kMaxTubeLength_mm)};
  return std::nullopt;
}

void check_slot(const SlotSpec& slot) {
  if (const auto problem = slot_problem(slot))
    throw InvalidInput("slot '" + slot.name + "': " + problem->key + " " + problem->reason);
}

SlotFrame slot_frame(const SlotSpec& slot) {
  SlotFrame f;
  f.origin = slot.origin;
  f.n = slot.normal.normalized();
  const Vec3 d = slot.direction.normalized();
  f.d = (d - d.dot(f.n) * f.n).normalized();
  f.e = f.n.cross(f.d);
  return f;
}

void normalise_slot(SlotSpec& slot) {
  if (slot.auto_direction) {
    slot.normal.normalize();
    return;
  }
  const SlotFrame f = slot_frame(slot);
  slot.normal = f.n;
  slot.direction = f.d;
}

Vec3 slot_direction(const SlotSpec& slot, const AabbTree& bone) {
  const double radius = kSlotDirectionRadius;
  const auto [sum, area] = bone.area_normal_near(slot.origin, radius);
  const std::string name = "slot '" + slot.name + "'";
  if (!(area > 0.0))
    throw GeometryError(name + ": no travel is planned and no bone lies within " + detail::mm(radius) +
                        " of its origin " + detail::where(slot.origin) + "; give its direction");
  const Vec3 n = slot.normal.normalized();
  const Vec3 in_plane = sum - sum.dot(n) * n;
  if (in_plane.norm() < 0.2 * area)
    throw GeometryError(name + ": no travel is planned and the bone within " + detail::mm(radius) + " of its origin " +
                        detail::where(slot.origin) +
                        " does not face a way within the cut plane (the plane runs along the surface, or the "
                        "bone there is an edge); give its direction");
  return -in_plane.normalized();
}

void direct_slots(std::vector<SlotSpec>& slots, const std::function<const AabbTree&()>& bone_tree) {
  for (SlotSpec& s : slots) {
    if (!s.auto_direction) continue;
    s.direction = slot_direction(s, bone_tree());
    s.auto_direction = false;
  }
}

TriangleMesh frame_box(const SlotFrame& frame, double half_width, double e0, double e1, double z0, double z1) {
  TriangleMesh box;
  for (int k = 0; k < 8; ++k)
    box.positions.push_back(frame.at((k & 1) ? half_width : -half_width, (k & 2) ? e1 : e0, (k & 4) ? z1 : z0));
  // (n, e, up) is right-handed: n x e = n x (n x d) = -d = up. Faces listed counter-clockwise seen
  // from outside.
  const std::array<std::array<Index, 4>, 6> quads{{{0, 4, 6, 2},   // -n
                                                   {1, 3, 7, 5},   // +n
                                                   {0, 1, 5, 4},   // -e
                                                   {2, 6, 7, 3},   // +e
                                                   {0, 2, 3, 1},   // bottom (-up)
                                                   {4, 5, 7, 6}}}; // top
  for (const auto& q : quads) {
    box.triangles.push_back({q[0], q[1], q[2]});
    box.triangles.push_back({q[0], q[2], q[3]});
  }
  return box;
}

TriangleMesh footed_frame_box(const SlotFrame& frame, double half_width, double e0, double e1, double z0, double z1,
                              double spacing, Index& foot) {
  const int across = std::clamp(static_cast<int>(std::ceil(2.0 * half_width / spacing)), 1, 256);
  const int along = std::clamp(static_cast<int>(std::ceil((e1 - e0) / spacing)), 1, 1024);
  TriangleMesh box;
  auto grid = [&](int i, int j) { return static_cast<Index>(j * (across + 1) + i); };
  for (int j = 0; j <= along; ++j)
    for (int i = 0; i <= across; ++i)
      box.positions.push_back(frame.at(-half_width + 2.0 * half_width * i / across, e0 + (e1 - e0) * j / along, z0));
  foot = box.vertex_count();
  // The grid's border, counter-clockwise seen from above (n, e, up right-handed), and the top's copy.
  std::vector<Index> border;
  for (int i = 0; i < across; ++i) border.push_back(grid(i, 0));
  for (int j = 0; j < along; ++j) border.push_back(grid(across, j));
  for (int i = across; i > 0; --i) border.push_back(grid(i, along));
  for (int j = along; j > 0; --j) border.push_back(grid(0, j));
  const Index top0 = box.vertex_count();
  for (const Index b : border) box.positions.push_back(box.positions[b] + (z1 - z0) * frame.up());
  const Index centre = box.vertex_count();
  box.positions.push_back(frame.at(0.0, 0.5 * (e0 + e1), z1));
  // Bottom facing down: clockwise seen from above.
  for (int j = 0; j < along; ++j)
    for (int i = 0; i < across; ++i) {
      box.triangles.push_back({grid(i, j), grid(i + 1, j + 1), grid(i + 1, j)});
      box.triangles.push_back({grid(i, j), grid(i, j + 1), grid(i + 1, j + 1)});
    }
  const auto n = static_cast<Index>(border.size());
  for (Index k = 0; k < n; ++k) {
    const Index b0 = border[k], b1 = border[(k + 1) % n], t0 = top0 + k, t1 = top0 + (k + 1) % n;
    box.triangles.push_back({b0, b1, t1});
    box.triangles.push_back({b0, t1, t0});
    box.triangles.push_back({centre, t0, t1});
  }
  return box;
}

} // namespace st
