#include "convert.h"

#include "st/boolean.h"

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
}
