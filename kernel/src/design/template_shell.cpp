// Steps 2-5 of the template design: offset, outer points, outer cut, simplification, wall.

#include "design/template_shell.h"
#include "detail/cell_set.h"
#include "detail/timing.h"

#include "st/core/float32.h"
#include "st/core/aabb_tree.h"
#include "st/core/topology.h"
#include "st/design/decimate.h"
#include "st/design/offset.h"
#include "st/design/ruled_surface.h"
#include "st/design/surface_curve.h"
#include "detail/format.h"
#include "st/core/errors.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <unordered_map>

namespace st::template_detail {
namespace {

using detail::Clock;
using detail::seconds_since;

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
  detail::CellSet cells(reach);
  for (Index v : rim) cells.mark_around(region.positions[v]);
  cells.mark_around(region.positions[centre]);
  std::vector<Index> faces;
  for (Index f = 0; f < mesh.face_count(); ++f)
    if (cells.contains(mesh.positions[mesh.triangles[f][0]])) faces.push_back(f);
  return faces;
}

} // namespace

double shell_resolution(const TemplateOptions& options) {
  return options.resolution > 0.0 ? options.resolution : options.thickness / 8.0;
}

ShellBuild build_shell(const CutResult& inner, const TemplateOptions& options, bool tetrahedra,
                       TemplateResult& result) {
  // 2. Offset of the inner surface.
  auto t0 = Clock::now();
  const double T = options.thickness;
  OffsetOptions offset_options;
  offset_options.distance = T;
  offset_options.cell_size = shell_resolution(options);
  offset_options.front_only = true;
  offset_options.tetrahedra = tetrahedra;
  offset_options.max_cells = options.max_field_cells;
  const OffsetResult offset = offset_surface(inner.region, offset_options);
  result.resolution = offset.cell_size;
  result.field_voxels = offset.band_voxels;
  result.offset_triangles = offset.surface.face_count();
  result.times.offset += seconds_since(t0);

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
  result.times.outer_points += seconds_since(t0);

  // 4. Outer surface: the offset cut along those points, keeping the side above the inner surface.
  //    Where the border turns tightly, projected samples can zig-zag and the loop cross itself (the
  //    paper's reason for a sampling step); with an automatic step, a coarser one is tried then.
  const MeshTopology offset_topology(offset.surface, MeshTopology::KeepOpposites{});
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
  // The contour has a few small, often sliver, triangles per grid cell: simplify the outer surface
  // to about the cell size, within a tenth of a cell, keeping its rim exactly (the wall joins it).
  TriangleMesh contoured_outer;     // kept to fall back on if the simplified shell fails its check
  std::vector<Index> contoured_rim; // empty unless simplified
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
    round_to_float32(shell);
    return shell;
  };
  ShellBuild built;
  built.shell = Shell{assemble(outer->region, outer->rim), std::move(outer->region)};
  if (!contoured_rim.empty())
    built.contoured = Shell{assemble(contoured_outer, contoured_rim), std::move(contoured_outer)};
  result.times.connection += seconds_since(t0);
  return built;
}
} // namespace st::template_detail
