#include "convert.h"

#include "st/core/aabb_tree.h"
#include "st/io/mesh_io.h"
#include "st/validate/validate.h"

#include <memory>

namespace py = pybind11;
using namespace st;
using namespace st::py_convert;

namespace {

/// A mesh and its AABB tree, built once for many ray queries (the drawing's hidden-line test).
struct RayCaster {
  TriangleMesh mesh;
  std::unique_ptr<AabbTree> tree; // refers to mesh: built after it, never moved
};

} // namespace

void bind_mesh(py::module_& m) {
  m.def(
      "read_mesh",
      [](const std::string& path) {
        TriangleMesh mesh;
        {
          py::gil_scoped_release release;
          mesh = read_mesh(path);
        }
        return from_mesh(mesh);
      },
      py::arg("path"),
      "Reads an STL (binary or ASCII), PLY or OBJ file. Returns (vertices (n,3) float64, triangles (m,3) int32).");
  m.def(
      "write_stl",
      [](const Points& v, const Faces& f, const std::string& path, const std::string& header) {
        const TriangleMesh mesh = to_mesh(v, f, "mesh");
        py::gil_scoped_release release;
        write_stl(mesh, path, header);
      },
      py::arg("vertices"), py::arg("triangles"), py::arg("path"), py::arg("header") = "surgical-template",
      "Writes a binary STL (atomically) with `header` (up to 80 bytes; e.g. \"SPACE=RAS\" for 3D Slicer).");
  m.def(
      "check_solid",
      [](const Points& v, const Faces& f, bool self_intersections) {
        const TriangleMesh mesh = to_mesh(v, f, "mesh");
        SolidOptions o;
        o.check_self_intersections = self_intersections;
        SolidReport r;
        {
          py::gil_scoped_release release;
          r = check_solid(mesh, o);
        }
        return solid_dict(r);
      },
      py::arg("vertices"), py::arg("triangles"), py::arg("self_intersections") = true,
      "Checks a mesh as a solid: closed, 2-manifold, outward oriented, no self-intersection. Returns a dict.");
  m.def(
      "distances_to_surface",
      [](const Points& points, const Points& v, const Faces& f) {
        const auto p = to_points(points, "points");
        const TriangleMesh mesh = to_mesh(v, f, "surface");
        DistanceStats s;
        {
          py::gil_scoped_release release;
          s = distances_to_surface(p, mesh);
        }
        return from_json(to_json(s));
      },
      py::arg("points"), py::arg("vertices"), py::arg("triangles"),
      "Min/max/mean exact distance of points to a triangle surface, mm.");
  py::class_<RayCaster>(m, "RayCaster", "A triangle mesh prepared for ray queries (AABB tree), e.g. hidden-line tests.")
      .def(py::init([](const Points& v, const Faces& f) {
             auto r = std::make_unique<RayCaster>();
             r->mesh = to_mesh(v, f, "mesh");
             r->tree = std::make_unique<AabbTree>(r->mesh);
             return r;
           }),
           py::arg("vertices"), py::arg("triangles"))
      .def(
          "occluded",
          [](const RayCaster& r, const Points& points, const py::object& direction, double tolerance) {
            const std::vector<Vec3> p = to_points(points, "points");
            const std::optional<Vec3> d = to_optional_point(direction, "direction");
            if (!d || !(d->norm() > 0.0)) throw InvalidInput("direction: must be a non-zero vector");
            const Vec3 unit = d->normalized();
            py::array_t<bool> out(static_cast<py::ssize_t>(p.size()));
            bool* o = out.mutable_data();
            {
              py::gil_scoped_release release;
              for (std::size_t i = 0; i < p.size(); ++i) o[i] = r.tree->first_hit(p[i], unit, tolerance).has_value();
            }
            return out;
          },
          py::arg("points"), py::arg("direction"), py::arg("tolerance") = 0.0,
          "Per point ((n, 3) array): does the mesh lie in front of it, i.e. does the ray from the point along "
          "`direction` (towards the viewer) meet a facet farther than `tolerance` (mm)?");
}
