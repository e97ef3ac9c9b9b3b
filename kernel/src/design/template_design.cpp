#include "st/design/template_design.h"
#include "detail/parallel.h"
#include "detail/timing.h"
#include "design/template_analyses.h"
#include "design/template_shell.h"
#include "st/guide/sleeve.h"

#include "st/design/blockout.h"
#include "st/design/skirt.h"
#include "st/design/insertion.h"
#include "st/validate/removal.h"
#include "st/validate/stability.h"

#include "st/core/aabb_tree.h"
#include "st/design/cut.h"
#include "detail/format.h"
#include "st/core/tolerances.h"
#include "st/core/errors.h"
#include "st/design/surface_curve.h"
#include "st/core/topology.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <future>
#include <memory>
#include <unordered_map>

namespace st {

namespace {

using detail::Clock;
using detail::seconds_since;
using template_detail::analyse_removal;
using template_detail::analyse_shell;
using template_detail::Analyses;
using template_detail::AnalysisInputs;
using template_detail::contact_reach;
using template_detail::PreparedAnalyses;

void check_options(const TemplateOptions& o) {
  auto finite_positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!finite_positive(o.thickness))
    throw InvalidInput("template.thickness must be a finite number > 0 mm, got " + detail::number(o.thickness));
  if (o.thickness > tol::kMaxThickness_mm)
    throw InvalidInput("template.thickness " + detail::mm(o.thickness) + " is absurd (over " +
                       detail::mm(tol::kMaxThickness_mm) + ")");
  if (!std::isfinite(o.clearance) || o.clearance < 0.0)
    throw InvalidInput("template.clearance must be a finite number >= 0 mm, got " + detail::number(o.clearance));
  if (o.clearance > tol::kMaxClearance_mm)
    throw InvalidInput("template.clearance " + detail::mm(o.clearance) + " is absurd (over " +
                       detail::mm(tol::kMaxClearance_mm) + ")");
  if (!std::isfinite(o.resolution) || o.resolution < 0.0)
    throw InvalidInput("template.resolution must be a finite number > 0 mm, got " + detail::number(o.resolution));
  if (o.resolution > tol::kMaxCellSizePerOffset * o.thickness)
    throw InvalidInput("template.resolution " + detail::mm(o.resolution) + " is over half the thickness " +
                       detail::mm(o.thickness) + "; use at most " +
                       detail::mm(tol::kMaxCellSizePerOffset * o.thickness) + " (thickness / 2)");
  if (o.sampling_step < 0)
    throw InvalidInput("template.sampling_step must be >= 1, got " + detail::number(o.sampling_step));
  if (o.inside && !o.inside->allFinite()) throw InvalidInput("boundary.inside has a non-finite coordinate");
  for (const TubeSpec& t : o.tubes) check_tube(t); // before any work
  for (const SlotSpec& s : o.slots) check_slot(s);
  for (const LabelSpec& l : o.labels) {
    check_label(l);
    if (l.mode == LabelMode::engrave && !(l.depth < o.thickness))
      throw InvalidInput("label '" + l.name + "': depth " + detail::mm(l.depth) +
                         " must be less than the template's thickness " + detail::mm(o.thickness));
    if (l.outlines.empty())
      throw InvalidInput("label '" + l.name +
                         "': its text has no outlines (they are made with OpenCASCADE's fonts; this build has none)");
  }
}

// Moves the region off the bone by `distance` (the clearance) along a smooth normal field of the
// bone: vertex normals averaged over a few rings (raw normals of scanned bone turn sharply from one
// vertex to the next), interpolated along the cut edges for the rim vertices. Because the field is
// continuous across the bone's triangles, the tiny triangles the cut makes move with their
// neighbours instead of folding over.
void displace(const MeshTopology& bone, CutResult& region, double distance) {
  if (distance <= 0.0) return;
  const TriangleMesh& mesh = bone.mesh();
  std::unordered_map<Index, Vec3> normal;
  for (const CutResult::Source& s : region.source)
    for (Index v : s.edge) normal.emplace(v, Vec3::Zero());
  for (auto& [v, n] : normal) {
    for (Index f : bone.faces_of(v)) n += triangle_normal(mesh, f);
    if (n.norm() > 0.0) n.normalize();
  }
  for (int iteration = 0; iteration < 4; ++iteration) {
    std::unordered_map<Index, Vec3> next = normal;
    for (auto& [v, n] : next) {
      Vec3 sum = Vec3::Zero();
      for (Index f : bone.faces_of(v))
        for (Index w : mesh.triangles[f])
          if (const auto it = normal.find(w); it != normal.end()) sum += it->second;
      if (sum.norm() > 0.0) n = sum.normalized();
    }
    normal = std::move(next);
  }
  for (std::size_t i = 0; i < region.source.size(); ++i) {
    const CutResult::Source& s = region.source[i];
    Vec3 n = (1.0 - s.t) * normal[s.edge[0]] + s.t * normal[s.edge[1]];
    if (n.norm() > 0.0) n.normalize();
    region.region.positions[i] += distance * n;
  }
}

// The undercut of the covered bone along the given direction or the least-undercut one, sampled
// at about 20000 points (at least 0.05 mm apart).
InsertionReport analyse_insertion(const AabbTree& tree, const TriangleMesh& region,
                                  const std::optional<Vec3>& direction, double reach) {
  InsertionReport report;
  report.analysed = true;
  report.automatic = !direction;
  const Vec3 d = direction ? *direction : least_undercut_direction(tree, region, std::nullopt, reach);
  const double area = surface_area(region);
  const Undercut u = undercut(tree, region, d, std::max(0.05, std::sqrt(2.0 * area / 20000.0)), reach);
  report.direction = u.direction;
  report.region_area_mm2 = u.area_mm2;
  report.undercut_area_mm2 = u.hidden_mm2;
  report.hidden = u.hidden;
  report.region = region;
  return report;
}

// The region's faces after block-out, its unused vertices dropped (rim and sources renumbered). With
// zones trimmed at the rim, marks the region's vertices on the rim as cut and gives the positions of the
// rim vertices dropped (where the skirt goes, skirt.h).
struct RimChange {
  std::vector<std::uint8_t> on_input_rim; ///< per region vertex
  std::vector<Vec3> dropped_rim;
};
RimChange apply_block_out(CutResult& inner, BlockOutResult&& b) {
  std::vector<Index> all(b.triangles.size()), old_of; // old_of: per kept vertex, its index before
  std::iota(all.begin(), all.end(), Index{0});
  TriangleMesh region = submesh(TriangleMesh{inner.region.positions, std::move(b.triangles)}, all, &old_of);
  std::vector<CutResult::Source> source;
  std::vector<Index> source_vertex, renumber(inner.region.vertex_count(), kInvalidIndex);
  for (Index v = 0; v < old_of.size(); ++v) {
    renumber[old_of[v]] = v;
    source.push_back(inner.source[old_of[v]]);
    source_vertex.push_back(inner.source_vertex[old_of[v]]);
  }
  RimChange change;
  if (b.rim_changed) {
    change.on_input_rim.assign(region.vertex_count(), 0);
    for (Index v : inner.rim)
      if (renumber[v] != kInvalidIndex) change.on_input_rim[renumber[v]] = 1;
      else change.dropped_rim.push_back(inner.region.positions[v]);
  }
  inner.region = std::move(region);
  if (b.rim_changed) // trimmed zones: the rim is the region's one border loop (block_out checked it)
    inner.rim = border_loops(inner.region, MeshTopology(inner.region).all_opposites()).front();
  else
    for (Index& v : inner.rim) v = renumber[v];
  inner.source = std::move(source);
  inner.source_vertex = std::move(source_vertex);
  return change;
}

} // namespace

TemplateResult design_template(const TriangleMesh& bone, const TemplateOptions& options) {
  check_options(options);
  check_mesh(bone, "bone mesh");
  if (bone.empty()) throw InvalidInput("bone mesh: no triangles");

  TemplateResult result;
  std::optional<AabbTree> bone_tree;
  // Pins planned by their entry only go into the bone there (pin_direction), decided before any work.
  std::vector<TubeSpec> tubes = options.tubes;
  direct_pins(tubes, [&]() -> const AabbTree& {
    if (!bone_tree) bone_tree.emplace(bone);
    return *bone_tree;
  });
  // The bone's tree, for the insertion analysis, is built beside the curve and the cut.
  std::optional<detail::Background> bone_tree_build;
  if (options.analyse_insertion && !bone_tree) bone_tree_build.emplace([&] { bone_tree.emplace(bone); });

  // 1. Inner surface: the boundary curve and the cut.
  auto t0 = Clock::now();
  const MeshTopology topology(bone);
  CurveOptions curve_options;
  curve_options.max_snap_distance = options.max_snap_distance;
  curve_options.also_index = options.inside;
  const SurfaceCurve curve = trace_surface_curve(topology, options.boundary_points, curve_options);
  CutOptions cut_options;
  cut_options.inside = options.inside;
  CutResult inner = cut_region(topology, curve, cut_options);
  const TriangleMesh bone_region = inner.region;
  result.times.inner_segmentation = seconds_since(t0);
  std::optional<SweepTest> sweep; // the bone prepared for the block-out's and the removal check's sweeps
  RimChange rim_change;           // where block-out trimmed the rim
  // The insertion analysis reads the bone and the region as cut. With block-out the inner surface
  // depends on it: it runs first. Without, nothing the shell is built from does (see below).
  auto analyse = [&] {
    const auto t = Clock::now();
    if (bone_tree_build) bone_tree_build->join();
    result.insertion = analyse_insertion(*bone_tree, bone_region, options.insertion, options.removal_distance);
    result.times.insertion = seconds_since(t);
  };
  if (options.analyse_insertion && options.block_out) {
    analyse();
    if (result.insertion.undercut_area_mm2 > 0.0) {
      t0 = Clock::now();
      sweep.emplace(*bone_tree, &topology);
      BlockOutResult b =
          block_out(*sweep, bone_region, result.insertion.hidden, result.insertion.direction, options.removal_distance);
      InsertionReport& ins = result.insertion;
      ins.blocked_out = true;
      ins.blocked_out_volume_mm3 = b.volume_mm3;
      ins.blocked_out_zones = b.filled_zones;
      ins.trimmed_zones = b.trimmed_zones;
      ins.trimmed_area_mm2 = b.trimmed_area_mm2;
      ins.unfilled = b.unfilled;
      ins.filled = b.filled;
      rim_change = apply_block_out(inner, std::move(b));
      result.times.block_out = seconds_since(t0);
      result.times.inner_segmentation += result.times.block_out;
    }
  }
  t0 = Clock::now();
  displace(topology, inner, options.clearance);
  // Where zones were cut off at the rim, the skirt hangs from the silhouette; the guide without it is
  // kept to fall back on if the guide with it fails its check.
  std::optional<CutResult> unskirted;
  if (!rim_change.dropped_rim.empty()) {
    unskirted = inner;
    InsertionReport& ins = result.insertion;
    const SkirtResult skirt = add_skirt(inner, rim_change.on_input_rim, rim_change.dropped_rim, ins.direction,
                                        *bone_tree, options.clearance, ins.filled);
    ins.skirt_faces = skirt.faces;
    ins.skirt_area_mm2 = skirt.area_mm2;
    ins.skirt_depth_mm = skirt.max_depth_mm;
    if (skirt.faces == 0) unskirted.reset();
  }
  result.curve = curve.polyline;
  result.inner_rim_points = inner.rim.size();
  result.times.inner_segmentation += seconds_since(t0);

  // Without block-out the insertion analysis, and then what the shell's analyses read that the shell
  // does not change (PreparedAnalyses), run beside the shell, in the time its steps leave a core idle.
  // (At normal priority: the design waits for both, and a lowered one cannot be raised again without
  // privileges; under load from other processes it would starve.) The insertion is known (its failure
  // thrown, before what the shell threw) once the shell is built, before the parts read the bone's
  // tree and the analyses the report.
  std::promise<void> insertion_promise;
  std::future<void> insertion_future;
  PreparedAnalyses prepared;
  std::optional<detail::Background> preparing; // declared after what it reads: joined before it goes
  if (options.analyse_insertion && !options.block_out) {
    insertion_future = insertion_promise.get_future();
    preparing.emplace([&] {
      try {
        analyse();
      } catch (...) {
        insertion_promise.set_exception(std::current_exception());
        return;
      }
      insertion_promise.set_value();
      if (!options.check) return;
      try {
        const auto t = Clock::now();
        const InsertionReport& ins = result.insertion;
        prepared.resolution = template_detail::shell_resolution(options);
        prepared.stability =
            stability_of_contacts(inner.region, *bone_tree, ins.direction, contact_reach(options, prepared.resolution),
                                  ins.filled, false, &topology);
        prepared.stability_seconds = seconds_since(t);
        prepared.covered_tree.emplace(ins.region.empty() ? inner.region : ins.region);
        if (options.measure_fit) prepared.inner_tree.emplace(inner.region);
      } catch (...) {
        prepared.failure = std::current_exception();
      }
    });
    prepared.made = &*preparing;
  }
  auto insertion_known = [&] {
    if (insertion_future.valid()) insertion_future.get();
  };

  // 2.-5. The shell: offset, outer surface, wall; then the parts. Checked, not trusted: a simplified
  // outer surface that fails falls back to the surface as contoured, marching cubes to marching
  // tetrahedra. With parts, the finished guide is checked and the shell only when the guide fails (a
  // valid guide is what is printed; a broken shell breaks the guide too).
  const bool parts = !tubes.empty() || !options.slots.empty() || !options.labels.empty();
  GuideOptions guide_options;
  guide_options.chordal_tolerance = options.tube_tolerance;
  guide_options.clearance = options.clearance;
  guide_options.thickness = options.thickness;
  guide_options.check_blade_paths = options.check;
  std::optional<template_detail::ShellBuild> built;
  std::optional<GuideResult> guide;
  // The analyses of the candidate shell, from when it is built, and of the candidate guide (or shell),
  // beside its check (declared after what they read, so that they are joined before it goes).
  Analyses analyses;
  // The candidate's tree, read by the removal check and the guide's check: built first thing on the
  // removal check's thread, while the check goes through the guide's topology on the caller's.
  std::optional<AabbTree> candidate_tree;
  std::shared_future<void> candidate_tree_built;
  std::optional<detail::Background> analysing_shell, analysing_guide;
  auto stop_analyses = [&] {
    analysing_guide.reset();
    analysing_shell.reset();
  };
  auto inputs = [&] {
    return AnalysisInputs{inner.region,
                          inner.rim,
                          built->shell.outer.positions,
                          bone_region,
                          curve.polyline,
                          options.analyse_insertion ? &*bone_tree : nullptr,
                          topology,
                          sweep ? &*sweep : nullptr,
                          result.insertion,
                          result.resolution,
                          preparing && options.check ? &prepared : nullptr};
  };
  auto analyse_shell_beside = [&] {
    stop_analyses();
    if (!options.check) return;
    analysing_shell.emplace([&, in = inputs()] { analyse_shell(in, options, analyses); });
  };
  // The candidate's analysis and tree let go (the analysis first: it reads the tree).
  auto drop_candidate = [&] {
    analysing_guide.reset();
    candidate_tree.reset();
    candidate_tree_built = {};
  };
  auto analyse_guide_beside = [&](const TriangleMesh& candidate) {
    drop_candidate();
    if (!options.check || !options.analyse_insertion) return; // the check builds the tree it needs
    auto tree_built = std::make_shared<std::promise<void>>();
    candidate_tree_built = tree_built->get_future().share();
    analysing_guide.emplace([&, tree_built, in = inputs()] {
      try {
        candidate_tree.emplace(candidate);
      } catch (...) {
        tree_built->set_exception(std::current_exception());
        throw;
      }
      tree_built->set_value();
      analyse_removal(in, candidate, *candidate_tree, options, analyses);
    });
  };
  // The solid check of the shell or guide; of the candidate, with its tree from beside.
  auto check = [&](const TriangleMesh& mesh, bool candidate = false) {
    const auto t_check = Clock::now();
    SolidOptions solid_options;
    if (candidate && candidate_tree_built.valid())
      solid_options.tree_source = [&]() -> const AabbTree& {
        candidate_tree_built.get(); // rethrows what building it threw
        return *candidate_tree;
      };
    result.solid = check_solid(mesh, solid_options);
    result.times.validation += seconds_since(t_check);
    return result.solid.valid();
  };
  // One contouring's shell (and its contoured alternative) with the parts: true when it passed.
  auto accept = [&](bool tetrahedra) {
    stop_analyses();
    result.body_inner_faces = inner.region.face_count();
    try {
      built = template_detail::build_shell(inner, options, tetrahedra, result);
    } catch (...) {
      insertion_known();
      throw;
    }
    insertion_known();
    guide_options.bone_tree = bone_tree ? &*bone_tree : nullptr; // built (and joined) by now when there is one
    for (int contoured = 0; contoured < (built->contoured ? 2 : 1); ++contoured) {
      if (contoured) {
        stop_analyses();
        built->shell = std::move(*built->contoured);
      }
      const TriangleMesh& shell = built->shell.mesh;
      analyse_shell_beside();
      if (!parts) {
        analyse_guide_beside(shell);
        if (!options.check || check(shell, true)) return true;
        continue;
      }
      // Checked, the Booleans leave the faces they make to the guide's check, which covers them; when
      // it fails, a Boolean throws (a conflict found before them is found again: an error costs a second
      // build) or a part was dropped after them (the check does not see it), the guide is built again
      // with the Booleans' own checks, which perturb a degenerate contact away.
      std::optional<GeometryError> failure;
      for (guide_options.check_booleans = !options.check;; guide_options.check_booleans = true) {
        failure.reset();
        try {
          guide = build_guide(shell, result.body_inner_faces, bone, GuideParts{tubes, options.slots, options.labels},
                              guide_options);
          result.times.boolean += guide->seconds;
          result.times.validation += guide->blade_path_seconds;
          if (guide->unchecked_part_dropped) {
            guide.reset();
            continue; // built again with the checks
          }
          analyse_guide_beside(guide->mesh);
          if (!options.check || check(guide->mesh, true)) return true;
          failure.emplace("the guide with its tubes failed its check: " + result.solid.summary());
        } catch (const GeometryError& e) {
          failure = e;
        }
        if (guide_options.check_booleans) break;
        drop_candidate(); // it reads the guide
        guide.reset();
      }
      if (!options.check || check(shell)) throw *failure; // the parts' doing, not the shell's
      analysing_guide.reset();                            // it reads the guide
      guide.reset();
    }
    return false;
  };
  auto design_shell = [&]() -> std::optional<std::string> {
    try {
      if (accept(false)) return std::nullopt;
      const std::string cubes = result.solid.summary();
      if (accept(true)) return std::nullopt;
      return "the template shell failed its check: " + result.solid.summary() + " (contoured by cubes: " + cubes + ")";
    } catch (const GeometryError& e) {
      if (!unskirted) throw;
      return e.what();
    }
  };
  std::optional<std::string> failure = design_shell();
  if (failure && unskirted) { // the skirt's doing: the guide ends at the silhouette instead
    stop_analyses();          // (a skirt comes with block-out only: nothing that reads `inner` was prepared)
    inner = std::move(*unskirted);
    unskirted.reset(); // a failure now is the guide's own: thrown as it is
    InsertionReport& ins = result.insertion;
    ins.filled.resize(inner.region.face_count());
    ins.skirt_faces = 0;
    ins.skirt_area_mm2 = ins.skirt_depth_mm = 0.0;
    ins.skirt_dropped = *failure;
    failure = design_shell();
  }
  if (failure) throw GeometryError(*failure);
  // The analyses read the accepted guide, its shell and surfaces: joined before they move. Validation
  // counts the wall time from the check's start to here: the check's, and what the analyses took
  // beyond it.
  const auto t_join = Clock::now();
  if (analysing_shell) analysing_shell->join(); // what the analyses threw is thrown here
  if (analysing_guide) analysing_guide->join();
  result.times.validation += seconds_since(t_join);
  if (analyses.fit) result.fit = *analyses.fit;
  if (analyses.stability) result.stability = std::move(*analyses.stability);
  result.times.stability = analyses.stability_seconds;
  if (const std::optional<RemovalReport>& removal = analyses.removal) {
    InsertionReport& ins = result.insertion;
    ins.removal_checked = true;
    ins.removable = removal->removable;
    ins.removal_distance = removal->distance;
    ins.blocking = removal->blocking;
    ins.blocked_faces = removal->blocked_faces;
    ins.inner_area_mm2 = analyses.inner_area_mm2;
    ins.contact_area_mm2 = analyses.contact_area_mm2;
    result.times.removal = analyses.removal_seconds;
  }
  result.shell = std::move(built->shell.mesh);
  result.times.total = result.times.inner_segmentation + result.times.offset + result.times.outer_points +
                       result.times.outer_segmentation + result.times.connection;
  if (guide) {
    result.tubes = std::move(guide->tubes);
    result.slots = std::move(guide->slots);
    result.labels = std::move(guide->labels);
    result.blade_paths = std::move(guide->blade_paths);
    result.perturbed_operations = guide->perturbed_operations;
    result.max_perturbation = guide->max_perturbation;
    result.curve_tolerance = guide->curve_tolerance;
    result.fragments_dropped = guide->fragments_dropped;
    result.from_tube = std::move(guide->from_tube);
    result.columns = std::move(guide->columns);
    result.bores = std::move(guide->bores);
    result.body = std::move(result.shell);
    result.shell = std::move(guide->mesh);
  } else {
    result.body = result.shell;
    result.from_tube.assign(result.shell.face_count(), 0);
  }
  result.inner = std::move(inner.region);
  result.outer = std::move(built->shell.outer);
  return result;
}

} // namespace st
