#pragma once
// The initial template, end to end (paper: Methods, steps 1 to 5): boundary curve on the bone, inner
// surface cut through the triangles, clearance, narrow-band offset at the thickness, outer surface cut
// by the border samples projected along averaged normals, and the ruled wall joining both borders into
// one closed shell. The shell is checked (closed, 2-manifold, outward oriented, no self-intersection)
// and its fit measured before it is returned.

#include "st/guide/tube.h"
#include "st/guide/guide.h"
#include "st/core/mesh.h"
#include "st/core/tolerances.h"
#include "st/guide/blade_path.h"
#include "st/validate/stability.h"
#include "st/validate/validate.h"

#include <optional>
#include <string>
#include <vector>

namespace st {

struct TemplateOptions {
  std::vector<Vec3> boundary_points; ///< control points around the region, in order (>= 3)
  std::optional<Vec3> inside;        ///< a point inside the region to keep; else the smaller side
  double thickness = 2.5;            ///< outer surface distance from the inner surface, mm (> 0)
  double clearance = 0.0;            ///< gap between bone and inner surface, mm (>= 0)
  double resolution = 0.0;           ///< distance-field cell size, mm; 0 picks thickness / 8
  int sampling_step = 0;             ///< border points between outer-cut samples; 0 picks ~ thickness apart
  double max_snap_distance = tol::kMaxSnapDistance_mm;
  double max_field_cells = tol::kMaxFieldCells;
  /// Simplify the contoured outer surface to about two cells per edge, within a tenth of a cell,
  /// keeping its rim and first ring exactly (5x fewer triangles, no slivers; costs 0.3-0.7 s today).
  /// A simplified shell that fails the check falls back to the contoured one.
  bool simplify_outer = false;
  bool check = true;       ///< run check_solid on the result (a broken shell is refused)
  bool measure_fit = true; ///< with check: also measure the fit (TemplateResult::fit)
  /// Insertion analysis (insertion.h): the undercut of the covered bone along `insertion` (the
  /// direction the guide moves onto the bone), or along the least-undercut direction when it is not
  /// given, and the removal check of the finished guide along it (removal.h). Off by default (the
  /// case file path, the tool and the workbench turn it on).
  bool analyse_insertion = false;
  std::optional<Vec3> insertion;
  /// With analyse_insertion: block the undercuts out (blockout.h) before the clearance, so that the
  /// inner surface is what the guide can reach along the direction. A case file turns it on when it
  /// names template.insertion; without that key a case keeps the guide it always had.
  bool block_out = false;
  double removal_distance = 20.0; ///< how far the removal check moves the guide off, mm
  /// Drilling tubes merged into the shell (guide.h); empty for a template without sleeves.
  std::vector<TubeSpec> tubes;
  /// Saw slots on planned osteotomy planes (slot.h); their housings are merged with the sleeves.
  std::vector<SlotSpec> slots;
  /// Labels engraved into or embossed onto the outer surface (label.h), their outlines filled in
  /// (st/occt/occt_text.h); laid with the sleeves and slots.
  std::vector<LabelSpec> labels;
  double tube_tolerance = 0.01; ///< chordal tolerance of sleeves and bores, mm
};

/// Seconds per step, named after the rows of the paper's Table 1.
struct TemplateTimes {
  double inner_segmentation = 0.0;
  double offset = 0.0;
  double outer_points = 0.0;
  double outer_segmentation = 0.0;
  double connection = 0.0;
  double total = 0.0;      ///< sum of the above: the paper's "initial template generation"
  double boolean = 0.0;    ///< tubes merged and bores cut: the paper's "Runtime of Boolean operation"
  double validation = 0.0; ///< wall time of the checks and analyses beyond the design; not part of total
  double insertion = 0.0;  ///< the insertion analysis (beside the shell without block-out); not part of total
  double block_out = 0.0;  ///< the undercut block-out; part of inner_segmentation
  double removal = 0.0;    ///< the removal check and contact area: own time, beside the guide's check
  double stability = 0.0;  ///< contacts, free motions, score, press point: own time, beside the check
};

/// Where the guide goes on (TemplateOptions::analyse_insertion).
struct InsertionReport {
  bool analysed = false;
  Vec3 direction = Vec3::Zero();  ///< unit; the guide moves along it onto the bone
  bool automatic = false;         ///< the least-undercut direction (no direction was given)
  double region_area_mm2 = 0.0;   ///< the covered bone's area
  double undercut_area_mm2 = 0.0; ///< of it, what the guide cannot reach along `direction`
  TriangleMesh region;            ///< the covered bone (the inner surface before block-out and clearance)
  std::vector<float> hidden;      ///< per face of `region`, the fraction of its area hidden
  bool blocked_out = false;       ///< the undercuts were blocked out (TemplateOptions::block_out)
  double blocked_out_volume_mm3 = 0.0;
  std::size_t blocked_out_zones = 0; ///< hidden zones filled
  std::size_t trimmed_zones = 0;     ///< hidden zones at the rim cut off (the guide ends where the bone turns under)
  double trimmed_area_mm2 = 0.0;
  std::size_t skirt_faces = 0; ///< the skirt hung from the silhouette where zones were cut off (skirt.h)
  double skirt_area_mm2 = 0.0;
  double skirt_depth_mm = 0.0;             ///< its deepest wall along the direction
  std::string skirt_dropped;               ///< why the guide ends at the silhouette after all (the shell with the
                                           ///< skirt failed), or empty
  std::vector<Vec3> unfilled;              ///< a point of each hidden zone block-out left as it was
  std::vector<std::uint8_t> filled;        ///< per inner-surface face: 1 for a block-out fill
  double contact_area_mm2 = 0.0;           ///< inner surface within clearance + h/4 of the bone
  double inner_area_mm2 = 0.0;             ///< the inner surface's area
  bool removal_checked = false;            ///< the removal check ran (needs options.check)
  bool removable = false;                  ///< the guide moves off along -direction without meeting the bone
  double removal_distance = 0.0;           ///< how far, mm
  std::vector<Vec3> blocking;              ///< where it meets the bone, when not removable
  std::vector<std::uint8_t> blocked_faces; ///< per shell face: 1 where it meets the bone on the way off
};

struct TemplateFit {
  DistanceStats inner_to_bone;  ///< inner-surface vertices to the bone region (== clearance)
  DistanceStats outer_to_inner; ///< outer-surface vertices to the inner surface (== thickness)
  DistanceStats rim_to_curve;   ///< inner rim vertices to the boundary curve (== 0)
};

struct TemplateResult {
  TriangleMesh shell;                       ///< the closed template, with its sleeves and bores when it has tubes
  TriangleMesh body;                        ///< the template before the tubes (== shell without tubes)
  std::size_t body_inner_faces = 0;         ///< the body's first faces are its inner surface
  std::vector<std::uint8_t> from_tube;      ///< per shell face: 1 for sleeve and bore faces
  std::vector<TubePlacement> tubes;         ///< per tube: where its sleeve and bore were put
  std::vector<SlotPlacement> slots;         ///< per slot: where its housing and cut were put
  std::vector<BladePathReport> blade_paths; ///< per slot, with options.check: its blade path is free
  std::vector<LabelPlacement> labels;       ///< per label: where it was laid and what it leaves
  int perturbed_operations = 0;             ///< Boolean operations that needed a tiny displacement
  double max_perturbation = 0.0;            ///< the largest such displacement, mm
  double curve_tolerance = 0.0;             ///< how far the Boolean intersection curves may have moved, mm
  std::size_t fragments_dropped = 0;        ///< slivers of template the bores cut off (dropped, guide.h)
  TriangleMesh columns, bores;              ///< the operands of the tubes' union and difference (guide.h)
  TriangleMesh inner;                       ///< inner surface (bone side), oriented as the bone
  TriangleMesh outer;                       ///< outer surface, oriented outward
  std::vector<Vec3> curve;                  ///< the boundary curve on the bone (closed polyline)
  std::vector<Vec3> outer_curve;            ///< the cut curve on the offset surface
  std::size_t inner_rim_points = 0;
  std::size_t outer_rim_points = 0;
  std::size_t wall_triangles = 0;
  std::size_t offset_triangles = 0; ///< of the offset before the outer cut
  std::size_t field_voxels = 0;
  double resolution = 0.0; ///< the cell size used
  int sampling_step = 0;   ///< the sampling step used
  TemplateTimes times;
  InsertionReport insertion;
  StabilityResult stability;
  SolidReport solid; ///< filled when options.check
  TemplateFit fit;   ///< filled when options.check
};

/// Designs the initial template on `bone`. Throws InvalidInput for invalid options (naming the
/// option) and GeometryError when the geometry cannot give a template (see trace_surface_curve and
/// cut_region); never returns a shell it knows to be broken: when options.check finds it invalid it
/// throws GeometryError with the report.
TemplateResult design_template(const TriangleMesh& bone, const TemplateOptions& options);

} // namespace st
