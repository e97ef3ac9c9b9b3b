#include "convert.h"

#include "st/design/cut.h"
#include "st/design/offset.h"
#include "st/design/ruled_surface.h"
#include "st/design/surface_curve.h"
#include "st/guide/guide.h"
#include "st/guide/sleeve.h"
#include "st/design/template_design.h"
#include "st/core/topology.h"

#include <cstdio>

namespace py = pybind11;
using namespace st;
using namespace st::py_convert;

namespace {} // namespace

void bind_template(py::module_& m) {
  m.def(
      "trace_surface_curve",
      [](const Points& v, const Faces& f, const Points& control_points, double max_snap_distance,
         bool check_self_crossing) {
        const TriangleMesh mesh = to_mesh(v, f, "mesh");
        const auto pts = to_points(control_points, "control_points");
        SurfaceCurve c;
        {
          py::gil_scoped_release release;
          const MeshTopology topology(mesh);
          CurveOptions o;
          o.max_snap_distance = max_snap_distance;
          o.check_self_crossing = check_self_crossing;
          c = trace_surface_curve(topology, pts, o);
        }
        return from_points(c.polyline);
      },
      py::arg("vertices"), py::arg("triangles"), py::arg("control_points"),
      py::arg("max_snap_distance") = tol::kMaxSnapDistance_mm, py::arg("check_self_crossing") = true,
      "The closed curve on the surface through the control points, as an (n,3) polyline.");

  m.def(
      "cut_region",
      [](const Points& v, const Faces& f, const Points& control_points, const py::object& inside,
         double max_snap_distance) {
        const TriangleMesh mesh = to_mesh(v, f, "mesh");
        const auto pts = to_points(control_points, "control_points");
        CutResult r;
        {
          CutOptions co;
          co.inside = to_optional_point(inside, "inside");
          py::gil_scoped_release release;
          const MeshTopology topology(mesh);
          CurveOptions o;
          o.max_snap_distance = max_snap_distance;
          o.also_index = co.inside;
          const SurfaceCurve c = trace_surface_curve(topology, pts, o);
          r = cut_region(topology, c, co);
        }
        py::array_t<std::int32_t> rim(static_cast<py::ssize_t>(r.rim.size()));
        for (std::size_t i = 0; i < r.rim.size(); ++i) rim.mutable_data()[i] = static_cast<std::int32_t>(r.rim[i]);
        return py::make_tuple(from_points(r.region.positions), from_triangles(r.region.triangles), rim);
      },
      py::arg("vertices"), py::arg("triangles"), py::arg("control_points"), py::arg("inside") = py::none(),
      py::arg("max_snap_distance") = tol::kMaxSnapDistance_mm,
      "Cuts the region enclosed by the surface curve through the control points, through the triangles. "
      "Returns (vertices, triangles, rim) with rim the border loop's vertex indices.");

  m.def(
      "offset_surface",
      [](const Points& v, const Faces& f, double distance, double cell_size, bool front_only) {
        const TriangleMesh mesh = to_mesh(v, f, "surface");
        OffsetOptions o;
        o.distance = distance;
        o.cell_size = cell_size;
        o.front_only = front_only;
        OffsetResult r;
        {
          py::gil_scoped_release release;
          r = offset_surface(mesh, o);
        }
        return from_mesh(r.surface);
      },
      py::arg("vertices"), py::arg("triangles"), py::arg("distance"), py::arg("cell_size") = 0.0,
      py::arg("front_only") = false,
      "The iso-surface at `distance` of the surface's unsigned distance field (narrow band, marching tetrahedra).");

  m.def(
      "ruled_surface",
      [](const Points& p, const Points& q) {
        const auto pp = to_points(p, "p");
        const auto qq = to_points(q, "q");
        RuledResult r;
        {
          py::gil_scoped_release release;
          r = ruled_surface(pp, qq, 0, static_cast<Index>(pp.size()));
        }
        return from_triangles(r.triangles);
      },
      py::arg("p"), py::arg("q"),
      "Triangles (indices: p then q) of the least-span ruled strip joining closed loops p and q.");

  m.def(
      "design_template",
      [](const Points& v, const Faces& f, const Points& boundary_points, double thickness, double clearance,
         double resolution, int sampling_step, const py::object& inside, double max_snap_distance, bool check,
         bool simplify_outer, const py::object& tubes, double tube_tolerance, bool fit, const py::object& insertion,
         const py::object& block_out, const py::object& slots, const py::object& labels) {
        const TriangleMesh bone = to_mesh(v, f, "bone");
        TemplateOptions o;
        o.boundary_points = to_points(boundary_points, "boundary_points");
        o.inside = to_optional_point(inside, "inside");
        o.thickness = thickness;
        o.clearance = clearance;
        o.resolution = resolution;
        o.sampling_step = sampling_step;
        o.max_snap_distance = max_snap_distance;
        o.check = check;
        o.measure_fit = fit;
        o.simplify_outer = simplify_outer;
        o.tubes = to_tubes(tubes);
        o.slots = to_slots(slots);
        o.labels = to_labels(labels, true);
        o.tube_tolerance = tube_tolerance;
        o.analyse_insertion = !insertion.is_none();
        o.insertion = to_insertion(insertion).second;
        o.block_out = block_out.is_none() ? o.analyse_insertion : block_out.cast<bool>();
        TemplateResult r;
        {
          py::gil_scoped_release release;
          r = design_template(bone, o);
        }
        py::dict d = from_json(to_json(r, o)); // counts, times, tubes, boolean, solid, fit
        d["shell"] = from_mesh(r.shell);
        d["body"] = from_mesh(r.body);
        d["inner_faces"] = r.body_inner_faces;
        d["from_tube"] = py::array_t<std::uint8_t>(static_cast<py::ssize_t>(r.from_tube.size()), r.from_tube.data());
        d["inner"] = from_mesh(r.inner);
        d["outer"] = from_mesh(r.outer);
        d["curve"] = from_points(r.curve);
        d["outer_curve"] = from_points(r.outer_curve);
        if (o.check) d["solid"] = solid_dict(r.solid);
        if (const InsertionReport& ins = r.insertion; ins.analysed) {
          py::dict i = d["insertion"];
          i["hidden"] = py::array_t<float>(static_cast<py::ssize_t>(ins.hidden.size()), ins.hidden.data());
          i["region"] = from_mesh(ins.region);
          i["filled"] = py::array_t<std::uint8_t>(static_cast<py::ssize_t>(ins.filled.size()), ins.filled.data());
          i["blocked_faces"] =
              py::array_t<std::uint8_t>(static_cast<py::ssize_t>(ins.blocked_faces.size()), ins.blocked_faces.data());
        }
        if (r.stability.analysed) d["stability"] = stability_dict(r.stability);
        return d;
      },
      py::arg("vertices"), py::arg("triangles"), py::arg("boundary_points"), py::arg("thickness"),
      py::arg("clearance") = 0.0, py::arg("resolution") = 0.0, py::arg("sampling_step") = 0,
      py::arg("inside") = py::none(), py::arg("max_snap_distance") = tol::kMaxSnapDistance_mm, py::arg("check") = true,
      py::arg("simplify_outer") = false, py::arg("tubes") = py::none(), py::arg("tube_tolerance") = 0.01,
      py::arg("fit") = true, py::arg("insertion") = py::none(), py::arg("block_out") = py::none(),
      py::arg("slots") = py::none(), py::arg("labels") = py::none(),
      "Designs the template (closed shell) on a bone mesh, with its drilling tubes (dicts with the case file's "
      "tube keys) merged and bored, its saw slots (dicts with the case file's slot keys: housing merged, "
      "slot cut; 'slots' in the result: placements with 'blade_path_free') and its labels (dicts with the case "
      "file's label keys: text engraved or embossed; 'labels' in the result: where each went, its depth, the wall "
      "left under it, its clearance). Returns a dict with 'shell' (the guide), "
      "'body' (before the tubes; its first "
      "'inner_faces' faces are the inner surface), 'inner', 'outer' (each (vertices, triangles)), 'from_tube' "
      "(per shell face), 'tubes' (placements), 'curve', and the report's 'counts', 'times' (s), 'boolean', 'solid' and "
      "(with fit=True) 'fit' (the keys of the tool's --report, st/io/report.h). insertion='auto' or a direction "
      "adds 'insertion': the report's insertion keys (direction, auto, undercut_area_mm2, blocked_out_volume_mm3, "
      "removable, blocking, contact_area_mm2, ...) and 'stability' (score, free_motions, worst_motion, press_point, "
      "contact_points, contact_normals, ...: st/validate/stability.h), 'region' (the covered bone, (vertices, "
      "triangles)), 'hidden' "
      "(per region face, the fraction the guide cannot reach along the direction), 'filled' (per inner face, 1 for "
      "a block-out fill) and 'blocked_faces' (per shell face, 1 where it meets the bone on the way off). block_out "
      "(default: with an insertion) blocks the undercuts out before the clearance.");

  m.def(
      "add_tubes",
      [](const Points& sv, const Faces& sf, std::size_t inner_faces, const Points& bv, const Faces& bf,
         const py::object& tubes, double chordal_tolerance, double clearance, const py::object& slots,
         const py::object& labels, double thickness) {
        const TriangleMesh shell = to_mesh(sv, sf, "shell");
        const TriangleMesh bone = to_mesh(bv, bf, "bone");
        GuideOptions o;
        o.chordal_tolerance = chordal_tolerance;
        o.clearance = clearance;
        o.thickness = thickness;
        const GuideParts parts{to_tubes(tubes), to_slots(slots), to_labels(labels, true)};
        GuideResult g;
        {
          py::gil_scoped_release release;
          g = build_guide(shell, inner_faces, bone, parts, o); // blade paths checked
        }
        py::dict d = from_json(to_json(g)); // tubes, slots, seconds, perturbed_operations, ...
        d["mesh"] = from_mesh(g.mesh);
        d["from_tube"] = py::array_t<std::uint8_t>(static_cast<py::ssize_t>(g.from_tube.size()), g.from_tube.data());
        return d;
      },
      py::arg("shell_vertices"), py::arg("shell_triangles"), py::arg("inner_faces"), py::arg("bone_vertices"),
      py::arg("bone_triangles"), py::arg("tubes"), py::arg("chordal_tolerance") = 0.01, py::arg("clearance") = 0.0,
      py::arg("slots") = py::none(), py::arg("labels") = py::none(), py::arg("thickness") = 0.0,
      "Merges drilling tubes (and saw slots: dicts with the case file's slot keys, their blade paths checked; and "
      "labels: dicts with the case file's label keys, engraved leaving at least thickness - depth of wall when "
      "thickness > 0) into a "
      "closed template shell whose first `inner_faces` faces are its inner surface "
      "(design_template's 'body' and 'inner_faces'), cutting their bores. Returns a dict with 'mesh', 'from_tube', "
      "'tubes' (placements), 'seconds'. Raises ValueError for a bad tube, RuntimeError for one that misses the "
      "template or runs into the bone.");

  m.def(
      "pin_direction",
      [](const Points& bv, const Faces& bf, const py::object& entry, double outer_radius, const std::string& name) {
        const TriangleMesh bone = to_mesh(bv, bf, "bone");
        TubeSpec t;
        t.name = name;
        const auto at = to_optional_point(entry, "entry");
        if (!at) throw InvalidInput("entry: must be a point");
        t.entry = *at;
        const AabbTree tree(bone);
        const Vec3 d = pin_direction(t, tree, std::max(3.0, 2.0 * outer_radius));
        return from_points({d}).attr("reshape")(3);
      },
      py::arg("bone_vertices"), py::arg("bone_triangles"), py::arg("entry"), py::arg("outer_radius"),
      py::arg("name") = "pin",
      "The direction into the bone for a pin planned by its entry only (what design_template gives it): against "
      "the mean outward normal of the bone within max(3, 2 x outer_radius) mm of the entry. RuntimeError naming the "
      "pin on an edge (the normals cancel) or away from the bone.");
}
