#pragma once
// The surgical guide: the template shell with its drilling tubes (paper: "Collision detection and
// merging") and saw slots, made with the kernel's Boolean operations (boolean.h).
//
// Per tube, rays along the planned axis find where the template lies under the sleeve. The sleeve's
// outer cylinder is extended down to the middle of the template wall (a column, so a sleeve planned
// above the template still joins it), the columns are united with each other and with the shell,
// and pieces that would pass the shell's inner surface into the bone are dropped (the seat: the
// inner surface inside a column is kept instead). A column's foot stands over the bone under it:
// each foot vertex at least clearance + foot lift over the highest bone over the foot triangles
// around it, that height taken exactly from the bone triangles clipped to the prism over each foot
// triangle. Where bone rises to the sleeve's top under part of it, the column and sleeve are trimmed
// instead: minus a block standing that high over the bone (the same exact clipping), and pieces the
// bone cuts off from the template dropped; a plan is refused only for bone in the bore (two
// crossings of the axis between the sleeve's top and the entry) or a sleeve left with nothing
// joined to the template, by the tube's name. Then the bores (inner radius,
// circumscribed so the drill always fits) are cut along each whole axis, from above the sleeve
// through to the bone.

#include "st/guide/label.h"
#include "st/guide/slot.h"
#include "st/guide/sleeve.h"
#include "st/guide/tube.h"
#include "st/core/aabb_tree.h"
#include "st/core/mesh.h"

#include <optional>
#include <string>
#include <vector>

namespace st {

struct GuideOptions {
  double chordal_tolerance = 0.01; ///< sleeve and bore tessellation: largest chord deviation, mm
  double clearance = 0.0;          ///< bone clearance, for sleeve parts that overhang the template
  double bore_margin = 1.0;        ///< how far the bore runs past the sleeve top and the inner surface, mm
  /// The template's wall thickness: an engraved label must leave at least thickness - depth of wall
  /// under it (0: not checked).
  double thickness = 0.0;
  /// Each slot's blade path checked free on the finished guide (check_blade_path); a guide that fails
  /// it is refused, naming the slot and the place.
  bool check_blade_paths = true;
  /// The Booleans with the template check the faces they make near their curves (check_result). False
  /// when the caller checks the finished guide with check_solid, which covers those faces, and builds it
  /// again with this on when that check fails, this throws a GeometryError or the result says a part
  /// was dropped (unchecked_part_dropped): then a degenerate contact is perturbed away as before.
  bool check_booleans = true;
  /// AabbTree(bone), the tree over all of the bone's faces, when the caller has one (the design's),
  /// built on this very mesh object (refused otherwise), its coordinates finite: the bone under the
  /// parts is found in it instead of by a pass over every face, and the direction of pins and slots
  /// planned without one is decided in it. Null: built here as needed.
  const AabbTree* bone_tree = nullptr;
};

/// What was decided for one tube; heights z along its axis from the entry, outward (sleeve.h).
struct TubePlacement {
  std::string name;
  TubeKind kind = TubeKind::sleeve;
  Vec3 direction = Vec3::Zero(); ///< the drilling direction as built (a pin's decided from the bone when not planned)
  double sleeve_bottom = 0.0;    ///< offset: the sleeve's lower end as planned
  double sleeve_top = 0.0;       ///< offset + length
  double column_bottom = 0.0;    ///< where the sleeve's outer wall stops, inside the template wall
  double foot_lift = 0.0;        ///< the column's foot stays this far above bone + clearance
  double template_top = 0.0;     ///< highest point where the template lies under the sleeve
  double template_bottom = 0.0;  ///< lowest point of the template's inner surface under the sleeve
  double bore_bottom = 0.0;
  double bore_top = 0.0;
  bool sleeve_inside_template = false;      ///< the whole sleeve lies inside the template's wall
  bool trimmed_by_bone = false;             ///< bone rises to the sleeve's top beside the bore: the sleeve is notched
  std::optional<double> counterbore_bottom; ///< with a counterbore: it is cut from here up (sleeve top - its depth)
  /// Tubes whose path (from above the sleeve to the planned depth into the bone, 20 mm when none is
  /// planned) passes within 1 mm of this one's (bore to bore): "tube 't2' (0.40 mm)".
  std::vector<std::string> near;
};

/// What was decided for one saw slot; heights z along its frame's up from the origin (slot.h).
struct SlotPlacement {
  std::string name;
  Vec3 direction = Vec3::UnitZ(); ///< the saw's travel as built (planned, or slot_direction)
  double width = 0.0;             ///< blade + 2 x clearance
  double template_top = 0.0;      ///< highest point of the template's outer surface under the housing
  double housing_top = 0.0;       ///< template_top + height
  double housing_bottom = 0.0;    ///< the housing's foot before it is raised over the bone (in the template wall)
  double foot_lift = 0.0;         ///< the housing's foot stays this far above bone + clearance
  double cut_bottom = 0.0;        ///< the slot is cut from here (past the template's inner surface)...
  double cut_top = 0.0;           ///< ...to here (past the housing's top)
  double slot_start = 0.0;        ///< the slot's extent along e: closed ends at -length / 2, +length / 2,
  double slot_end = 0.0;          ///< open ones past the housing's end
  double housing_start = 0.0;     ///< the housing's extent along e (a wall beyond each closed end)
  double housing_end = 0.0;
  std::vector<std::string> meets; ///< the tubes ("tube 't1'") and slots whose guide material it cuts or meets
};

/// What was decided for one label (label.h): its frame on the surface and what it leaves.
struct LabelPlacement {
  std::string name;
  std::string text;
  LabelMode mode = LabelMode::engrave;
  Vec3 origin = Vec3::Zero();  ///< the point of the outer surface nearest the planned point
  Vec3 normal = Vec3::UnitZ(); ///< outward, averaged over the surface around origin
  Vec3 up = Vec3::UnitY();     ///< the text's up in the tangent plane
  Vec3 right = Vec3::UnitX();  ///< up x normal: the reading direction
  double width = 0.0;          ///< the text's extent along right, mm
  double text_height = 0.0;    ///< its extent along up, mm
  double depth = 0.0;          ///< the engraving's depth or the embossing's height along normal, everywhere
  double surface_rise = 0.0;   ///< how far the outer surface under the text rises and falls along normal
  double top = 0.0;            ///< the label's solid's highest point over origin along normal (2 mm over it are free)
  double min_wall = 0.0;       ///< engraved: the thinnest wall left under the text (to the inner surface)
  double min_clearance = 0.0;  ///< the text's least distance to a sleeve, bore or slot housing (infinite: none)
};

/// A slot's blade path on the finished guide (blade_path.h).
struct BladePathReport {
  std::string name;
  bool free = false;           ///< no guide material in the path
  std::optional<Vec3> blocked; ///< where guide material lies in it
};

/// Everything a guide carries besides its template.
struct GuideParts {
  std::vector<TubeSpec> tubes;
  std::vector<SlotSpec> slots;
  std::vector<LabelSpec> labels;
};

struct GuideResult {
  TriangleMesh mesh;                   ///< the guide, float32-exact
  std::vector<std::uint8_t> from_tube; ///< per face: 1 when it is sleeve wall, cap or bore, or slot housing or wall
  std::vector<TubePlacement> tubes;
  std::vector<SlotPlacement> slots;
  std::vector<LabelPlacement> labels;
  std::vector<BladePathReport> blade_paths; ///< per slot, with options.check_blade_paths
  double blade_path_seconds = 0.0;          ///< the blade paths' check (validation: not in `seconds`)
  double placement_seconds = 0.0;           ///< rays along the axes (part of union_seconds)
  double columns_seconds = 0.0;             ///< columns united with each other (part of union_seconds)
  double union_seconds = 0.0;               ///< placement, columns united with each other and with the shell
  double bore_seconds = 0.0;                ///< bores united and cut
  double seconds = 0.0;                     ///< all of it: the paper's "Runtime of Boolean operation"
  int perturbed_operations = 0;             ///< Boolean operations that needed a tiny displacement
  double max_perturbation = 0.0;            ///< the largest such displacement, mm (surfaces may move this much)
  double curve_tolerance = 0.0;             ///< how far the intersection curves may have moved, mm (boolean.h)
  std::size_t fragments_dropped = 0;        ///< slivers of template the bores cut off the guide (dropped)
  /// With check_booleans false: a part was dropped after a Boolean that left the faces near its curve
  /// unchecked. A check of the guide does not see what was dropped: build it again with the checks.
  bool unchecked_part_dropped = false;
  TriangleMesh columns; ///< the sleeve columns united (second operand of the union)
  TriangleMesh bores;   ///< the bores united (second operand of the difference)
};

/// Merges `tubes` into the closed template `shell` whose first `inner_faces` faces are its inner
/// surface (the seat on the bone). `bone` is only used for sleeve parts beyond the template's rim.
/// Throws InvalidInput for a bad tube (naming it and the key) and GeometryError for a tube that misses
/// the template (naming it and how far it passes) or a merge that cannot be made valid.
GuideResult add_tubes(const TriangleMesh& shell, std::size_t inner_faces, const TriangleMesh& bone,
                      const std::vector<TubeSpec>& tubes, const GuideOptions& options = {});

/// add_tubes with saw slots too (and pins planned without a direction given theirs, pin_direction): each slot's housing
/// stands on the template like a sleeve's column (its foot over the bone, the same exact clipping), united with the
/// columns and the shell; each slot is cut with the bores, from above its housing down past the template's inner
/// surface. Throws InvalidInput for a bad slot (naming it and the key) and GeometryError for a slot that misses the
/// template or whose housing the bone reaches (naming it and the place). Labels are laid on the template's outer
/// surface (label.h) and engraved with the bores' cut or embossed with the columns' union; GeometryError names a
/// label that runs off the outer surface, over a step or too steep a surface, within kLabelClearance_mm of a sleeve,
/// bore or slot housing, or (engraved) leaves less than options.thickness - depth of wall under it.
GuideResult build_guide(const TriangleMesh& shell, std::size_t inner_faces, const TriangleMesh& bone,
                        const GuideParts& parts, const GuideOptions& options = {});

} // namespace st
