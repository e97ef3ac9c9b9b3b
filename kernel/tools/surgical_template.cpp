// surgical-template: designs a surgical template from a case file (docs/CASE-FORMAT.md).
//
//   surgical-template design CASE.json [-o OUT.stl] [--report REPORT.json] [--simplify] [--tolerance MM]
//                     [--plan PLAN] [--preset NAME] [--blade NAME] [--slot-length MM] [--presets FILE]
//   surgical-template plan PLAN [--bone MESH | --space LPS|RAS] [--preset NAME] [--blade NAME]
//                     [--slot-length MM] [--presets FILE]
//   surgical-template presets [--presets FILE]
//   surgical-template union|difference|intersection A B -o OUT.stl
//   surgical-template check MESH
//
// Exit codes: 0 done, 1 the geometry cannot give a template (message says where), 2 invalid input.

#include "detail/format.h"
#include "detail/input_file.h"
#include "st/boolean/boolean.h"
#include "st/io/case_file.h"
#include "st/core/errors.h"
#include "st/io/mesh_io.h"
#include "st/io/plan.h"
#include "st/io/report.h"
#include "st/design/template_design.h"
#include "st/validate/validate.h"
#include "st/occt/font_module.h"

#include <nlohmann/json.hpp>
#include <dlfcn.h>
#include <malloc.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>

namespace {

constexpr const char* kUsage =
    "usage:\n"
    "  surgical-template design CASE.json [-o OUT.stl] [--report REPORT.json] [--simplify] [--tolerance MM]\n"
    "      design the template of a case file, with its drilling tubes; writes the STL to -o, else to\n"
    "      the case's \"output\"\n"
    "      --simplify: simplify the outer surface (about 5x fewer triangles, slower)\n"
    "      --tolerance: chordal tolerance of sleeves and bores in mm (default 0.01)\n"
    "      --operands DIR: also write the Boolean operands (body, columns, bores) there\n"
    "      --plan PLAN: take the boundary, drilling axes and/or cut planes from a plan instead (3D Slicer\n"
    "        markups .mrk.json, CSV of axes or of planes, or another case file), converted into the bone's\n"
    "        frame\n"
    "      --preset NAME: sleeve sizes for axes whose plan gives none (see `presets`)\n"
    "      --blade NAME: the saw blade of slots whose plan gives none (see `presets`)\n"
    "      --slot-length MM: the length of slots whose plan gives none\n"
    "      --presets FILE: a sleeve catalogue of your own (surgical-template-sleeves/1)\n"
    "  surgical-template plan PLAN [--bone MESH | --space LPS|RAS] [--preset NAME] [--blade NAME]\n"
    "                    [--slot-length MM] [--presets FILE]\n"
    "      print a plan as case-file JSON (boundary, tubes, slots) in the bone's frame (LPS unless the\n"
    "      mesh header says SPACE=RAS), to check an import or paste into a case\n"
    "  surgical-template presets [--presets FILE]\n"
    "      list the sleeve catalogue\n"
    "  surgical-template union|difference|intersection A B -o OUT.stl\n"
    "      Boolean operation of two closed meshes (A minus B for difference)\n"
    "  surgical-template check MESH\n"
    "      report whether a mesh is a closed, 2-manifold, oriented solid without self-intersections\n";

// The process's own peak: VmHWM of its address space (getrusage's ru_maxrss starts from the parent's
// resident size at fork, so a tool started by a large process, FreeCAD or a benchmark, reported that).
double peak_memory_mb() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("VmHWM:", 0) == 0) return std::strtod(line.c_str() + 6, nullptr) / 1024.0;
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

double parse_length(const std::string& text, const std::string& what) {
  std::size_t used = 0;
  double value = 0.0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || !std::isfinite(value) || value <= 0.0)
    throw st::InvalidInput(what + ": expected a positive length in mm, got '" + text + "'");
  return value;
}

/// The plan options shared by `design` and `plan`.
struct PlanOptions {
  std::vector<std::string> plans;
  std::string preset, blade, presets_file;
  std::optional<double> slot_length;

  /// Takes the option at argv[i] (and its value) if it is one of ours.
  bool parse(int argc, char** argv, int& i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) return false;
    if (a == "--plan") plans.push_back(argv[++i]);
    else if (a == "--preset") preset = argv[++i];
    else if (a == "--blade") blade = argv[++i];
    else if (a == "--slot-length") slot_length = parse_length(argv[++i], "--slot-length");
    else if (a == "--presets") presets_file = argv[++i];
    else return false;
    return true;
  }

  std::vector<st::SleevePreset> catalogue() const {
    return presets_file.empty() ? st::default_sleeve_presets() : st::read_sleeve_presets(presets_file);
  }

  std::optional<st::SleevePreset> sizes() const {
    if (preset.empty()) return std::nullopt;
    return st::find_sleeve_preset(catalogue(), preset);
  }

  std::vector<st::BladePreset> blades() const {
    return presets_file.empty() ? st::default_blade_presets() : st::read_blade_presets(presets_file);
  }

  st::SlotSizes slot_sizes() const {
    st::SlotSizes s;
    if (!blade.empty()) s.blade = st::find_blade_preset(blades(), blade);
    s.length = slot_length;
    return s;
  }
};

nlohmann::json point_json(const st::Vec3& p) { return {p.x(), p.y(), p.z()}; }

int plan(int argc, char** argv) {
  std::string plan_path, bone_path, space_name;
  PlanOptions options;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (options.parse(argc, argv, i)) continue;
    if (a == "--bone" && i + 1 < argc) bone_path = argv[++i];
    else if (a == "--space" && i + 1 < argc) space_name = argv[++i];
    else if (!a.empty() && a[0] != '-' && plan_path.empty()) plan_path = a;
    else throw st::InvalidInput("unexpected argument '" + a + "'\n" + kUsage);
  }
  if (plan_path.empty()) throw st::InvalidInput(std::string("no plan file given\n") + kUsage);
  st::Space space = st::Space::LPS;
  if (!bone_path.empty()) space = st::mesh_file_space(bone_path);
  if (space_name == "RAS") space = st::Space::RAS;
  else if (!space_name.empty() && space_name != "LPS")
    throw st::InvalidInput("--space: must be LPS or RAS, got '" + space_name + "'");
  const st::Plan p = st::read_plan(plan_path, space);
  const std::optional<st::SleevePreset> sizes = options.sizes();
  nlohmann::json out;
  if (!p.boundary_points.empty()) {
    out["boundary"]["points"] = nlohmann::json::array();
    for (const st::Vec3& q : p.boundary_points) out["boundary"]["points"].push_back(point_json(q));
  }
  if (p.inside) out["boundary"]["inside"] = point_json(*p.inside);
  out["tubes"] = nlohmann::json::array();
  for (const st::PlanAxis& axis : p.axes) {
    nlohmann::json t = {
        {"name", axis.name}, {"entry", point_json(axis.entry)}, {"direction", point_json(axis.direction)}};
    if (sizes || (axis.inner_radius && axis.outer_radius && axis.length)) {
      const st::TubeSpec s = st::tube_from_axis(axis, sizes); // the sizes filled and checked
      t.update({{"inner_radius", s.inner_radius},
                {"outer_radius", s.outer_radius},
                {"length", s.length},
                {"offset", s.offset}});
    } else { // what the plan gives; a preset completes it
      for (const auto& [key, value] :
           {std::pair{"inner_radius", axis.inner_radius}, std::pair{"outer_radius", axis.outer_radius},
            std::pair{"length", axis.length}, std::pair{"offset", axis.offset}})
        if (value) t[key] = *value;
    }
    if (axis.depth) t["depth"] = *axis.depth;
    out["tubes"].push_back(t);
  }
  const st::SlotSizes slot_sizes = options.slot_sizes();
  for (const st::PlanPlane& plane : p.planes) {
    nlohmann::json s = {
        {"name", plane.name}, {"origin", point_json(plane.origin)}, {"normal", point_json(plane.normal)}};
    if (plane.direction) s["direction"] = point_json(*plane.direction);
    if ((plane.blade || slot_sizes.blade) && (plane.length || slot_sizes.length)) {
      const st::SlotSpec slot = st::slot_from_plane(plane, slot_sizes); // the sizes filled and checked
      s.update({{"blade", slot.blade},
                {"clearance", slot.clearance},
                {"length", slot.length},
                {"height", slot.height},
                {"wall", slot.wall}});
    } else { // what the plan gives; --blade and --slot-length complete it
      for (const auto& [key, value] :
           {std::pair{"blade", plane.blade}, std::pair{"clearance", plane.clearance}, std::pair{"length", plane.length},
            std::pair{"height", plane.height}, std::pair{"wall", plane.wall}})
        if (value) s[key] = *value;
    }
    if (plane.closed) {
      s["closed"] = nlohmann::json::array();
      if ((*plane.closed)[0]) s["closed"].push_back("start");
      if ((*plane.closed)[1]) s["closed"].push_back("end");
    }
    out["slots"].push_back(s);
  }
  out["space"] = space == st::Space::RAS ? "RAS" : "LPS";
  for (const std::string& w : p.warnings) std::cerr << "warning: " << w << "\n";
  std::printf("%s\n", out.dump(2).c_str());
  return 0;
}

int presets(int argc, char** argv) {
  PlanOptions options;
  for (int i = 2; i < argc; ++i)
    if (!options.parse(argc, argv, i))
      throw st::InvalidInput(std::string("unexpected argument '") + argv[i] + "'\n" + kUsage);
  std::printf("%-16s %8s %8s %8s %8s  %s\n", "name", "bore", "outer", "length", "offset", "description");
  for (const st::SleevePreset& p : options.catalogue())
    std::printf("%-16s %8.2f %8.2f %8.2f %8.2f  %s\n", p.name.c_str(), 2 * p.inner_radius, 2 * p.outer_radius, p.length,
                p.offset, p.description.c_str());
  const std::vector<st::BladePreset> blades = options.blades();
  if (!blades.empty()) {
    std::printf("\n%-16s %8s %8s %8s  %s\n", "blade", "thick", "gap", "slot", "description");
    for (const st::BladePreset& b : blades)
      std::printf("%-16s %8.2f %8.2f %8.2f  %s\n", b.name.c_str(), b.thickness, b.clearance,
                  b.thickness + 2 * b.clearance, b.description.c_str());
  }
  std::printf("(diameters, lengths in mm; a blade's slot is its thickness + 2 x gap wide)\n");
  return 0;
}

// The labels' outlines from the font module beside the tool (st/occt/font_module.h), loaded only here:
// a case without labels never loads OpenCASCADE.
void fill_label_outlines(std::vector<st::LabelSpec>& labels) {
  if (labels.empty()) return;
  std::error_code ec;
  const std::filesystem::path tool = std::filesystem::read_symlink("/proc/self/exe", ec);
  const std::string path = ((ec ? std::filesystem::path(".") : tool.parent_path()) / st::kFontModuleFile).string();
  void* module = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!module) {
    const char* why = dlerror();
    throw st::InvalidInput("label '" + labels.front().name + "': its text needs the font module " + path + " (built " +
                           "with OpenCASCADE), which does not load: " + (why ? why : "unknown reason"));
  }
  const auto fill = reinterpret_cast<st::FillLabelOutlinesEntry>(dlsym(module, st::kFontModuleEntry));
  if (!fill) throw st::InvalidInput(path + ": not the labels' font module (no " + st::kFontModuleEntry + ")");
  std::string error;
  const int status = fill(&labels, &error);
  if (status == 1) throw st::InvalidInput(error);
  if (status != 0) throw st::GeometryError(error);
}

int design(int argc, char** argv) {
  std::string case_path, out_path, report_path;
  bool simplify = false;
  double tolerance = 0.01;
  std::string operands_dir;
  PlanOptions plan_options;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (plan_options.parse(argc, argv, i)) continue;
    if ((a == "-o" || a == "--output") && i + 1 < argc) out_path = argv[++i];
    else if (a == "--report" && i + 1 < argc) report_path = argv[++i];
    else if (a == "--simplify") simplify = true;
    else if (a == "--tolerance" && i + 1 < argc) tolerance = parse_length(argv[++i], "--tolerance");
    else if (a == "--operands" && i + 1 < argc) operands_dir = argv[++i];
    else if (!a.empty() && a[0] != '-' && case_path.empty()) case_path = a;
    else throw st::InvalidInput("unexpected argument '" + a + "'\n" + kUsage);
  }
  if (case_path.empty()) throw st::InvalidInput(std::string("no case file given\n") + kUsage);

  const auto t_start = std::chrono::steady_clock::now();
  st::CaseFile c = st::read_case(case_path);
  for (const std::string& w : c.warnings) std::cerr << "warning: " << w << "\n";
  if (out_path.empty()) {
    if (!c.output) throw st::InvalidInput(case_path + ": no \"output\" in the case and no -o given");
    out_path = *c.output;
  }

  const auto t_read = std::chrono::steady_clock::now();
  st::ReadReport read_report;
  const st::TriangleMesh bone = st::read_mesh(c.bone, &read_report);
  const double read_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_read).count();
  for (const std::string& plan_path : plan_options.plans)
    for (const std::string& w : st::apply_plan(c, st::read_plan(plan_path, st::mesh_space(read_report.header)),
                                               plan_options.sizes(), st::PlanTubes::Replace, plan_options.slot_sizes()))
      std::cerr << "warning: " << w << "\n";

  st::TemplateOptions o = st::template_options(c);
  fill_label_outlines(o.labels); // the text's outlines from the font
  o.simplify_outer = simplify;
  o.tube_tolerance = tolerance;
  const st::TemplateResult r = st::design_template(bone, o);

  const std::filesystem::path out_file(out_path);
  if (out_file.has_parent_path()) std::filesystem::create_directories(out_file.parent_path());
  st::write_stl(r.shell, out_path, "surgical-template " + c.name);
  if (!operands_dir.empty()) {
    // The Boolean operands, for comparing other kernels on the same input (bench/references).
    std::filesystem::create_directories(operands_dir);
    st::write_stl(r.body, operands_dir + "/body.stl", "template body " + c.name);
    if (!r.columns.empty()) st::write_stl(r.columns, operands_dir + "/columns.stl", "sleeve columns " + c.name);
    if (!r.bores.empty()) st::write_stl(r.bores, operands_dir + "/bores.stl", "bores " + c.name);
  }

  const auto& t = r.times;
  std::printf("%s: template of %zu triangles, volume %.1f mm^3 -> %s\n", c.name.c_str(), r.shell.triangles.size(),
              r.solid.volume, out_path.c_str());
  std::printf("  %s\n", r.solid.summary().c_str());
  std::printf("  fit: inner surface %.3f mm from bone (max), outer surface %.3f..%.3f mm from inner, rim %.4f mm from "
              "curve (max)\n",
              r.fit.inner_to_bone.max, r.fit.outer_to_inner.min, r.fit.outer_to_inner.max, r.fit.rim_to_curve.max);
  std::printf("  times (s): inner %.3f  offset %.3f  outer points %.3f  outer cut %.3f  connection %.3f  total %.3f\n",
              t.inner_segmentation, t.offset, t.outer_points, t.outer_segmentation, t.connection, t.total);
  if (!r.tubes.empty() || !r.slots.empty() || !r.labels.empty())
    std::printf("  %zu drilling tube(s), %zu saw slot(s) and %zu label(s) merged and cut in %.3f s\n", r.tubes.size(),
                r.slots.size(), r.labels.size(), t.boolean);
  for (const st::TubePlacement& p : r.tubes)
    for (const std::string& other : p.near)
      std::fprintf(stderr, "warning: %s: the path of tube '%s' passes within 1 mm of %s\n", c.name.c_str(),
                   p.name.c_str(), other.c_str());
  for (std::size_t i = 0; i < r.slots.size(); ++i) {
    const st::SlotPlacement& p = r.slots[i];
    const bool free = i < r.blade_paths.size() && r.blade_paths[i].free;
    std::printf("    slot '%s': %.2f mm wide, %.1f mm long, housing %.1f mm over the template; blade path %s\n",
                p.name.c_str(), p.width, o.slots[i].length, p.housing_top - p.template_top,
                free ? "free" : "not checked");
    for (const std::string& m : p.meets)
      std::fprintf(stderr, "warning: %s: slot '%s' meets %s\n", c.name.c_str(), p.name.c_str(), m.c_str());
  }
  for (const st::LabelPlacement& p : r.labels) {
    const bool engraved = p.mode == st::LabelMode::engrave;
    std::printf("    label '%s': \"%s\" %s %.2f mm %s, %.1f x %.1f mm", p.name.c_str(), p.text.c_str(),
                engraved ? "engraved" : "embossed", p.depth, engraved ? "deep" : "high", p.width, p.text_height);
    if (engraved) std::printf("; wall under it %.2f mm", p.min_wall);
    if (std::isfinite(p.min_clearance)) std::printf("; %.1f mm from the nearest sleeve or slot", p.min_clearance);
    std::printf("\n");
  }
  if (const st::InsertionReport& ins = r.insertion; ins.analysed) {
    std::printf("  insertion: along (%.3f, %.3f, %.3f)%s; undercut %.1f of %.1f mm^2 in %.3f s\n", ins.direction.x(),
                ins.direction.y(), ins.direction.z(), ins.automatic ? ", the least-undercut direction" : "",
                ins.undercut_area_mm2, ins.region_area_mm2, t.insertion);
    if (ins.blocked_out) {
      std::printf("  block-out: %zu zone(s) filled (%.1f mm^3), %zu at the rim cut off (%.1f mm^2), %zu left as they "
                  "were, in %.3f s\n",
                  ins.blocked_out_zones, ins.blocked_out_volume_mm3, ins.trimmed_zones, ins.trimmed_area_mm2,
                  ins.unfilled.size(), t.block_out);
      if (ins.skirt_faces > 0)
        std::printf("  skirt: %.1f mm^2 hung from the silhouette, down to %.1f mm along the insertion direction\n",
                    ins.skirt_area_mm2, ins.skirt_depth_mm);
      if (!ins.skirt_dropped.empty())
        std::fprintf(stderr,
                     "warning: %s: the guide ends where the bone turns under, without the skirt down to the "
                     "drawn border (with it: %s)\n",
                     c.name.c_str(), ins.skirt_dropped.c_str());
    }
    if (ins.removal_checked) {
      if (ins.removable)
        std::printf("  removal: the guide comes off along (%.3f, %.3f, %.3f) over %.0f mm without meeting the bone; "
                    "%.0f%% of its inner surface in contact (checked in %.3f s)\n",
                    -ins.direction.x(), -ins.direction.y(), -ins.direction.z(), ins.removal_distance,
                    100.0 * ins.contact_area_mm2 / std::max(ins.inner_area_mm2, 1e-300), t.removal);
      else
        std::printf("  removal: the guide meets the bone when it comes off along (%.3f, %.3f, %.3f), first near %s "
                    "(%zu place(s)); checked in %.3f s\n",
                    -ins.direction.x(), -ins.direction.y(), -ins.direction.z(),
                    st::detail::where(ins.blocking.front()).c_str(), ins.blocking.size(), t.removal);
      if (!ins.removable)
        std::fprintf(
            stderr,
            "warning: %s: the guide cannot come off the bone along its insertion direction (it meets "
            "the bone near %s)%s\n",
            c.name.c_str(), st::detail::where(ins.blocking.front()).c_str(),
            ins.blocked_out ? "" : "; set template.insertion to \"auto\" or a direction to block the undercuts out");
    }
  }

  if (const st::StabilityResult& s = r.stability; s.analysed) {
    const st::StabilityReport& sr = s.report;
    std::printf("  stability: score %.2f from %zu contacts (computed in %.3f s); worst motion: %s\n", sr.score,
                sr.contacts, t.stability, sr.worst_motion.describe().c_str());
    for (const st::FreeMotion& m : sr.free_motions) std::printf("    free: %s\n", m.describe().c_str());
    std::printf("    press near %s along the insertion direction (score %.2f there)\n",
                st::detail::where(s.press.point).c_str(), s.press.score);
    if (s.extend.found) std::printf("    to hold it better: %s\n", s.extend.describe().c_str());
  }

  if (!report_path.empty()) {
    nlohmann::json rep = st::to_json(r, o);
    rep["case"] = c.name;
    rep["output"] = out_path;
    rep["input"] = {{"triangles", bone.face_count()},
                    {"points", bone.vertex_count()},
                    {"degenerate_dropped", read_report.degenerate_dropped},
                    {"read_seconds", read_seconds}};
    rep["times"]["wall_clock"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    rep["peak_memory_mb"] = peak_memory_mb();
    rep["fit"]["thickness"] = c.thickness;
    rep["fit"]["clearance"] = c.clearance;
    st::detail::write_text_atomically(report_path, rep.dump(2) + "\n", "report");
  }
  return 0;
}

int boolean(int argc, char** argv, st::BooleanOp op) {
  std::vector<std::string> inputs;
  std::string out_path;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if ((a == "-o" || a == "--output") && i + 1 < argc) out_path = argv[++i];
    else if (!a.empty() && a[0] != '-') inputs.push_back(a);
    else throw st::InvalidInput("unexpected argument '" + a + "'\n" + kUsage);
  }
  if (inputs.size() != 2 || out_path.empty())
    throw st::InvalidInput(std::string("a Boolean operation needs two meshes and -o OUT.stl\n") + kUsage);
  const st::TriangleMesh a = st::read_mesh(inputs[0]);
  const st::TriangleMesh b = st::read_mesh(inputs[1]);
  st::check_closed_manifold(a, inputs[0]);
  st::check_closed_manifold(b, inputs[1]);
  st::BooleanOptions options;
  options.check_operands = false; // done above, naming the files
  const st::BooleanResult r = st::mesh_boolean(a, b, op, options);
  const st::SolidReport report = st::check_solid(r.mesh);
  if (r.mesh.empty()) throw st::GeometryError("the result is empty (the operands do not overlap)");
  if (!report.valid()) throw st::GeometryError("the result failed its check: " + report.summary());
  const std::filesystem::path out_file(out_path);
  if (out_file.has_parent_path()) std::filesystem::create_directories(out_file.parent_path());
  st::write_stl(r.mesh, out_path, "surgical-template boolean");
  std::printf("%s: %zu triangles, volume %.3f mm^3, %zu intersection edges, %.3f s%s\n", out_path.c_str(),
              r.mesh.triangles.size(), report.volume, r.curve_segments, r.seconds,
              r.attempts > 1 ? " (touching contact resolved by a displacement)" : "");
  return 0;
}

int check(int argc, char** argv) {
  if (argc != 3) throw st::InvalidInput(std::string("check needs one mesh file\n") + kUsage);
  const st::TriangleMesh mesh = st::read_mesh(argv[2]);
  const st::SolidReport r = st::check_solid(mesh);
  std::printf("%s: %s\n", argv[2], r.summary().c_str());
  return r.valid() ? 0 : 1;
}

// The tool's working memory in transparent huge pages. A design touches about 400 bytes per input
// triangle, much of it freshly allocated, and on virtual machines each first touch of a 4 KiB page
// costs microseconds (200k-triangle case: 24k faults, a third of the wall clock). Every thread
// allocates from the main heap, which keeps what is freed; a reserve at its top is advised for huge
// pages (virtual until touched). Where huge pages are off this does nothing; the results are the same.
void use_huge_pages() {
#if defined(__GLIBC__) && defined(MADV_HUGEPAGE)
  constexpr std::size_t kHuge = std::size_t{2} << 20;
  constexpr std::size_t kReserve = std::size_t{1} << 30;
  mallopt(M_ARENA_MAX, 1);            // threads share the advised heap
  mallopt(M_MMAP_MAX, 0);             // large blocks from it too, not from fresh mappings
  mallopt(M_TRIM_THRESHOLD, INT_MAX); // what is freed stays (the reserve too), its pages there
  const auto begin = reinterpret_cast<std::uintptr_t>(sbrk(0));
  void* reserve = std::malloc(kReserve);
  const auto end = reinterpret_cast<std::uintptr_t>(sbrk(0));
  const std::uintptr_t first = (begin + kHuge - 1) / kHuge * kHuge;
  if (reserve != nullptr && end > first) madvise(reinterpret_cast<void*>(first), end - first, MADV_HUGEPAGE);
  std::free(reserve);
#endif
}

} // namespace

int main(int argc, char** argv) {
  use_huge_pages();
  try {
    const std::string command = argc > 1 ? argv[1] : "";
    if (command == "design") return design(argc, argv);
    if (command == "check") return check(argc, argv);
    if (command == "plan") return plan(argc, argv);
    if (command == "presets") return presets(argc, argv);
    if (command == "union") return boolean(argc, argv, st::BooleanOp::Union);
    if (command == "difference") return boolean(argc, argv, st::BooleanOp::Difference);
    if (command == "intersection") return boolean(argc, argv, st::BooleanOp::Intersection);
    if (command == "-h" || command == "--help") {
      std::fputs(kUsage, stdout);
      return 0;
    }
    std::fputs(kUsage, stderr);
    return 2;
  } catch (const st::InvalidInput& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  } catch (const st::GeometryError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
