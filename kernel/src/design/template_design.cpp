#include "st/design/template_design.h"
#include "st/guide/sleeve.h"

#include "st/design/blockout.h"
#include "st/design/insertion.h"
#include "st/validate/removal.h"

#include "st/core/aabb_tree.h"
#include "st/design/cut.h"
#include "st/design/decimate.h"
#include "detail/format.h"
#include "st/core/tolerances.h"
#include "st/core/errors.h"
#include "st/design/offset.h"
#include "st/design/ruled_surface.h"
#include "st/design/surface_curve.h"
#include "st/core/topology.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <numeric>
#include <unordered_map>
#include <unordered_set>

namespace st {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

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

// The region vertex farthest (in edges) from the border: a point well inside the region.
Index innermost_vertex(const TriangleMesh& mesh, const std::vector<Index>& rim) {
  const MeshTopology topology(mesh);
  std::vector<char> seen(mesh.vertex_count(), 0);
  std::deque<Index> queue;
  for (Index v : rim) {
    seen[v] = 1;
    queue.push_back(v);
  }
  Index last = rim.front();
  while (!queue.empty()) {
    const Index v = queue.front();
    queue.pop_front();
    last = v;
    for (Index f : topology.faces_of(v))
      for (Index w : mesh.triangles[f])
        if (!seen[w]) {
          seen[w] = 1;
          queue.push_back(w);
        }
  }
  return last;
}

// Faces of `mesh` with a corner within about `reach` of a rim vertex or of the centre vertex.
std::vector<Index> faces_near(const TriangleMesh& mesh, const TriangleMesh& region, const std::vector<Index>& rim,
                              Index centre, double reach) {
  auto cell = [reach](const Vec3& p) {
    const Eigen::Array3d c = (p / reach).array().floor();
    return (static_cast<std::uint64_t>(static_cast<std::int64_t>(c[0]) & 0x1fffff) << 42) |
           (static_cast<std::uint64_t>(static_cast<std::int64_t>(c[1]) & 0x1fffff) << 21) |
           (static_cast<std::uint64_t>(static_cast<std::int64_t>(c[2]) & 0x1fffff));
  };
  std::unordered_set<std::uint64_t> cells;
  auto mark = [&](const Vec3& p) {
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) cells.insert(cell(p + reach * Vec3(dx, dy, dz)));
  };
  for (Index v : rim) mark(region.positions[v]);
  mark(region.positions[centre]);
  std::vector<Index> faces;
  for (Index f = 0; f < mesh.face_count(); ++f)
    if (cells.count(cell(mesh.positions[mesh.triangles[f][0]]))) faces.push_back(f);
  return faces;
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

// The region's faces after block-out, its unused vertices dropped (rim and sources renumbered).
void apply_block_out(CutResult& inner, BlockOutResult&& b) {
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
  inner.region = std::move(region);
  if (b.rim_changed) // trimmed zones: the rim is the region's one border loop (block_out checked it)
    inner.rim = border_loops(inner.region, MeshTopology(inner.region).all_opposites()).front();
  else
    for (Index& v : inner.rim) v = renumber[v];
  inner.source = std::move(source);
  inner.source_vertex = std::move(source_vertex);
}

// The inner surface's area within `reach` of the bone: kept faces lie at the clearance (their
// whole area counts); block-out fills are sampled (16 points each).
double contact_area(const TriangleMesh& inner, const std::vector<std::uint8_t>& filled, const AabbTree& bone,
                    double reach) {
  double area = 0.0;
  for (Index f = 0; f < inner.face_count(); ++f) {
    const Triangle& t = inner.triangles[f];
    const Vec3 &a = inner.positions[t[0]], &b = inner.positions[t[1]], &c = inner.positions[t[2]];
    const double full = 0.5 * triangle_normal(inner, f).norm();
    if (f >= filled.size() || !filled[f]) {
      area += full;
      continue;
    }
    constexpr int k = 4;
    for (int i = 0; i < k; ++i)
      for (int j = 0; i + j < k; ++j)
        for (int up = 0; up < (i + j + 2 <= k ? 2 : 1); ++up) {
          const double s = (i + (up ? 2.0 : 1.0) / 3.0) / k, r = (j + (up ? 2.0 : 1.0) / 3.0) / k;
          const Vec3 p = a + s * (b - a) + r * (c - a);
          if (const auto cp = bone.closest_point(p, reach); cp && cp->distance <= reach) area += full / (k * k);
        }
  }
  return area;
}

double point_segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

} // namespace

TemplateResult design_template(const TriangleMesh& bone, const TemplateOptions& options) {
  check_options(options);
  check_mesh(bone, "bone mesh");
  if (bone.empty()) throw InvalidInput("bone mesh: no triangles");

  TemplateResult result;
  const double T = options.thickness;
  std::optional<AabbTree> bone_tree;
  // Pins planned by their entry only go into the bone there (pin_direction), decided before any work.
  std::vector<TubeSpec> tubes = options.tubes;
  direct_pins(tubes, [&]() -> const AabbTree& {
    if (!bone_tree) bone_tree.emplace(bone);
    return *bone_tree;
  });

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
  if (options.analyse_insertion) {
    t0 = Clock::now();
    if (!bone_tree) bone_tree.emplace(bone);
    result.insertion = analyse_insertion(*bone_tree, bone_region, options.insertion, options.removal_distance);
    result.times.insertion = seconds_since(t0);
    if (options.block_out && result.insertion.undercut_area_mm2 > 0.0) {
      t0 = Clock::now();
      sweep.emplace(*bone_tree);
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
      apply_block_out(inner, std::move(b));
      result.times.block_out = seconds_since(t0);
      result.times.inner_segmentation += result.times.block_out;
    }
  }
  t0 = Clock::now();
  displace(topology, inner, options.clearance);
  result.curve = curve.polyline;
  result.inner_rim_points = inner.rim.size();
  result.times.inner_segmentation += seconds_since(t0);

  // 2. Offset of the inner surface.
  t0 = Clock::now();
  OffsetOptions offset_options;
  offset_options.distance = T;
  // Without an explicit resolution, T / 8: independent of how finely the bone is triangulated, so
  // a refined scan costs no more here than the coarse one.
  offset_options.cell_size = options.resolution > 0.0 ? options.resolution : T / 8.0;
  offset_options.front_only = true;
  offset_options.max_cells = options.max_field_cells;
  const OffsetResult offset = offset_surface(inner.region, offset_options);
  result.resolution = offset.cell_size;
  result.field_voxels = offset.band_voxels;
  result.offset_triangles = offset.surface.face_count();
  result.times.offset = seconds_since(t0);

  // 3. Points for the outer cut: border samples moved along averaged normals onto the offset.
  t0 = Clock::now();
  const std::size_t m = inner.rim.size();
  double rim_length = 0.0;
  for (std::size_t i = 0; i < m; ++i)
    rim_length += (inner.region.positions[inner.rim[(i + 1) % m]] - inner.region.positions[inner.rim[i]]).norm();
  const bool auto_step = options.sampling_step == 0;
  int step = options.sampling_step;
  if (auto_step) step = std::max(1, static_cast<int>(std::lround(0.5 * T / (rim_length / static_cast<double>(m)))));
  step = std::clamp<int>(step, 1, std::max<int>(1, static_cast<int>(m / 3)));
  const std::vector<Vec3> normals = vertex_normals(inner.region);
  // Rays start at the rim and at the region's innermost vertex and go at most 3T: index only the
  // offset triangles near those (a hash grid of cells 3T wide over the start points).
  const Index centre = innermost_vertex(inner.region, inner.rim);
  const Vec3& centre_point = inner.region.positions[centre];
  const AabbTree offset_tree(offset.surface, faces_near(offset.surface, inner.region, inner.rim, centre, 3.0 * T));
  // Every `step` rim points, a ray along the normal averaged over the step meets the offset.
  auto project = [&](int step, std::vector<Vec3>& points, std::vector<Index>& faces) {
    points.clear();
    faces.clear();
    const int half = std::max(1, step / 2);
    for (std::size_t i = 0; i < m; i += static_cast<std::size_t>(step)) {
      if (m - i < static_cast<std::size_t>(step) / 2 && i != 0) break; // avoid a crowded last sample
      Vec3 n = Vec3::Zero();
      for (int k = -half; k <= half; ++k)
        n += normals[inner.rim[(i + m + static_cast<std::size_t>(k + static_cast<int>(m))) % m]];
      if (n.squaredNorm() == 0.0) continue;
      n.normalize();
      const Vec3& p = inner.region.positions[inner.rim[i]];
      if (const auto hit = offset_tree.first_hit(p, n, 0.0, 3.0 * T)) {
        points.push_back(hit->point);
        faces.push_back(hit->face);
      } else if (const auto c = offset_tree.closest_point(p + T * n)) {
        points.push_back(c->point);
        faces.push_back(c->face);
      }
    }
  };
  // A point on the outer sheet above the middle of the inner surface tells the sides apart.
  const auto above = offset_tree.first_hit(centre_point, normals[centre], 0.0, 3.0 * T);
  if (!above)
    throw GeometryError("the offset surface is missing above the inner surface near " + detail::where(centre_point));
  result.times.outer_points = seconds_since(t0);

  // 4. Outer surface: the offset cut along those points, keeping the side above the inner surface.
  //    Where the border turns tightly, projected samples can zig-zag and the loop cross itself (the
  //    paper's reason for a sampling step); with an automatic step, a coarser one is tried then.
  const MeshTopology offset_topology(offset.surface);
  CurveOptions outer_curve_options;
  outer_curve_options.name = "outer cut";
  CutOptions outer_cut_options;
  outer_cut_options.inside = above->point;
  outer_cut_options.inside_face = above->face;
  std::optional<CutResult> outer;
  for (int attempt = 0; !outer; ++attempt) {
    t0 = Clock::now();
    std::vector<Vec3> outer_points;
    std::vector<Index> outer_faces;
    project(step, outer_points, outer_faces);
    result.times.outer_points += seconds_since(t0);
    t0 = Clock::now();
    try {
      const SurfaceCurve outer_curve =
          join_surface_points(offset_topology, outer_points, outer_faces, outer_curve_options);
      outer = cut_region(offset_topology, outer_curve, outer_cut_options);
      result.outer_curve = outer_curve.polyline;
    } catch (const CurveCrossesItself& e) {
      if (!auto_step)
        throw CurveCrossesItself(std::string(e.what()) + " (try a larger template.sampling_step than " +
                                 std::to_string(step) + ")");
      if (attempt >= 3 || 2 * step > static_cast<int>(m / 3)) throw;
      step *= 2;
    }
    result.times.outer_segmentation += seconds_since(t0);
  }
  result.sampling_step = step;
  result.outer_rim_points = outer->rim.size();
  TriangleMesh contoured_outer; // kept to fall back on if the simplified shell fails its check
  std::vector<Index> contoured_rim;
  // The contour has a few small, often sliver, triangles per grid cell: simplify the outer surface
  // to about the cell size, within a tenth of a cell, keeping its rim exactly (the wall joins it).
  if (options.simplify_outer) {
    t0 = Clock::now();
    DecimateOptions d;
    d.target_edge_length = 2.0 * offset.cell_size;
    d.max_error = 0.1 * offset.cell_size;
    d.keep_border = true;
    // The rim and its first ring stay as contoured, so the triangles the wall meets keep their shape.
    d.frozen.assign(outer->region.vertex_count(), 0);
    for (Index v : outer->rim) d.frozen[v] = 1;
    for (const Triangle& t : outer->region.triangles)
      if (d.frozen[t[0]] == 1 || d.frozen[t[1]] == 1 || d.frozen[t[2]] == 1)
        for (Index v : t) d.frozen[v] = d.frozen[v] ? d.frozen[v] : 2;
    DecimateResult simpler = decimate(outer->region, d);
    std::unordered_map<Index, Index> new_index;
    for (Index v = 0; v < simpler.vertex_source.size(); ++v)
      if (simpler.vertex_source[v] != kInvalidIndex) new_index.emplace(simpler.vertex_source[v], v);
    contoured_outer = outer->region;
    contoured_rim = outer->rim;
    for (Index& v : outer->rim) v = new_index.at(v);
    outer->region = std::move(simpler.mesh);
    result.times.outer_segmentation += seconds_since(t0);
  }

  // 5. Connection: the ruled wall, and the shell.
  t0 = Clock::now();
  std::vector<Vec3> p_loop, q_loop;
  for (Index v : inner.rim) p_loop.push_back(inner.region.positions[v]);
  for (Index v : outer->rim) q_loop.push_back(outer->region.positions[v]);
  // The wall uses loop positions 0..m-1 / 0..n-1, mapped to shell vertices when assembling.
  const RuledResult wall = ruled_surface(p_loop, q_loop, 0, static_cast<Index>(m));
  result.wall_triangles = wall.triangles.size();
  auto assemble = [&](const TriangleMesh& outer_region, const std::vector<Index>& outer_rim) {
    const Index n_inner = inner.region.vertex_count();
    TriangleMesh shell;
    shell.positions = inner.region.positions;
    shell.positions.insert(shell.positions.end(), outer_region.positions.begin(), outer_region.positions.end());
    for (const Triangle& t : inner.region.triangles) shell.triangles.push_back({t[0], t[2], t[1]});
    for (const Triangle& t : outer_region.triangles)
      shell.triangles.push_back({t[0] + n_inner, t[1] + n_inner, t[2] + n_inner});
    for (const Triangle& t : wall.triangles) {
      Triangle s{};
      for (int k = 0; k < 3; ++k) s[k] = t[k] < m ? inner.rim[t[k]] : outer_rim[t[k] - m] + n_inner;
      shell.triangles.push_back(s);
    }
    // STL stores float32: round now, so that the shell checked is the one a file will hold.
    for (Vec3& p : shell.positions) p = p.cast<float>().cast<double>();
    return shell;
  };
  result.shell = assemble(outer->region, outer->rim);
  result.times.connection = seconds_since(t0);
  result.times.total = result.times.inner_segmentation + result.times.offset + result.times.outer_points +
                       result.times.outer_segmentation + result.times.connection;

  if (options.check) {
    t0 = Clock::now();
    result.solid = check_solid(result.shell);
    if (!result.solid.valid() && !contoured_rim.empty()) {
      // The simplification is checked, not trusted: fall back to the outer surface as contoured.
      result.shell = assemble(contoured_outer, contoured_rim);
      outer->region = std::move(contoured_outer);
      result.solid = check_solid(result.shell);
    }
    if (!result.solid.valid()) throw GeometryError("the template shell failed its check: " + result.solid.summary());
  }
  if (options.check) result.times.validation = seconds_since(t0);
  result.body_inner_faces = inner.region.face_count();
  if (!tubes.empty() || !options.slots.empty() || !options.labels.empty()) {
    GuideOptions guide_options;
    guide_options.chordal_tolerance = options.tube_tolerance;
    guide_options.clearance = options.clearance;
    guide_options.thickness = options.thickness;
    guide_options.check_blade_paths = options.check;
    GuideResult guide = build_guide(result.shell, result.body_inner_faces, bone,
                                    GuideParts{tubes, options.slots, options.labels}, guide_options);
    result.times.boolean = guide.seconds;
    result.tubes = std::move(guide.tubes);
    result.slots = std::move(guide.slots);
    result.labels = std::move(guide.labels);
    result.blade_paths = std::move(guide.blade_paths);
    result.perturbed_operations = guide.perturbed_operations;
    result.max_perturbation = guide.max_perturbation;
    result.curve_tolerance = guide.curve_tolerance;
    result.fragments_dropped = guide.fragments_dropped;
    result.from_tube = std::move(guide.from_tube);
    result.columns = std::move(guide.columns);
    result.bores = std::move(guide.bores);
    result.body = std::move(result.shell);
    result.shell = std::move(guide.mesh);
    if (options.check) {
      t0 = Clock::now();
      result.solid = check_solid(result.shell);
      if (!result.solid.valid())
        throw GeometryError("the guide with its tubes failed its check: " + result.solid.summary());
      result.times.validation += seconds_since(t0) + guide.blade_path_seconds;
    }
  } else {
    result.body = result.shell;
    result.from_tube.assign(result.shell.face_count(), 0);
  }
  result.inner = std::move(inner.region);
  result.outer = std::move(outer->region);
  if (options.analyse_insertion && options.check) {
    t0 = Clock::now();
    InsertionReport& ins = result.insertion;
    if (!sweep) sweep.emplace(*bone_tree);
    const RemovalReport removal = (*sweep)(result.shell, ins.direction, options.removal_distance);
    ins.removal_checked = true;
    ins.removable = removal.removable;
    ins.removal_distance = removal.distance;
    ins.blocking = removal.blocking;
    ins.blocked_faces = removal.blocked_faces;
    ins.inner_area_mm2 = surface_area(result.inner);
    ins.contact_area_mm2 =
        contact_area(result.inner, ins.filled, *bone_tree, options.clearance + 0.25 * result.resolution);
    result.times.removal = seconds_since(t0);
    result.times.validation += result.times.removal;
    t0 = Clock::now();
    // Contacts of the inner surface (block-out fills left out: they bridge what the guide cannot reach).
    const AabbTree covered(ins.region.empty() ? result.inner : ins.region);
    result.stability =
        guide_stability(result.inner, *bone_tree, ins.direction, options.clearance + 0.25 * result.resolution,
                        result.outer.positions, result.curve, covered, 0.05, ins.filled);
    result.times.stability = seconds_since(t0);
    result.times.validation += result.times.stability;
  }
  if (options.check && options.measure_fit) {
    t0 = Clock::now();
    result.fit.inner_to_bone = distances_to_surface(result.inner.positions, bone_region);
    result.fit.outer_to_inner = distances_to_surface(result.outer.positions, result.inner);
    DistanceStats rim;
    rim.min = std::numeric_limits<double>::infinity();
    double sum = 0.0;
    const auto& poly = curve.polyline;
    for (const Vec3& p : p_loop) {
      // The curve lies on the bone, so the expected distance is the clearance.
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t i = 0; i < poly.size(); ++i)
        best = std::min(best, point_segment_distance(p, poly[i], poly[(i + 1) % poly.size()]));
      rim.min = std::min(rim.min, best);
      rim.max = std::max(rim.max, best);
      sum += best;
    }
    rim.count = p_loop.size();
    rim.mean = rim.count ? sum / static_cast<double>(rim.count) : 0.0;
    result.fit.rim_to_curve = rim;
    result.times.validation += seconds_since(t0);
  }
  return result;
}

} // namespace st
