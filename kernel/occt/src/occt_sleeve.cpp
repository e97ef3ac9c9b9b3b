#include "st/occt/occt_sleeve.h"

#include "detail/format.h"
#include "st/core/errors.h"

#include <BRepBuilderAPI_Copy.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakePolygon.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeRevol.hxx>
#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <Poly_Triangulation.hxx>
#include <Standard_Failure.hxx>
#include <TopExp_Explorer.hxx>
#include <TopLoc_Location.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Solid.hxx>
#include <gp_Ax1.hxx>
#include <gp_Ax2.hxx>
#include <gp_Dir.hxx>
#include <gp_Pnt.hxx>
#include <gp_Trsf.hxx>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <locale>
#include <numbers>
#include <sstream>
#include <unordered_map>

namespace st {

namespace {

gp_Pnt to_pnt(const Vec3& p) { return {p.x(), p.y(), p.z()}; }
gp_Dir to_dir(const Vec3& d) { return {d.x(), d.y(), d.z()}; }

std::string point_text(const Vec3& p) {
  std::ostringstream s;
  s.imbue(std::locale::classic());
  s << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return s.str();
}

/// Runs `f`, turning an OpenCASCADE exception (not derived from std::exception, so pybind11 would
/// only report "unknown exception") into a GeometryError that names `what`.
template <class F> auto occt_guard(const std::string& what, F&& f) {
  try {
    return f();
  } catch (const Standard_Failure& e) {
    const char* message = e.GetMessageString();
    throw GeometryError(what + ": OpenCASCADE failed (" + e.DynamicType()->Name() + ")" +
                        (message && *message ? std::string(": ") + message : std::string()));
  }
}

/// The single solid of `shape`: the shape itself, or the only solid of a compound.
TopoDS_Shape single_solid(const TopoDS_Shape& shape, const std::string& what) {
  if (shape.ShapeType() == TopAbs_SOLID) return shape;
  TopoDS_Shape solid;
  int count = 0;
  for (TopExp_Explorer ex(shape, TopAbs_SOLID); ex.More(); ex.Next(), ++count) solid = ex.Current();
  if (count != 1) throw GeometryError(what + ": expected one solid from OpenCASCADE, got " + std::to_string(count));
  return solid;
}

/// Hash key of a node: its exact coordinates. -0.0 and 0.0 are equal nodes, so zeros are made +0.0
/// before the bits are compared.
struct NodeKey {
  std::array<double, 3> xyz;
  bool operator==(const NodeKey& o) const { return xyz == o.xyz; }
};

struct NodeKeyHash {
  std::size_t operator()(const NodeKey& k) const {
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (double c : k.xyz) h = (h ^ std::bit_cast<std::uint64_t>(c)) * 0x100000001b3ull;
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};

/// Throws GeometryError unless every edge of `mesh` is used exactly once in each direction (closed,
/// edge-manifold, consistently oriented) and the enclosed volume is positive (outward).
void require_closed_outward(const TriangleMesh& mesh) {
  auto key = [](Index a, Index b) { return (static_cast<std::uint64_t>(a) << 32) | b; };
  std::unordered_map<std::uint64_t, int> directed;
  directed.reserve(3 * mesh.triangles.size());
  for (const Triangle& t : mesh.triangles)
    for (std::size_t k = 0; k < 3; ++k) ++directed[key(t[k], t[(k + 1) % 3])];
  std::size_t border = 0, repeated = 0;
  std::uint64_t first_bad = 0;
  for (const auto& [k, count] : directed) {
    const auto a = static_cast<Index>(k >> 32), b = static_cast<Index>(k & 0xffffffffu);
    const auto twin = directed.find(key(b, a));
    const bool bad_border = twin == directed.end();
    const bool bad_repeat = count > 1;
    if ((bad_border || bad_repeat) && border + repeated == 0) first_bad = k;
    border += bad_border;
    repeated += bad_repeat;
  }
  if (border + repeated > 0) {
    const Vec3& p = mesh.positions[static_cast<Index>(first_bad >> 32)];
    throw GeometryError(
        "tessellate_shape: the welded mesh is not a closed, oriented surface: " + std::to_string(border) +
        " border edges, " + std::to_string(repeated) + " edges used twice the same way, the first at " + point_text(p) +
        " mm (is the shape a closed solid?)");
  }
  const double volume = signed_volume(mesh);
  if (!(volume > 0.0))
    throw GeometryError("tessellate_shape: the welded mesh encloses a volume of " + detail::number(volume) +
                        " mm^3, not a positive one (is the solid inside out?)");
}

} // namespace

TopoDS_Shape make_cylinder_shape(const Cylinder& c) {
  if (!c.base.allFinite() || !c.axis.allFinite() || !(c.axis.norm() > 1e-12))
    throw InvalidInput("make_cylinder_shape: base and axis must be finite, the axis non-zero");
  if (!std::isfinite(c.radius) || !(c.radius > 0.0) || !std::isfinite(c.height) || !(c.height > 0.0))
    throw InvalidInput("make_cylinder_shape: radius and height must be finite and > 0 (radius " +
                       detail::number(c.radius) + ", height " + detail::number(c.height) + ")");
  const Vec3 axis = c.axis.normalized();
  Vec3 u, v;
  orthonormal_frame(axis, u, v);
  return occt_guard("make_cylinder_shape", [&] {
    // The X direction of the placement is where OpenCASCADE puts the seam (angle 0): the kernel's u.
    BRepPrimAPI_MakeCylinder make(gp_Ax2(to_pnt(c.base), to_dir(axis), to_dir(u)), c.radius, c.height);
    return TopoDS_Shape(make.Solid());
  });
}

TopoDS_Shape make_sleeve_shape(const TubeSpec& tube) {
  check_tube(tube);
  const std::string what = "make_sleeve_shape: tube '" + tube.name + "'";
  const Vec3 axis = tube_axis(tube);
  Vec3 u, v;
  orthonormal_frame(axis, u, v);
  const Vec3 bottom = tube_point(tube, tube.offset);
  const Vec3 top = tube_point(tube, tube.offset + tube.length);
  return occt_guard(what, [&] {
    // The wall's cross-section in the half-plane of angle 0 (spanned by the axis and u), revolved
    // once: a solid with exactly the four faces of the sleeve and its seam at the kernel's angle 0.
    // Cylinder-cut-cylinder would give the same solid wrapped in a compound, through a boolean.
    BRepBuilderAPI_MakePolygon rectangle(to_pnt(bottom + tube.inner_radius * u), to_pnt(bottom + tube.outer_radius * u),
                                         to_pnt(top + tube.outer_radius * u), to_pnt(top + tube.inner_radius * u),
                                         Standard_True);
    if (!rectangle.IsDone()) throw GeometryError(what + ": could not build the cross-section");
    BRepBuilderAPI_MakeFace face(rectangle.Wire(), Standard_True);
    if (!face.IsDone()) throw GeometryError(what + ": could not build the cross-section face");
    BRepPrimAPI_MakeRevol revol(face.Face(), gp_Ax1(to_pnt(bottom), to_dir(axis)), 2.0 * std::numbers::pi,
                                Standard_False);
    revol.Build();
    if (!revol.IsDone()) throw GeometryError(what + ": revolving the cross-section failed");
    return single_solid(revol.Shape(), what);
  });
}

TriangleMesh tessellate_shape(const TopoDS_Shape& shape, double linear_deflection, double angular_deflection_rad) {
  if (shape.IsNull()) throw InvalidInput("tessellate_shape: the shape is null");
  if (!std::isfinite(linear_deflection) || !(linear_deflection > 0.0))
    throw InvalidInput("tessellate_shape: linear_deflection must be finite and > 0 mm, got " +
                       std::to_string(linear_deflection));
  if (!std::isfinite(angular_deflection_rad) || !(angular_deflection_rad > 0.0))
    throw InvalidInput("tessellate_shape: angular_deflection must be finite and > 0 rad, got " +
                       std::to_string(angular_deflection_rad));

  return occt_guard("tessellate_shape", [&] {
    // BRepMesh stores its triangulation on the shape's faces and keeps an existing one that is fine
    // enough; meshing a copy (new faces, shared geometry) makes the result depend on the deflections
    // only and leaves the caller's shape as it was.
    const TopoDS_Shape work = BRepBuilderAPI_Copy(shape, Standard_False, Standard_False).Shape();
    BRepMesh_IncrementalMesh mesher(work, linear_deflection, Standard_False, angular_deflection_rad, Standard_False);
    if (!mesher.IsDone()) throw GeometryError("tessellate_shape: BRepMesh_IncrementalMesh failed");

    TriangleMesh mesh;
    std::unordered_map<NodeKey, Index, NodeKeyHash> welded;
    std::vector<Index> local; // node of the current face -> welded vertex
    int face_number = 0;
    for (TopExp_Explorer ex(work, TopAbs_FACE); ex.More(); ex.Next(), ++face_number) {
      const TopoDS_Face& face = TopoDS::Face(ex.Current());
      TopLoc_Location location;
      const Handle(Poly_Triangulation)& tri = BRep_Tool::Triangulation(face, location);
      if (tri.IsNull())
        throw GeometryError("tessellate_shape: face " + std::to_string(face_number) +
                            " has no triangulation after meshing");
      const gp_Trsf trsf = location.Transformation();
      const bool moved = !location.IsIdentity();
      local.assign(static_cast<std::size_t>(tri->NbNodes()), kInvalidIndex);
      for (int i = 1; i <= tri->NbNodes(); ++i) {
        gp_Pnt p = tri->Node(i);
        if (moved) p.Transform(trsf);
        // Two faces meet along an edge discretised once, so their nodes there are bit-identical.
        const NodeKey key{{p.X() + 0.0, p.Y() + 0.0, p.Z() + 0.0}};
        const auto [it, inserted] = welded.try_emplace(key, static_cast<Index>(mesh.positions.size()));
        if (inserted) mesh.positions.emplace_back(key.xyz[0], key.xyz[1], key.xyz[2]);
        local[static_cast<std::size_t>(i - 1)] = it->second;
      }
      // The triangles run counter-clockwise around the surface normal; a reversed face's outside is
      // the other side.
      const bool reversed = face.Orientation() == TopAbs_REVERSED;
      for (int t = 1; t <= tri->NbTriangles(); ++t) {
        int n1 = 0, n2 = 0, n3 = 0;
        tri->Triangle(t).Get(n1, n2, n3);
        if (reversed) std::swap(n2, n3);
        const Triangle f{local[static_cast<std::size_t>(n1 - 1)], local[static_cast<std::size_t>(n2 - 1)],
                         local[static_cast<std::size_t>(n3 - 1)]};
        // Collapsed by the weld: the nodes of a degenerate edge (a cone's apex) are one point.
        if (f[0] == f[1] || f[1] == f[2] || f[2] == f[0]) continue;
        mesh.triangles.push_back(f);
      }
    }
    if (mesh.triangles.empty()) throw GeometryError("tessellate_shape: the shape has no faces to mesh");
    require_closed_outward(mesh);
    return mesh;
  });
}

std::string shape_to_brep(const TopoDS_Shape& shape) {
  if (shape.IsNull()) throw InvalidInput("shape_to_brep: the shape is null");
  return occt_guard("shape_to_brep", [&] {
    std::ostringstream out;
    // Numbers must read back as numbers whatever the program's global C++ locale (a decimal comma
    // would break the file).
    out.imbue(std::locale::classic());
    // BRepTools::Write(shape, stream) writes TopTools_FormatVersion_CURRENT (version 3 in 7.6, which
    // OpenCASCADE 7.5 and older refuse) with triangles; the exact geometry in version 2 is all the
    // workbench needs and any FreeCAD reads it.
    BRepTools::Write(shape, out, Standard_False, Standard_False, TopTools_FormatVersion_VERSION_2);
    if (!out) throw GeometryError("shape_to_brep: writing the BREP text failed");
    return out.str();
  });
}

} // namespace st
