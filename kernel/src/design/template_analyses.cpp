#include "design/template_analyses.h"

#include "detail/timing.h"

#include <algorithm>

namespace st::template_detail {

using detail::Clock;
using detail::seconds_since;

namespace {

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

TemplateFit measure_fit(const AnalysisInputs& in, const AabbTree* inner_tree) {
  TemplateFit fit;
  // The inner surface's vertices were moved from the region's (numbered alike where block-out and
  // skirt left them): each one's source bounds its search, and at zero clearance is its closest point.
  std::vector<Index> source(in.inner.vertex_count(), kInvalidIndex);
  for (Index v = 0; v < std::min(in.inner.vertex_count(), in.bone_region.vertex_count()); ++v) source[v] = v;
  fit.inner_to_bone = distances_to_surface(in.inner.positions, in.bone_region, source);
  fit.outer_to_inner = distances_to_surface(in.outer, in.inner, {}, inner_tree);
  // The curve lies on the bone, so the expected distance is the clearance.
  std::vector<Vec3> rim_points;
  for (const Index v : in.rim) rim_points.push_back(in.inner.positions[v]); // the inner region, moved there
  fit.rim_to_curve = distances_to_polyline(rim_points, in.curve);
  return fit;
}

} // namespace

double contact_reach(const TemplateOptions& options, double resolution) {
  return options.clearance + 0.25 * resolution;
}

void analyse_shell(const AnalysisInputs& in, const TemplateOptions& options, Analyses& out) {
  const InsertionReport& ins = in.insertion;
  const bool stability = in.bone_tree != nullptr;
  PreparedAnalyses* prepared = in.prepared;
  if (prepared) {
    prepared->made->join();
    // Made for another cell size than the shell's (none so far), or failed: made here instead.
    if (prepared->failure || prepared->resolution != in.resolution) prepared = nullptr;
  }
  const AabbTree* fit_tree = prepared && prepared->inner_tree ? &*prepared->inner_tree : nullptr;
  std::optional<detail::Background> fit;
  if (options.measure_fit) fit.emplace([&] { out.fit = measure_fit(in, fit_tree); });
  if (stability) {
    const auto t0 = Clock::now();
    // Contacts of the inner surface (block-out fills left out: they bridge what the guide cannot reach).
    const double reach = contact_reach(options, in.resolution);
    std::optional<AabbTree> region_tree;
    const AabbTree& covered = prepared && prepared->covered_tree
                                  ? *prepared->covered_tree
                                  : region_tree.emplace(ins.region.empty() ? in.inner : ins.region);
    if (prepared && prepared->stability) {
      out.stability = *prepared->stability;
      finish_stability(*out.stability, *in.bone_tree, in.outer, in.curve, covered, 0.05, &in.bone_topology);
      out.stability_seconds = prepared->stability_seconds + seconds_since(t0);
    } else {
      out.stability = guide_stability(in.inner, *in.bone_tree, ins.direction, reach, in.outer, in.curve, covered, 0.05,
                                      ins.filled, false, &in.bone_topology);
      out.stability_seconds = seconds_since(t0);
    }
  }
  if (fit) fit->join();
}

void analyse_removal(const AnalysisInputs& in, const TriangleMesh& guide, const AabbTree& guide_tree,
                     const TemplateOptions& options, Analyses& out) {
  const auto t0 = Clock::now();
  const InsertionReport& ins = in.insertion;
  std::optional<SweepTest> own;
  const SweepTest& sweep = in.sweep ? *in.sweep : own.emplace(*in.bone_tree, &in.bone_topology);
  out.removal = sweep(guide, ins.direction, options.removal_distance, SweepStart::shrunk, &guide_tree);
  out.inner_area_mm2 = surface_area(in.inner);
  out.contact_area_mm2 = contact_area(in.inner, ins.filled, *in.bone_tree, contact_reach(options, in.resolution));
  out.removal_seconds = seconds_since(t0);
}

} // namespace st::template_detail
