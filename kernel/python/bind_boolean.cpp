#include "convert.h"

#include "st/boolean/boolean.h"
#include "st/guide/inspect.h"
#include "st/validate/removal.h"
#include "st/core/aabb_tree.h"

namespace py = pybind11;
using namespace st;
using namespace st::py_convert;

void bind_boolean(py::module_& m) {
  m.def(
      "mesh_boolean",
      [](const Points& va, const Faces& fa, const Points& vb, const Faces& fb, const std::string& op) {
        BooleanOp o;
        if (op == "union") o = BooleanOp::Union;
        else if (op == "difference") o = BooleanOp::Difference;
        else if (op == "intersection") o = BooleanOp::Intersection;
        else throw InvalidInput("op: expected 'union', 'difference' or 'intersection', got '" + op + "'");
        const TriangleMesh a = to_mesh(va, fa, "the first operand");
        const TriangleMesh b = to_mesh(vb, fb, "the second operand");
        BooleanResult r;
        {
          py::gil_scoped_release release;
          r = mesh_boolean(a, b, o);
        }
        py::dict d;
        d["mesh"] = from_mesh(r.mesh);
        d["from_b"] = py::array_t<std::uint8_t>(static_cast<py::ssize_t>(r.from_b.size()), r.from_b.data());
        d["curve_segments"] = r.curve_segments;
        d["attempts"] = r.attempts;
        d["perturbation"] = r.perturbation;
        d["seconds"] = r.seconds;
        return d;
      },
      py::arg("vertices_a"), py::arg("triangles_a"), py::arg("vertices_b"), py::arg("triangles_b"),
      py::arg("op") = "union",
      "Boolean operation of two closed, 2-manifold, outward meshes by corefinement ('union', 'difference' = A "
      "minus B, 'intersection'). Returns a dict with 'mesh' (vertices, triangles; float32-exact), 'from_b' "
      "(per face), 'curve_segments', 'attempts' (> 1 when a touching contact needed a tiny displacement "
      "of B, of size 'perturbation' mm) and 'seconds'. Raises ValueError for an open or non-manifold operand.");
  m.def(
      "inspect_guide",
      [](const Points& vg, const Faces& fg, const Points& vb, const Faces& fb, const py::object& tubes,
         double clearance, double tolerance) {
        const TriangleMesh guide = to_mesh(vg, fg, "guide");
        const TriangleMesh bone = to_mesh(vb, fb, "bone");
        const std::vector<TubeSpec> specs = to_tubes(tubes);
        GuideInspection g;
        {
          py::gil_scoped_release release;
          g = inspect_guide(guide, bone, specs, clearance, tolerance);
        }
        py::dict d;
        d["solid"] = solid_dict(g.solid);
        d["vertex_distance"] =
            py::array_t<double>(static_cast<py::ssize_t>(g.vertex_distance.size()), g.vertex_distance.data());
        d["vertices_in_bone"] = g.vertices_in_bone;
        d["deepest_in_bone"] = g.deepest_in_bone;
        d["seated_vertices"] = g.seated_vertices;
        py::list bores;
        for (const BoreCheck& b : g.bores) {
          py::dict bd;
          bd["name"] = b.name;
          bd["margin"] = b.margin;
          bd["open"] = b.open;
          bores.append(bd);
        }
        d["bores"] = bores;
        d["passed"] = g.passed();
        d["summary"] = g.summary();
        return d;
      },
      py::arg("guide_vertices"), py::arg("guide_triangles"), py::arg("bone_vertices"), py::arg("bone_triangles"),
      py::arg("tubes") = py::list(), py::arg("clearance") = 0.0, py::arg("tolerance") = 0.01,
      "Inspects a finished guide on its bone: {solid, vertex_distance (per guide vertex, mm from the bone: the "
      "thickness map), vertices_in_bone, deepest_in_bone, seated_vertices, bores: [{name, margin, open}], passed, "
      "summary}; vertex_distance is negative behind the bone surface.");
  m.def(
      "check_removal",
      [](const Points& vg, const Faces& fg, const Points& vb, const Faces& fb, const py::object& direction,
         double distance) {
        const TriangleMesh guide = to_mesh(vg, fg, "guide");
        const TriangleMesh bone = to_mesh(vb, fb, "bone");
        const std::optional<Vec3> given = to_optional_point(direction, "direction");
        if (!given) throw InvalidInput("direction: expected [x, y, z], not None");
        const Vec3 d = *given;
        RemovalReport r;
        {
          py::gil_scoped_release release;
          r = check_removal(AabbTree(bone), guide, d, distance);
        }
        py::dict out;
        out["removable"] = r.removable;
        out["distance"] = r.distance;
        out["blocking"] = from_points(r.blocking);
        out["blocked_faces"] =
            py::array_t<std::uint8_t>(static_cast<py::ssize_t>(r.blocked_faces.size()), r.blocked_faces.data());
        return out;
      },
      py::arg("guide_vertices"), py::arg("guide_triangles"), py::arg("bone_vertices"), py::arg("bone_triangles"),
      py::arg("direction"), py::arg("distance") = 20.0,
      "The removal check (st/validate/removal.h): moves the guide against `direction` (the insertion direction, "
      "onto the bone) by up to `distance` mm. Returns {removable, distance, blocking ((n, 3) places on the guide "
      "where it meets the bone, 2 mm apart, at most 20), blocked_faces (per guide face, 1 where it meets it)}.");
}
