#include "guide/slot_guide.h"

#include "detail/format.h"
#include "guide/seat.h"
#include "st/boolean/triangle_intersection.h"
#include "st/core/errors.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

namespace st::guide_detail {

namespace {

/// Spacing of the rays over a housing's footprint and of its foot grid, mm.
constexpr double kSlotSampleSpacing = 0.5;

GeometryError slot_conflict(const SlotSpec& slot, const Vec3& where, const std::string& how) {
  return GeometryError("slot '" + slot.name + "': " + how + " near " + detail::where(where) +
                       "; raise its height, shorten it or move it");
}

} // namespace

SlotPlacement place_slot(const SlotSpec& slot, const TriangleMesh& shell, const GuideOptions& options) {
  const SlotFrame f = slot_frame(slot);
  SlotPlacement p;
  p.name = slot.name;
  p.direction = f.d;
  p.width = slot.width();
  p.housing_start = -0.5 * slot.length - (slot.closed_start ? slot.wall : 0.0);
  p.housing_end = 0.5 * slot.length + (slot.closed_end ? slot.wall : 0.0);
  p.slot_start = slot.closed_start ? -0.5 * slot.length : p.housing_start - options.bore_margin;
  p.slot_end = slot.closed_end ? 0.5 * slot.length : p.housing_end + options.bore_margin;
  const double half = 0.5 * p.width + slot.wall;
  // Rays down the travel direction from well above the bone, over the housing's footprint.
  const double start = 40.0 + slot.height, reach = 2.0 * start;
  BoundingBox box;
  for (const double a : {-half, half})
    for (const double b : {p.housing_start, p.housing_end})
      for (const double z : {start, start - reach}) box.extend(f.at(a, b, z));
  std::vector<Index> near;
  for (Index face = 0; face < shell.face_count(); ++face)
    if (triangle_box(shell, face).overlaps(box)) near.push_back(face);
  const AabbTree tree(shell, std::move(near));
  const std::array<double, 5> across{-half, -0.5 * p.width, 0.0, 0.5 * p.width, half};
  const int along = std::max(1, static_cast<int>(std::ceil((p.housing_end - p.housing_start) / kSlotSampleSpacing)));
  std::optional<double> top, middle, bottom;
  std::vector<double> walls;
  for (int j = 0; j <= along && !tree.empty(); ++j)
    for (const double a : across) {
      const double b = p.housing_start + (p.housing_end - p.housing_start) * j / along;
      const Vec3 from = f.at(a, b, start);
      const auto first = tree.first_hit(from, f.d, 0.0, reach);
      if (!first) continue;
      double enter = start - first->t, exit = enter;
      if (triangle_normal(shell, first->face).dot(f.up()) > 0.0) { // entering the template from above
        const auto second = tree.first_hit(from, f.d, first->t + 1e-9, reach);
        if (!second) continue;
        exit = start - second->t;
      } else { // the ray starts in the template's wall
        enter = start;
      }
      top = std::max(top.value_or(enter), enter);
      middle = std::min(middle.value_or(0.5 * (enter + exit)), 0.5 * (enter + exit));
      if (std::abs(a) < half) bottom = std::min(bottom.value_or(exit), exit);
      walls.push_back(enter - exit);
    }
  if (!top)
    throw GeometryError("slot '" + slot.name + "' misses the template: no template lies under its housing (" +
                        detail::mm(2.0 * half) + " by " + detail::mm(p.housing_end - p.housing_start) +
                        ") along its direction from " + detail::where(slot.origin));
  std::nth_element(walls.begin(), walls.begin() + static_cast<std::ptrdiff_t>(walls.size() / 2), walls.end());
  p.foot_lift = std::min(0.1, 0.25 * walls[walls.size() / 2]);
  p.template_top = *top;
  p.housing_top = *top + slot.height;
  p.housing_bottom = *middle;
  p.cut_top = p.housing_top + options.bore_margin;
  p.cut_bottom = std::min(0.0, bottom.value_or(0.0)) - options.bore_margin;
  return p;
}

TriangleMesh slot_housing(const SlotSpec& slot, const SlotPlacement& p, const AabbTree& bone,
                          const GuideOptions& options) {
  const SlotFrame f = slot_frame(slot);
  Index foot = 0;
  TriangleMesh housing = footed_frame_box(f, 0.5 * p.width + slot.wall, p.housing_start, p.housing_end,
                                          p.housing_bottom, p.housing_top, kSlotSampleSpacing, foot);
  if (!bone.empty()) {
    const std::vector<double> need = foot_needs(housing, foot, f.origin, f.up(), p.housing_bottom, p.housing_top,
                                                options.clearance + p.foot_lift, bone);
    const double ceiling = p.housing_top - 0.01 * (p.housing_top - p.housing_bottom);
    for (Index v = 0; v < foot; ++v) {
      if (need[v] > ceiling)
        throw slot_conflict(slot, housing.positions[v], "the bone under its housing rises to the housing's top");
      if (need[v] > p.housing_bottom) housing.positions[v] += (need[v] - p.housing_bottom) * f.up();
    }
  }
  housing = rounded(std::move(housing));
  if (const auto meets = meets_bone(housing, bone)) throw slot_conflict(slot, *meets, "its housing runs into the bone");
  return housing;
}

TriangleMesh slot_cut(const SlotSpec& slot, const SlotPlacement& p) {
  return rounded(frame_box(slot_frame(slot), 0.5 * p.width, p.slot_start, p.slot_end, p.cut_bottom, p.cut_top));
}

bool solids_cross(const TriangleMesh& a, const TriangleMesh& b) {
  const AabbTree ta(a), tb(b);
  bool meet = false;
  ta.for_each_overlapping_pair(tb, [&](Index fa, Index fb) {
    if (meet) return;
    const Triangle& x = a.triangles[fa];
    const Triangle& y = b.triangles[fb];
    meet = triangles_intersect(a.positions[x[0]], a.positions[x[1]], a.positions[x[2]], b.positions[y[0]],
                               b.positions[y[1]], b.positions[y[2]]);
  });
  return meet;
}

bool convex_solids_meet(const TriangleMesh& a, const TriangleMesh& b) {
  if (solids_cross(a, b)) return true;
  auto inside = [](const Vec3& q, const TriangleMesh& solid) {
    for (Index face = 0; face < solid.face_count(); ++face) {
      const Triangle& t = solid.triangles[face];
      const Vec3& o = solid.positions[t[0]];
      if ((solid.positions[t[1]] - o).cross(solid.positions[t[2]] - o).dot(q - o) > 0.0) return false;
    }
    return true;
  };
  return (!a.positions.empty() && inside(a.positions.front(), b)) ||
         (!b.positions.empty() && inside(b.positions.front(), a));
}

} // namespace st::guide_detail
