#pragma once
// Surgical plans from planning software: 3D Slicer markups (.mrk.json), CSV tables of axes, and the
// project's case files, read into one Plan in the bone mesh's frame. Sleeve presets: a JSON
// catalogue of guide-sleeve sizes.
//
// Frames. 3D Slicer stores markups in LPS or RAS ("coordinateSystem", LPS when absent) and saves
// models in LPS, writing "SPACE=LPS" or "SPACE=RAS" into the STL header. A mesh is taken as LPS
// unless its header says SPACE=RAS; LPS and RAS differ by the sign of x and y.
//
// Markups files (Slicer's markups schema, any 1.x): every markup in "markups" is read:
//   ClosedCurve  -> the boundary's control points (the first one; more are reported and ignored)
//   Line         -> a drilling axis: first control point the entry at the bone, second a point
//                   along the drilling direction inside it (its distance is the planned depth);
//                   named by the markup's "name", else its first point's label, else "Line <n>"
//   Plane        -> a cut plane for a saw slot: its "center" and "normal" (Slicer 5), else its first
//                   control point and the normal of its first three (Slicer 4.11, 3-point planes);
//                   named by the markup's "name", else "Plane <n>"; the travel is left to
//                   slot_direction, the blade and length to the chosen sizes
//   Fiducial (point list) with one point -> the point inside the region to keep
//   Fiducial with 3 or more points       -> the boundary's control points when no ClosedCurve
//   anything else                        -> reported and ignored
// Control points whose positionStatus is not "defined" are skipped and reported. Coordinates in
// "um" are scaled to mm; other units are refused.
//
// CSV plans (comma, semicolon or tab separated; '#' starts a comment line): the first other line
// names the columns, in any order and case: name, entry_x, entry_y, entry_z, and either
// direction_x/_y/_z (into the bone) or target_x/_y/_z (a point along the axis inside the bone,
// which also gives the depth); optional inner_radius, outer_radius (or inner_diameter,
// outer_diameter), length, offset, depth. A table with a normal_x column is one of cut planes
// instead: name, origin_x/_y/_z, normal_x/_y/_z, optional direction_x/_y/_z (the saw's travel),
// blade, clearance, length, height, wall and closed ("both", "none", "start", "end", "start end").
// Lengths in mm, in the mesh's frame, unless a comment line "# space=RAS" or "# space=LPS" says the
// file's frame.
//
// Every reader throws InvalidInput naming the file and the markup, control point, line or column.

#include "st/io/case_file.h"
#include "st/core/mesh.h"

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace st {

enum class Space { LPS, RAS };

/// The frame of a mesh from the text of its header (ReadReport::header): RAS when it holds
/// "SPACE=RAS" (any case), else LPS.
Space mesh_space(std::string_view header);

/// The frame of the mesh file at `path` (STL, PLY, OBJ, also gzip-compressed) from its start only
/// (the first 64 KiB, inflated): the header read_mesh reports, without reading the triangles. Throws
/// InvalidInput for a file that cannot be opened or read.
Space mesh_file_space(const std::string& path);

/// `p` given in frame `from`, in frame `to`.
Vec3 convert_space(const Vec3& p, Space from, Space to);

/// A planned drilling axis; sizes the plan does not give are empty.
struct PlanAxis {
  std::string name;
  std::string source; ///< where it was read, for messages ("plan.csv:4", "a.mrk.json: markup 2")
  Vec3 entry = Vec3::Zero();
  Vec3 direction = Vec3::UnitZ(); ///< unit, into the bone
  std::optional<double> depth;    ///< planned drilling depth into the bone beyond the entry
  std::optional<double> inner_radius, outer_radius, length, offset;
};

/// A planned cut plane, for a saw slot (slot.h); what the plan does not give is empty.
struct PlanPlane {
  std::string name;
  std::string source; ///< where it was read, for messages
  Vec3 origin = Vec3::Zero();
  Vec3 normal = Vec3::UnitX();   ///< unit
  std::optional<Vec3> direction; ///< the saw's travel into the bone; empty: slot_direction decides
  std::optional<double> blade, clearance, length, height, wall;
  std::optional<std::array<bool, 2>> closed; ///< start, end
};

struct Plan {
  std::string path;
  std::string kind;                  ///< what the file was: "case", "markups" or "csv"
  std::vector<Vec3> boundary_points; ///< empty when the plan has no boundary
  std::optional<Vec3> inside;
  std::vector<PlanAxis> axes;
  std::vector<PlanPlane> planes;
  std::vector<std::string> warnings;
};

/// Reads a 3D Slicer markups file, converting into `target` (the bone mesh's frame).
Plan read_markups(const std::string& path, Space target);
Plan parse_markups(const std::string& text, const std::string& path, Space target);

/// Reads a CSV plan of drilling axes, converting into `target` when the file names its frame.
Plan read_plan_csv(const std::string& path, Space target);
Plan parse_plan_csv(const std::string& text, const std::string& path, Space target);

/// Any plan by its content: a case file (JSON with "format"), a markups file (JSON with
/// "markups"), else CSV. `target` is the frame of the bone the plan goes on.
Plan read_plan(const std::string& path, Space target);

/// The plan of a case file (its boundary and tubes, sizes included).
Plan plan_of_case(const CaseFile& c);

/// A guide-sleeve size from the catalogue.
struct SleevePreset {
  std::string name;
  std::string description;
  double inner_radius = 0.0;
  double outer_radius = 0.0;
  double length = 0.0;
  double offset = 0.0;
  TubeKind kind = TubeKind::sleeve;       ///< a pin preset makes pins (tube.h)
  std::optional<Counterbore> counterbore; ///< for a screw's head
};

/// Parses a sleeve catalogue: {"format": "surgical-template-sleeves/1", "sleeves": [{"name",
/// "inner_diameter", "outer_diameter", "length", "offset"?, "description"?, "kind"? ("sleeve" or "pin"),
/// "counterbore_diameter"?, "counterbore_depth"? (both or neither)}]}; diameters and lengths in mm.
std::vector<SleevePreset> parse_sleeve_presets(const std::string& text, const std::string& path);
std::vector<SleevePreset> read_sleeve_presets(const std::string& path);

/// The catalogue that ships with the project (data/sleeve-presets.json, built in).
const std::vector<SleevePreset>& default_sleeve_presets();

/// The preset called `name` in `presets` (exact, then case-insensitive); InvalidInput listing the
/// names when there is none.
const SleevePreset& find_sleeve_preset(const std::vector<SleevePreset>& presets, const std::string& name);

/// A saw blade of the catalogue (its "blades" section): a slot planned for it is thickness + 2 x
/// clearance wide (slot.h).
struct BladePreset {
  std::string name;
  std::string description;
  double thickness = 0.0;
  double clearance = 0.1;
};

/// Parses the blades of a catalogue (the same file as the sleeves): "blades": [{"name", "thickness",
/// "clearance"? (default 0.1), "description"?}], optional (none: no blades). Throws InvalidInput
/// naming the file and the key.
std::vector<BladePreset> parse_blade_presets(const std::string& text, const std::string& path);
std::vector<BladePreset> read_blade_presets(const std::string& path);

/// The blades of the catalogue that ships with the project.
const std::vector<BladePreset>& default_blade_presets();

/// The blade called `name` (exact, then case-insensitive); InvalidInput listing the names when there is none.
const BladePreset& find_blade_preset(const std::vector<BladePreset>& presets, const std::string& name);

/// A tube from a plan axis: sizes from the axis where it gives them, else from `sizes`. Throws
/// InvalidInput naming the axis when a size is missing from both or the sleeve is impossible.
TubeSpec tube_from_axis(const PlanAxis& axis, const std::optional<SleevePreset>& sizes);

/// What a slot takes where its plan does not say: the blade (thickness and clearance) and the length.
struct SlotSizes {
  std::optional<BladePreset> blade;
  std::optional<double> length;
};

/// A slot from a plan's cut plane: what the plane gives, else `sizes`, else the slot's defaults
/// (slot.h) for height, wall and ends; no direction gives an auto_direction slot. Throws
/// InvalidInput naming the plane when the blade or length is missing from both or a number is wrong.
SlotSpec slot_from_plane(const PlanPlane& plane, const SlotSizes& sizes);

/// How a plan's drilling axes (and cut planes) meet the tubes (and slots) a case already has.
enum class PlanTubes { Replace, Add };

/// Puts a plan into a case: its boundary (with its inside point, or none) and its inside point replace
/// the case's, its axes become tubes (sizes the plan lacks from `sizes`) and its planes slots (from
/// `slot_sizes`) that replace the case's or are added to them; what the plan does not give stays. Returns the warnings:
/// the plan's own, and that the case's inside point is dropped when a new boundary comes without one. Throws
/// InvalidInput (tube_from_axis) before anything changes. The one way the tool, the module and the workbench apply
/// plans.
std::vector<std::string> apply_plan(CaseFile& c, const Plan& plan, const std::optional<SleevePreset>& sizes,
                                    PlanTubes tubes = PlanTubes::Replace, const SlotSizes& slot_sizes = {});

} // namespace st
