#pragma once
// Drilling tubes (guide sleeves) as geometry: the one definition of where a sleeve is, shared by the
// kernel's own tessellation, the OpenCASCADE model (kernel/occt) and the FreeCAD workbench.
//
// A tube of the case file is given by its entry point on the bone, the drilling direction into the
// bone, and (inner_radius, outer_radius, length, offset). Heights z are measured from the entry
// outward along the axis, i.e. against the drilling direction: the sleeve is the hollow cylinder
// inner_radius <= r <= outer_radius, offset <= z <= offset + length.

#include "st/core/aabb_tree.h"
#include "st/core/mesh.h"
#include "st/guide/tube.h"

#include <functional>

namespace st {

/// A solid circular cylinder: base centre, unit axis from the base towards the top, radius, height.
struct Cylinder {
  Vec3 base = Vec3::Zero();
  Vec3 axis = Vec3::UnitZ();
  double radius = 0.0;
  double height = 0.0;

  [[nodiscard]] Vec3 top() const { return base + height * axis; }
};

/// The outward unit axis of a tube (minus its normalised drilling direction).
Vec3 tube_axis(const TubeSpec& tube);

/// The point at height z on the tube's axis (z = 0 is the entry, z > 0 away from the bone).
Vec3 tube_point(const TubeSpec& tube, double z);

/// The sleeve's outer cylinder between heights z0 < z1 (the sleeve itself is z0 = offset,
/// z1 = offset + length).
Cylinder tube_cylinder(const TubeSpec& tube, double radius, double z0, double z1);

/// Two unit vectors (u, v) completing `axis` to a right-handed orthonormal frame (u x v = axis).
/// Deterministic: the same axis always gives the same frame.
void orthonormal_frame(const Vec3& axis, Vec3& u, Vec3& v);

/// Segments around a circle of `radius` so that the chords stay within `chordal_tolerance` of it
/// (at least 8, at most 1024).
int circle_segments(double radius, double chordal_tolerance);

/// Closed, outward-oriented triangle mesh of a cylinder: a regular polygon prism, caps as fans around
/// a centre vertex. Inscribed (corners on the circle: the mesh lies inside the cylinder, within the
/// chordal tolerance), or circumscribed (sides tangent to the circle: the mesh contains the cylinder;
/// what a bore needs so the drill always fits). Throws InvalidInput for a non-positive radius, height
/// or tolerance.
TriangleMesh cylinder_mesh(const Cylinder& cylinder, double chordal_tolerance, bool circumscribed = false);

/// A cylinder standing on a foot: like cylinder_mesh (inscribed), but its bottom follows a height
/// field. `foot(p)` gives, for a point p of the base disk, the height above the base where the solid
/// starts (clamped to [0, height - 1% of height]); the bottom is a polar grid of rings with the side's
/// segments, so a foot that follows the bone keeps the whole solid out of it.
TriangleMesh footed_cylinder_mesh(const Cylinder& cylinder, double chordal_tolerance,
                                  const std::function<double(const Vec3&)>& foot);

/// The direction into the bone for a tube planned by its entry only (a fixation pin): against the
/// area-weighted mean normal of the bone's faces within `radius` of the entry (the bone's outward
/// normals). Throws GeometryError naming the tube when no bone lies within `radius` of the entry or
/// the normals there cancel (less than a fifth of the area faces one way: an edge or a thin crest).
Vec3 pin_direction(const TubeSpec& tube, const AabbTree& bone, double radius);

/// Gives each tube planned by its entry only (auto_direction) its pin_direction within max(3 mm,
/// 2 x outer radius) of its entry; `bone_tree` makes the bone's tree when one is first needed (the
/// callers that have one already hand it back). Throws as pin_direction.
void direct_pins(std::vector<TubeSpec>& tubes, const std::function<const AabbTree&()>& bone_tree);

} // namespace st
