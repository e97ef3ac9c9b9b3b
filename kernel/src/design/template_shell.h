#pragma once
// Steps 2-5 of design_template (private to it): the offset of the inner surface, the points and the
// cut of the outer surface, its optional simplification, and the ruled wall joining the two rims.

#include "st/design/cut.h"
#include "st/design/template_design.h"

#include <optional>

namespace st::template_detail {

/// A closed shell: the inner surface reversed, the outer surface and the wall, float32-rounded.
struct Shell {
  TriangleMesh mesh;
  TriangleMesh outer; ///< the outer surface as it is in `mesh`
};

struct ShellBuild {
  Shell shell;
  /// With options.simplify_outer: the shell with the outer surface as contoured, to fall back on
  /// when the simplified one fails its check.
  std::optional<Shell> contoured;
};

/// The shell over `inner` (its region and rim, at the clearance). `tetrahedra`: contour the offset by
/// marching tetrahedra (certified free of self-intersections) instead of cubes. Adds its step times
/// and fills the counts of `result` (resolution, field voxels, offset triangles, sampling step, rim
/// points, wall triangles, outer curve).
ShellBuild build_shell(const CutResult& inner, const TemplateOptions& options, bool tetrahedra, TemplateResult& result);

/// The offset's cell size build_shell uses (TemplateResult::resolution): options.resolution, or T / 8
/// without one (independent of how finely the bone is triangulated, so a refined scan costs no more
/// there than the coarse one).
double shell_resolution(const TemplateOptions& options);

} // namespace st::template_detail
