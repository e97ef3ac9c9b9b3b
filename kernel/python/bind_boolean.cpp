#include "convert.h"

#include "st/boolean/boolean.h"
#include "st/guide/blade_path.h"
#include "st/guide/inspect.h"
#include "st/validate/removal.h"
#include "st/validate/stability.h"
#include "st/core/topology.h"
#include "st/io/report.h"
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
      "check_blade_path",
      [](const Points& vg, const Faces& fg, const py::dict& slot, const py::dict& placement, double tolerance) {
        const TriangleMesh guide = to_mesh(vg, fg, "guide");
        SlotSpec s = to_slot(slot, "slot");
        if (placement.contains("direction")) { // the travel as built (a slot planned without one)
          s.direction =
              to_optional_point(py::object(placement["direction"]), "placement.direction").value_or(s.direction);
          s.auto_direction = false;
        }
        if (s.auto_direction) throw InvalidInput("slot '" + s.name + "': no travel planned and none in the placement");
        SlotPlacement p;
        p.name = s.name;
        p.width = placement["width"].cast<double>();
        const py::list cut = placement["cut"], housing = placement["housing"];
        p.cut_bottom = cut[0].cast<double>();
        p.cut_top = cut[1].cast<double>();
        p.housing_top = housing[1].cast<double>();
        BladePathReport r;
        {
          py::gil_scoped_release release;
          r = check_blade_path(guide, s, p, tolerance);
        }
        py::dict d;
        d["name"] = r.name;
        d["free"] = r.free;
        d["blocked_at"] = r.blocked ? py::object(from_points({*r.blocked}).attr("reshape")(3)) : py::object(py::none());
        return d;
      },
      py::arg("guide_vertices"), py::arg("guide_triangles"), py::arg("slot"), py::arg("placement"),
      py::arg("tolerance") = 0.02,
      "Whether a saw blade of the slot's planned thickness (plus its clearance on both sides) swept along the slot "
      "over the planned cut meets no material of the finished guide: exact triangle tests (blade_path.h). `slot`: "
      "the case file's slot keys; `placement`: the slot's entry of add_tubes' or design_template's 'slots' (width, "
      "cut, housing, direction). Returns {name, free, blocked_at (a point of the guide in the way, or None)}.");
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

  m.def(
      "analyse_stability",
      [](const Points& vi, const Faces& fi, const Points& vb, const Faces& fb, const py::object& direction,
         double reach, const py::object& outer_points, bool toward_bone) {
        const TriangleMesh inner = to_mesh(vi, fi, "inner surface");
        const TriangleMesh bone = to_mesh(vb, fb, "bone");
        const std::optional<Vec3> given = to_optional_point(direction, "direction");
        if (!given) throw InvalidInput("direction: expected [x, y, z], not None");
        if (!(reach >= 0.0)) throw InvalidInput("reach: must be >= 0");
        const std::vector<Vec3> outer =
            outer_points.is_none() ? std::vector<Vec3>{} : to_points(outer_points.cast<Points>(), "outer_points");
        StabilityResult r;
        {
          py::gil_scoped_release release;
          std::vector<Vec3> rim; // the inner surface's border vertices
          for (const auto& loop : border_loops(inner, MeshTopology(inner).all_opposites()))
            for (const Index v : loop) rim.push_back(inner.positions[v]);
          const AabbTree bone_tree(bone), covered(inner);
          r = guide_stability(inner, bone_tree, *given, reach, outer, rim, covered, reach + 0.05, {}, toward_bone);
        }
        return stability_dict(r);
      },
      py::arg("inner_vertices"), py::arg("inner_triangles"), py::arg("bone_vertices"), py::arg("bone_triangles"),
      py::arg("direction"), py::arg("reach") = 0.01, py::arg("outer_points") = py::none(),
      py::arg("toward_bone") = false,
      "Will the guide stay put (st/validate/stability.h): contacts of the inner surface within `reach` mm of the "
      "bone, the free motions and score pressed along `direction` (the insertion direction), the press point "
      "among `outer_points` and where to extend the border. toward_bone: the inner triangles face the bone (a "
      "closed guide's own inner facets), not away from it (design_template's 'inner'). Returns the report's stability "
      "keys (score, "
      "contacts, free_motions, worst_motion, press_point, press_score, extend, ...) and contact_points, "
      "contact_normals ((n, 3) arrays).");
}
