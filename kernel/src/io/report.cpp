#include "st/io/report.h"

namespace st {

namespace {
nlohmann::json xyz(const Vec3& p) { return {p.x(), p.y(), p.z()}; }
} // namespace

nlohmann::json to_json(const SolidReport& r) {
  return {{"valid", r.valid()},
          {"closed", r.closed()},
          {"manifold", r.manifold()},
          {"oriented", r.oriented()},
          {"border_edges", r.border_edges},
          {"nonmanifold_edges", r.nonmanifold_edges},
          {"nonmanifold_vertices", r.nonmanifold_vertices},
          {"misoriented_edges", r.misoriented_edges},
          {"degenerate_triangles", r.degenerate_triangles},
          {"self_intersections", r.self_intersections},
          {"components", r.components},
          {"area", r.area},
          {"volume", r.volume},
          {"summary", r.summary()}};
}

nlohmann::json to_json(const DistanceStats& s) {
  return {{"min", s.min}, {"max", s.max}, {"mean", s.mean}, {"count", s.count}};
}

nlohmann::json to_json(const TubePlacement& p) {
  nlohmann::json out = {{"name", p.name},
                        {"kind", tube_kind_name(p.kind)},
                        {"direction", xyz(p.direction)},
                        {"sleeve", {p.sleeve_bottom, p.sleeve_top}},
                        {"column_bottom", p.column_bottom},
                        {"template", {p.template_bottom, p.template_top}},
                        {"bore", {p.bore_bottom, p.bore_top}},
                        {"inside_template", p.sleeve_inside_template},
                        {"trimmed_by_bone", p.trimmed_by_bone},
                        {"near", p.near}};
  if (p.counterbore_bottom) out["counterbore"] = {*p.counterbore_bottom, p.bore_top};
  return out;
}

nlohmann::json to_json(const SlotPlacement& p) {
  return {{"name", p.name},
          {"direction", xyz(p.direction)},
          {"width", p.width},
          {"template_top", p.template_top},
          {"housing", {p.housing_bottom, p.housing_top}},
          {"cut", {p.cut_bottom, p.cut_top}},
          {"extent", {p.slot_start, p.slot_end}},
          {"housing_extent", {p.housing_start, p.housing_end}},
          {"meets", p.meets}};
}

nlohmann::json to_json(const LabelPlacement& p) {
  nlohmann::json out = {{"name", p.name},
                        {"text", p.text},
                        {"mode", label_mode_name(p.mode)},
                        {"origin", xyz(p.origin)},
                        {"normal", xyz(p.normal)},
                        {"up", xyz(p.up)},
                        {"width", p.width},
                        {"height", p.text_height},
                        {"depth", p.depth},
                        {"surface_rise", p.surface_rise}};
  if (p.mode == LabelMode::engrave) out["min_wall"] = p.min_wall;
  out["min_clearance"] = std::isfinite(p.min_clearance) ? nlohmann::json(p.min_clearance) : nlohmann::json(nullptr);
  return out;
}

namespace {

nlohmann::json placements(const std::vector<TubePlacement>& tubes) {
  nlohmann::json out = nlohmann::json::array();
  for (const TubePlacement& p : tubes) out.push_back(to_json(p));
  return out;
}

} // namespace

nlohmann::json to_json(const TemplateResult& r, const TemplateOptions& options) {
  const TemplateTimes& t = r.times;
  nlohmann::json out;
  out["counts"] = {{"edge_points_of_inner_surface", r.inner_rim_points},
                   {"triangles_of_inner_surface", r.inner.face_count()},
                   {"points_of_inner_surface", r.inner.vertex_count()},
                   {"edge_points_of_outer_surface", r.outer_rim_points},
                   {"triangles_of_outer_surface", r.outer.face_count()},
                   {"offset_triangles", r.offset_triangles},
                   {"field_voxels", r.field_voxels},
                   {"wall_triangles", r.wall_triangles},
                   {"template_triangles", r.shell.face_count()},
                   {"drilling_tubes", options.tubes.size()},
                   {"saw_slots", options.slots.size()},
                   {"labels", options.labels.size()},
                   {"sampling_step", r.sampling_step},
                   {"resolution", r.resolution}};
  out["times"] = {{"inner_surface_segmentation", t.inner_segmentation},
                  {"offset_of_inner_surface", t.offset},
                  {"points_for_outer_surface_segmentation", t.outer_points},
                  {"outer_surface_segmentation", t.outer_segmentation},
                  {"connection_of_inner_and_outer_surfaces", t.connection},
                  {"initial_template_generation", t.total},
                  {"boolean_operation", t.boolean},
                  {"validation", t.validation},
                  {"insertion_analysis", t.insertion},
                  {"block_out", t.block_out},
                  {"removal_check", t.removal},
                  {"stability", t.stability}};
  if (const InsertionReport& ins = r.insertion; ins.analysed) {
    auto points = [](const std::vector<Vec3>& ps) {
      nlohmann::json a = nlohmann::json::array();
      for (const Vec3& p : ps) a.push_back({p.x(), p.y(), p.z()});
      return a;
    };
    out["insertion"] = {{"direction", {ins.direction.x(), ins.direction.y(), ins.direction.z()}},
                        {"auto", ins.automatic},
                        {"region_area_mm2", ins.region_area_mm2},
                        {"undercut_area_mm2", ins.undercut_area_mm2},
                        {"blocked_out", ins.blocked_out},
                        {"blocked_out_volume_mm3", ins.blocked_out_volume_mm3},
                        {"blocked_out_zones", ins.blocked_out_zones},
                        {"trimmed_zones", ins.trimmed_zones},
                        {"trimmed_area_mm2", ins.trimmed_area_mm2},
                        {"skirt_faces", ins.skirt_faces},
                        {"skirt_area_mm2", ins.skirt_area_mm2},
                        {"skirt_depth_mm", ins.skirt_depth_mm},
                        {"skirt_dropped", ins.skirt_dropped},
                        {"unfilled", points(ins.unfilled)}};
    if (ins.removal_checked) {
      out["insertion"]["removable"] = ins.removable;
      out["insertion"]["removal_distance_mm"] = ins.removal_distance;
      out["insertion"]["blocking"] = points(ins.blocking);
      out["insertion"]["contact_area_mm2"] = ins.contact_area_mm2;
      out["insertion"]["inner_area_mm2"] = ins.inner_area_mm2;
    }
  }
  if (r.stability.analysed) out["stability"] = to_json(r.stability);
  out["tubes"] = placements(r.tubes);
  if (!r.slots.empty()) {
    out["slots"] = nlohmann::json::array();
    for (std::size_t i = 0; i < r.slots.size(); ++i) {
      nlohmann::json s = to_json(r.slots[i]);
      if (i < r.blade_paths.size()) {
        s["blade_path_free"] = r.blade_paths[i].free;
        if (r.blade_paths[i].blocked) s["blade_path_blocked_at"] = xyz(*r.blade_paths[i].blocked);
      }
      out["slots"].push_back(s);
    }
  }
  if (!r.labels.empty()) {
    out["labels"] = nlohmann::json::array();
    for (const LabelPlacement& p : r.labels) out["labels"].push_back(to_json(p));
  }
  out["boolean"] = {{"perturbed_operations", r.perturbed_operations},
                    {"max_perturbation_mm", r.max_perturbation},
                    {"curve_tolerance_mm", r.curve_tolerance},
                    {"fragments_dropped", r.fragments_dropped}};
  if (options.check) out["solid"] = to_json(r.solid);
  if (options.check && options.measure_fit)
    out["fit"] = {{"inner_to_bone", to_json(r.fit.inner_to_bone)},
                  {"outer_to_inner", to_json(r.fit.outer_to_inner)},
                  {"rim_to_curve", to_json(r.fit.rim_to_curve)}};
  return out;
}

nlohmann::json to_json(const FreeMotion& m) {
  static const char* const kinds[] = {"slide", "turn", "screw", "lift_off"};
  nlohmann::json out = {{"text", m.describe()},          {"kind", kinds[static_cast<int>(m.kind)]},
                        {"direction", xyz(m.direction)}, {"keeps_contact", m.keeps_contact},
                        {"blocked", m.blocked},          {"lift", m.lift}};
  if (m.kind == FreeMotion::Kind::turn || m.kind == FreeMotion::Kind::screw) out["point"] = xyz(m.point);
  if (m.kind == FreeMotion::Kind::screw) out["pitch_mm_per_rad"] = m.pitch;
  return out;
}

nlohmann::json to_json(const StabilityResult& s) {
  const StabilityReport& r = s.report;
  nlohmann::json motions = nlohmann::json::array();
  for (const FreeMotion& m : r.free_motions) motions.push_back(to_json(m));
  nlohmann::json out = {{"score", r.score},
                        {"contacts", r.contacts},
                        {"direction", xyz(r.direction)},
                        {"centroid", xyz(r.centroid)},
                        {"scale_mm", r.scale},
                        {"lift_off_free", r.lift_off_free},
                        {"free_motions", motions},
                        {"worst_motion", to_json(r.worst_motion)},
                        {"press_point", xyz(s.press.point)},
                        {"press_score", s.press.score}};
  if (s.extend.found)
    out["extend"] = {{"text", s.extend.describe()},
                     {"near", xyz(s.extend.rim_point)},
                     {"towards", xyz(s.extend.bone_point)},
                     {"facing", s.extend.facing}};
  return out;
}

nlohmann::json to_json(const GuideResult& g) {
  nlohmann::json slots = nlohmann::json::array();
  for (std::size_t i = 0; i < g.slots.size(); ++i) {
    nlohmann::json s = to_json(g.slots[i]);
    if (i < g.blade_paths.size()) s["blade_path_free"] = g.blade_paths[i].free;
    slots.push_back(s);
  }
  nlohmann::json labels = nlohmann::json::array();
  for (const LabelPlacement& p : g.labels) labels.push_back(to_json(p));
  return {{"tubes", placements(g.tubes)},
          {"slots", slots},
          {"labels", labels},
          {"seconds", g.seconds},
          {"perturbed_operations", g.perturbed_operations},
          {"max_perturbation_mm", g.max_perturbation},
          {"curve_tolerance_mm", g.curve_tolerance},
          {"fragments_dropped", g.fragments_dropped}};
}

} // namespace st
