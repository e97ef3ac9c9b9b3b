#pragma once
// Inspection of a finished guide against its bone and plan, for the workbench's Validate panel: the
// solid check, every vertex's distance from the bone (the thickness map: about `clearance` on the
// inner surface, `clearance + thickness` on the outer), whether the guide seats (nothing inside the
// bone), and whether each bore is open along its axis.

#include "st/guide/tube.h"
#include "st/core/mesh.h"
#include "st/validate/validate.h"

#include <string>
#include <vector>

namespace st {

struct BoreCheck {
  std::string name;
  /// Smallest distance from the guide's surface to the drilling axis, from inside the bone (one
  /// outer radius below the entry) to the sleeve's top, minus the bore radius: >= 0 when the
  /// drill passes.
  double margin = 0.0;
  bool open = false;
};

struct GuideInspection {
  SolidReport solid;
  /// Per guide vertex: signed distance from the bone surface (mm), negative behind it (in the bone).
  std::vector<double> vertex_distance;
  std::size_t vertices_in_bone = 0; ///< vertices behind the bone surface by more than the tolerance
  double deepest_in_bone = 0.0;     ///< mm
  std::size_t seated_vertices = 0;  ///< vertices within the tolerance of `clearance` from the bone
  std::vector<BoreCheck> bores;

  /// Valid solid, nothing in the bone, every bore open.
  [[nodiscard]] bool passed() const;
  [[nodiscard]] std::string summary() const;
};

/// Distance between segments [p0, p1] and [q0, q1].
double segment_segment_distance(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1);

/// Distance between segment [p0, p1] and triangle (a, b, c) (0 when they meet).
double segment_triangle_distance(const Vec3& p0, const Vec3& p1, const Vec3& a, const Vec3& b, const Vec3& c);

/// Inspects `guide` on `bone` with the planned `tubes`; `tolerance` (mm) is what counts as touching.
GuideInspection inspect_guide(const TriangleMesh& guide, const TriangleMesh& bone, const std::vector<TubeSpec>& tubes,
                              double clearance, double tolerance = 0.01);

} // namespace st
