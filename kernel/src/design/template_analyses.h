#pragma once
// The analyses of a candidate shell and guide that do not change them (private to design_template):
// the fit, the stability, and the removal check with the contact area, each on a thread beside the
// design's own work.

#include "detail/parallel.h"
#include "st/core/aabb_tree.h"
#include "st/core/topology.h"
#include "st/design/template_design.h"
#include "st/validate/removal.h"
#include "st/validate/stability.h"

#include <exception>
#include <optional>
#include <vector>

namespace st::template_detail {

// The analyses of a candidate guide that do not change it: the fit (the inner surface to the bone
// region it was cut from, the outer surface to the inner, the rim to the curve drawn on the bone), the
// stability, and how it comes off the bone along the insertion direction with its contact area. The
// fit and the stability read only the shell's surfaces: they start as soon as the shell is built and
// run beside the parts' Boolean (which runs on one thread) and the guide's check. The removal check
// reads the finished guide: it starts when the guide is built and runs beside its check.
struct Analyses {
  std::optional<TemplateFit> fit;
  std::optional<StabilityResult> stability;
  std::optional<RemovalReport> removal;
  double inner_area_mm2 = 0.0, contact_area_mm2 = 0.0;
  double stability_seconds = 0.0, removal_seconds = 0.0;
};

// What the shell's analyses read that does not depend on the shell, made beside it when the insertion
// direction is known that early (without block-out): the stability's contacts and report, the tree
// of the fit (over the inner surface) and that of the stability's extension (over the covered bone).
// `made` is joined before any of it is read; when its making failed, the analyses make it themselves.
struct PreparedAnalyses {
  std::optional<StabilityResult> stability;
  std::optional<AabbTree> inner_tree, covered_tree;
  double resolution = 0.0; // the one the contacts were found at
  double stability_seconds = 0.0;
  std::exception_ptr failure;
  detail::Background* made = nullptr;
};

struct AnalysisInputs {
  const TriangleMesh& inner;       // the shell's inner surface (the region at the clearance)
  const std::vector<Index>& rim;   // the inner surface's border
  const std::vector<Vec3>& outer;  // the outer surface's points
  const TriangleMesh& bone_region; // the region as cut from the bone
  const std::vector<Vec3>& curve;  // the curve drawn on the bone
  const AabbTree* bone_tree;       // with the insertion analysis: for the stability and the removal
  const MeshTopology& bone_topology;
  const SweepTest* sweep; // the bone prepared for sweeps, when block-out made it
  const InsertionReport& insertion;
  double resolution;
  PreparedAnalyses* prepared; // made beside the shell, or null
};

/// How far from the bone the inner surface counts as in contact: the clearance and a quarter cell.
double contact_reach(const TemplateOptions& options, double resolution);

/// The fit (on a thread of its own) and the stability (on the caller's thread) of a candidate shell,
/// from what was prepared beside the shell when there is that.
void analyse_shell(const AnalysisInputs& in, const TemplateOptions& options, Analyses& out);

/// How the candidate guide (or shell) comes off the bone, and its contact area.
void analyse_removal(const AnalysisInputs& in, const TriangleMesh& guide, const AabbTree& guide_tree,
                     const TemplateOptions& options, Analyses& out);

} // namespace st::template_detail
