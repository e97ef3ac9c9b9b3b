#pragma once
// Saw slots of a cutting guide: the planned osteotomy plane, the slot the blade runs in, and the
// housing around it; the one definition shared by the case reader, the guide builder (guide.h), the
// validation and the workbench.
//
// A slot's frame: o, a point of the cut plane on the bone; n, the plane's unit normal; d, the saw's
// travel direction in the plane, into the bone; e = n x d, across the slot, from its start to its end.
// Heights z are measured from o against d (away from the bone), as for tubes (sleeve.h). The slot is
// the slab |n . (x - o)| <= blade / 2 + clearance, -length / 2 <= e . (x - o) <= length / 2 (beyond an
// open end: through the housing), from above the housing down past the template's inner surface; the
// housing is the slab widened by `wall` on both sides and, at each closed end, beyond it, standing
// `height` over the template's outer surface.

#include "st/core/aabb_tree.h"
#include "st/core/mesh.h"
#include "st/guide/tube.h"

#include <functional>
#include <optional>
#include <string>

namespace st {

struct SlotSpec {
  std::string name;
  Vec3 origin = Vec3::Zero();
  Vec3 normal = Vec3::UnitX();    ///< the cut plane's normal (unit after check_slot / slot_frame)
  Vec3 direction = Vec3::UnitZ(); ///< the saw's travel direction, into the bone
  /// No travel was planned (a plane from a plan): design_template and build_guide set `direction`
  /// into the bone from the origin (slot_direction) before anything is built.
  bool auto_direction = false;
  double blade = 0.0;       ///< blade thickness
  double clearance = 0.1;   ///< gap on each side of the blade
  double length = 0.0;      ///< the slot's extent across `direction`, centred on `origin`
  double height = 5.0;      ///< the housing's height over the template's outer surface
  double wall = 3.0;        ///< the housing's wall on each side of the slot
  bool closed_start = true; ///< the housing closes the slot's end at -length / 2 (along -e)
  bool closed_end = true;   ///< the housing closes the slot's end at +length / 2 (along +e)

  [[nodiscard]] double width() const { return blade + 2.0 * clearance; }
};

/// The orthonormal frame of a slot: n (normal), d (travel, into the bone), e = n x d (start to end),
/// up = -d; heights from `origin` along up.
struct SlotFrame {
  Vec3 origin = Vec3::Zero();
  Vec3 n = Vec3::UnitX();
  Vec3 d = Vec3::UnitZ();
  Vec3 e = Vec3::UnitY();

  [[nodiscard]] Vec3 up() const { return -d; }
  /// The point with coordinates (across the plane along n, along the slot along e, height z).
  [[nodiscard]] Vec3 at(double across, double along, double z) const { return origin + across * n + along * e - z * d; }
};

/// The first rule a slot's numbers break (see check_slot), as the key relative to the slot and why.
std::optional<TubeProblem> slot_problem(const SlotSpec& slot);

/// Checks a slot's numbers: origin finite; normal and (unless auto_direction) direction finite, non-zero
/// and not parallel;
/// blade > 0, clearance >= 0, length > 0, height > 0, wall > 0, all finite and under the limits of
/// st/core/tolerances.h. Throws InvalidInput "slot '<name>': <key> <reason>".
void check_slot(const SlotSpec& slot);

/// The frame of a checked slot (n normalised; d's component along n removed, then normalised).
SlotFrame slot_frame(const SlotSpec& slot);

/// A checked slot as readers keep it: its normal unit and, when a travel is planned, the travel unit
/// and in the plane (slot_frame's n and d); a slot without a travel keeps none.
void normalise_slot(SlotSpec& slot);

/// The travel of a slot planned without one: in the cut plane, into the bone against the area-weighted
/// outward normal of the bone within kSlotDirectionRadius of the origin, projected onto the plane.
/// Throws GeometryError naming the slot when no bone lies there or the plane runs along the surface
/// (the projection is under a fifth of the normal: no way into the bone in the plane).
inline constexpr double kSlotDirectionRadius = 3.0; // mm
Vec3 slot_direction(const SlotSpec& slot, const AabbTree& bone);

/// Gives each slot planned without a travel (auto_direction) its slot_direction; `bone_tree` is
/// asked for the bone's tree only when one is needed. Throws as slot_direction.
void direct_slots(std::vector<SlotSpec>& slots, const std::function<const AabbTree&()>& bone_tree);

/// Closed, outward-oriented mesh of the box {|n . (x - o)| <= half_width, e0 <= e . (x - o) <= e1,
/// z0 <= height <= z1} in `frame` (12 triangles).
TriangleMesh frame_box(const SlotFrame& frame, double half_width, double e0, double e1, double z0, double z1);

/// The same box with its bottom (at z0) a grid of about `spacing`, its vertices first (`foot`
/// of them, row by row along e), so that each can be raised over the bone under it.
TriangleMesh footed_frame_box(const SlotFrame& frame, double half_width, double e0, double e1, double z0, double z1,
                              double spacing, Index& foot);

} // namespace st
