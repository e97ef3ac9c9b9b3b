#pragma once
// What the guide's Booleans leave that is not the guide (private to the guide builder,
// st/guide/guide.h): sleeve parts the union did not join to the template, and slivers of template the
// bores cut off.

#include "st/core/errors.h"
#include "st/core/mesh.h"
#include "st/guide/guide.h"

#include <cstdint>
#include <string>
#include <vector>

namespace st::guide_detail {

/// A tube's plan that cannot be built as it is: the error names the tube, what and where.
GeometryError conflict(const TubeSpec& tube, const Vec3& where, const std::string& how);

/// After the union, parts made of sleeve faces only (a column piece the bone cut off from the rest,
/// or a whole column whose foot rose over bone beside the template, clear of it) are dropped; a tube
/// left with no sleeve face joined to the template is a conflict named by the tube. Returns whether a
/// part was dropped.
bool drop_unjoined(TriangleMesh& mesh, std::vector<std::uint8_t>& from_tube, const std::vector<TubeSpec>& tubes,
                   const std::vector<TubePlacement>& placements);

/// A bore near the rim can cut a sliver of template off the guide: the pieces other than the largest
/// (by volume) would fall off the print; they are dropped and counted.
std::size_t drop_fragments(TriangleMesh& mesh, std::vector<std::uint8_t>& from_tube);

} // namespace st::guide_detail
