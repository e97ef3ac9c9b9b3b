// The OpenCASCADE sleeves (kernel/occt, st_occt). This file is globbed into the module whether or not
// the optional target is built, so without ST_HAVE_OCCT it compiles to nothing; module.cpp calls
// bind_occt only when ST_HAVE_OCCT is defined and always sets stkernel.has_occt.

#ifdef ST_HAVE_OCCT

#include "convert.h"

#include "st/occt/occt_sleeve.h"
#include "st/guide/sleeve.h"

namespace py = pybind11;
using namespace st;
using namespace st::py_convert;

namespace {

/// A point or vector given as any array-like of three numbers.
Vec3 to_vec3(const Points& a, const std::string& what) {
  if (a.size() != 3 || a.ndim() > 2) throw InvalidInput(what + ": expected three coordinates");
  const double* d = a.data();
  return {d[0], d[1], d[2]};
}

TubeSpec to_tube(const Points& entry, const Points& direction, double inner_radius, double outer_radius, double length,
                 double offset, const std::string& name) {
  TubeSpec t;
  t.name = name;
  t.entry = to_vec3(entry, "tube '" + name + "': entry");
  t.direction = to_vec3(direction, "tube '" + name + "': direction");
  t.inner_radius = inner_radius;
  t.outer_radius = outer_radius;
  t.length = length;
  t.offset = offset;
  return t;
}

} // namespace

void bind_occt(py::module_& m) {
  m.def(
      "sleeve_brep",
      [](const Points& entry, const Points& direction, double inner_radius, double outer_radius, double length,
         double offset, const std::string& name) {
        const TubeSpec tube = to_tube(entry, direction, inner_radius, outer_radius, length, offset, name);
        std::string text;
        {
          py::gil_scoped_release release;
          text = shape_to_brep(make_sleeve_shape(tube));
        }
        return text;
      },
      py::arg("entry"), py::arg("direction"), py::arg("inner_radius"), py::arg("outer_radius"), py::arg("length"),
      py::arg("offset"), py::arg("name") = "tube",
      "The guide sleeve of a drilling tube as OpenCASCADE BREP text (one solid): inner_radius <= r <= "
      "outer_radius, offset <= z <= offset + length, z measured from `entry` against the drilling "
      "`direction`. In FreeCAD: s = Part.Shape(); s.importBrepFromString(text). Raises ValueError naming "
      "the key for invalid numbers.");

  m.def(
      "tessellate_sleeve",
      [](const Points& entry, const Points& direction, double inner_radius, double outer_radius, double length,
         double offset, double linear_deflection, double angular_deflection) {
        const TubeSpec tube = to_tube(entry, direction, inner_radius, outer_radius, length, offset, "tube");
        TriangleMesh mesh;
        {
          py::gil_scoped_release release;
          mesh = tessellate_shape(make_sleeve_shape(tube), linear_deflection, angular_deflection);
        }
        return from_mesh(mesh);
      },
      py::arg("entry"), py::arg("direction"), py::arg("inner_radius"), py::arg("outer_radius"), py::arg("length"),
      py::arg("offset"), py::arg("linear_deflection") = 0.01, py::arg("angular_deflection") = 0.5,
      "The guide sleeve (see sleeve_brep) meshed by OpenCASCADE: (vertices (n,3) float64, triangles (m,3) "
      "int32), closed and outward oriented, every vertex on the exact surface, no triangle farther than "
      "linear_deflection (mm) from it. Raises ValueError for invalid numbers or deflections.");
}

#endif // ST_HAVE_OCCT
