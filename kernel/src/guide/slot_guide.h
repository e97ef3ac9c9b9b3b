#pragma once
// Saw slots on the guide (private to the guide builder, st/guide/guide.h): where the template lies
// under a slot, its housing standing on the bone, and the slot's cut.

#include "st/core/aabb_tree.h"
#include "st/guide/guide.h"

namespace st::guide_detail {

/// Rays along the slot's travel over its housing's footprint find the template under it: the
/// housing's top (`height` over the highest outer surface), its foot (the middle of the template wall,
/// lowest over the footprint) and how deep the cut goes. Throws GeometryError naming the slot when no
/// template lies under it.
SlotPlacement place_slot(const SlotSpec& slot, const TriangleMesh& shell, const GuideOptions& options);

/// The housing (the slab of the slot widened by its wall, closed ends included) from its foot to its
/// top, the foot raised over the bone (clearance + foot lift) where the bone is higher; rounded to
/// float. Throws GeometryError naming the slot and the place where the bone reaches the housing's top
/// or the housing meets the bone.
TriangleMesh slot_housing(const SlotSpec& slot, const SlotPlacement& p, const AabbTree& bone,
                          const GuideOptions& options);

/// The slot's cut: the slab blade + 2 x clearance wide over the slot's extent, from above the
/// housing down past the template's inner surface; rounded to float.
TriangleMesh slot_cut(const SlotSpec& slot, const SlotPlacement& p);

/// Whether a face of `a` crosses a face of `b` (exact tests).
bool solids_cross(const TriangleMesh& a, const TriangleMesh& b);

/// Whether two closed convex solids (boxes, prisms) meet: a face of one crosses one of the other's
/// (exact tests), or one lies inside the other.
bool convex_solids_meet(const TriangleMesh& a, const TriangleMesh& b);

} // namespace st::guide_detail
