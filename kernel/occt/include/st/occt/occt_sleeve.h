#pragma once
// Drilling-tube guide sleeves as OpenCASCADE solids (optional target st_occt, ST_HAVE_OCCT=1).
//
// The same sleeve as sleeve.h describes, modelled exactly (B-rep) instead of as a polygon prism: the
// workbench shows it in FreeCAD from the BREP text of shape_to_brep (Part.Shape.importBrepFromString),
// so FreeCAD and the kernel draw one and the same sleeve. tessellate_shape turns any closed B-rep into
// the kernel's TriangleMesh, for the mesh algorithms.

#include "st/io/case_file.h"
#include "st/core/mesh.h"
#include "st/guide/sleeve.h"

#include <TopoDS_Shape.hxx>

#include <string>

namespace st {

/// The solid cylinder `c` (TopoDS_Solid). Its seam lies at angle 0 of orthonormal_frame(c.axis), the
/// same place as the first vertex column of cylinder_mesh(c). Throws InvalidInput for a non-finite
/// base or axis, a zero axis, or a radius or height that is not finite and > 0.
TopoDS_Shape make_cylinder_shape(const Cylinder& c);

/// The hollow sleeve of `tube` (TopoDS_Solid, never a compound): inner_radius <= r <= outer_radius,
/// offset <= z <= offset + length, z along tube_axis(tube) from tube.entry. Made by revolving the
/// rectangle of the wall's cross-section once around the axis; the seam lies at angle 0 of
/// orthonormal_frame(tube_axis(tube)). Four faces: outer and inner cylinder, two annular caps.
/// Throws InvalidInput (via check_tube) naming the tube and the key for invalid numbers.
TopoDS_Shape make_sleeve_shape(const TubeSpec& tube);

/// Closed, outward-oriented, edge-manifold triangle mesh of the closed solid(s) in `shape`, from
/// OpenCASCADE's BRepMesh_IncrementalMesh with an absolute `linear_deflection` (mm, the largest
/// distance of a triangle from the surface) and `angular_deflection_rad` (largest angle between
/// neighbouring triangles along a curved direction).
///
/// Every vertex lies on the exact surface (up to floating-point rounding). Faces share their edges'
/// discretisation, so the nodes of two faces along an edge are bit-identical and are welded exactly;
/// triangles that collapse in the weld (at a degenerate edge such as a cone's apex) are dropped.
/// The caller's shape is left untouched: a copy is meshed, so the result depends only on the
/// arguments and not on a triangulation left on the shape by an earlier call.
///
/// Throws InvalidInput for a null shape or a deflection that is not finite and > 0; GeometryError if
/// OpenCASCADE fails, a face has no triangulation, or the welded mesh is not closed and consistently
/// oriented with a positive volume (e.g. the shape is an open shell or a single face).
TriangleMesh tessellate_shape(const TopoDS_Shape& shape, double linear_deflection, double angular_deflection_rad = 0.5);

/// The shape as OpenCASCADE BREP text (BRepTools::Write), without triangulation, in format version 2
/// so that OpenCASCADE releases before 7.6 (other FreeCAD builds) read it too. Read it back with
/// BRepTools::Read, or in FreeCAD with `s = Part.Shape(); s.importBrepFromString(text)`.
/// Throws InvalidInput for a null shape.
std::string shape_to_brep(const TopoDS_Shape& shape);

} // namespace st
