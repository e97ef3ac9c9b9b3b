#pragma once
// The saw's way through a cutting guide: a slot's blade path is free of guide material (validation of
// the finished guide, after every Boolean operation, st/guide/guide.h).

#include "st/core/mesh.h"
#include "st/guide/guide.h"

#include <optional>
#include <string>

namespace st {

/// Whether any guide material lies in the slab |n . (x - o)| < width / 2 - tolerance over the slot's
/// planned extent (|e . (x - o)| < length / 2 - tolerance) from the slot's bottom (past the template's
/// inner surface) up to the housing's top: the path of a blade of the planned thickness plus its
/// clearance on both sides, swept along the slot over the planned cut. Exact triangle tests of the
/// guide's faces against the slab's faces, and the guide's vertices inside it. The tolerance, 0.02 mm,
/// covers float rounding and the Boolean operation's collapse of intersection-curve edges under 256
/// float ulp where the slot's corners meet the template (boolean.h; up to 0.016 mm at 600 mm from the
/// origin): a blade of the planned thickness keeps clearance - 0.02 mm on each side.
BladePathReport check_blade_path(const TriangleMesh& guide, const SlotSpec& slot, const SlotPlacement& placement,
                                 double tolerance = 0.02);

} // namespace st
