#pragma once
// The results as JSON: one set of key names for the tool's --report, the Python module's dicts and
// the workbench (the design's counts and times are the rows of the paper's Table 1). Scalars and
// small lists only; meshes are the caller's to add.

#include "st/design/template_design.h"
#include "st/guide/guide.h"
#include "st/validate/validate.h"

#include <nlohmann/json.hpp>

namespace st {

/// {valid, closed, manifold, oriented, border_edges, nonmanifold_edges, nonmanifold_vertices,
/// misoriented_edges, degenerate_triangles, self_intersections, components, area, volume, summary}
nlohmann::json to_json(const SolidReport& r);

/// {min, max, mean, count}
nlohmann::json to_json(const DistanceStats& s);

/// {name, sleeve: [bottom, top], column_bottom, template: [bottom, top], bore: [bottom, top],
/// inside_template}
nlohmann::json to_json(const TubePlacement& p);
nlohmann::json to_json(const SlotPlacement& p);
/// A label as laid: name, text, mode, origin, normal, up, width and height of the text, depth, the
/// surface's rise under it, min_wall (engraved), min_clearance to sleeves, bores and slot housings.
nlohmann::json to_json(const LabelPlacement& p);

/// {counts: {edge_points_of_inner_surface, triangles_of_inner_surface, points_of_inner_surface,
/// edge_points_of_outer_surface, triangles_of_outer_surface, offset_triangles, field_voxels,
/// wall_triangles, template_triangles, drilling_tubes, sampling_step, resolution},
/// times: {inner_surface_segmentation, offset_of_inner_surface, points_for_outer_surface_segmentation,
/// outer_surface_segmentation, connection_of_inner_and_outer_surfaces, initial_template_generation,
/// boolean_operation, validation} (s), tubes: [placements], boolean: {perturbed_operations,
/// max_perturbation_mm, curve_tolerance_mm}, and, when the design checked them, solid and fit:
/// {inner_to_bone, outer_to_inner, rim_to_curve}}.
nlohmann::json to_json(const TemplateResult& r, const TemplateOptions& options);

/// {text, kind (slide, turn, screw, lift_off), direction, keeps_contact, lift, point (turn, screw),
/// pitch_mm_per_rad (screw)}
nlohmann::json to_json(const FreeMotion& m);

/// {score, contacts, centroid, scale_mm, lift_off_free, free_motions: [motions], worst_motion,
/// press_point, press_score, extend: {text, near, towards, facing} (when found)}
nlohmann::json to_json(const StabilityResult& s);

/// {tubes: [placements], seconds, perturbed_operations, max_perturbation_mm, curve_tolerance_mm}
nlohmann::json to_json(const GuideResult& g);

} // namespace st
