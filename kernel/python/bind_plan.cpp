#include "convert.h"

#include "st/io/plan.h"

#include <pybind11/stl.h>

namespace py = pybind11;
using namespace st;
using namespace st::py_convert;

namespace {

Space to_space(const std::string& s) {
  if (s == "LPS" || s == "lps") return Space::LPS;
  if (s == "RAS" || s == "ras") return Space::RAS;
  throw InvalidInput("space: must be \"LPS\" or \"RAS\", got \"" + s + "\"");
}

const char* space_name(Space s) { return s == Space::RAS ? "RAS" : "LPS"; }

py::object optional_number(const std::optional<double>& v) {
  return v ? py::object(py::float_(*v)) : py::object(py::none());
}

py::dict axis_dict(const PlanAxis& a) {
  py::dict d;
  d["name"] = a.name;
  d["source"] = a.source;
  d["entry"] = from_points({a.entry}).attr("reshape")(3);
  d["direction"] = from_points({a.direction}).attr("reshape")(3);
  d["depth"] = optional_number(a.depth);
  d["inner_radius"] = optional_number(a.inner_radius);
  d["outer_radius"] = optional_number(a.outer_radius);
  d["length"] = optional_number(a.length);
  d["offset"] = optional_number(a.offset);
  return d;
}

PlanAxis to_axis(const py::dict& d) {
  PlanAxis a;
  const auto optional = [&](const char* key) -> std::optional<double> {
    if (!d.contains(key) || d[key].is_none()) return std::nullopt;
    return d[key].cast<double>();
  };
  a.name = d.contains("name") ? py::str(d["name"]).cast<std::string>() : "axis";
  a.source = d.contains("source") ? py::str(d["source"]).cast<std::string>() : a.name;
  const auto point = [&](const char* key) {
    const auto p = d.contains(key) ? to_optional_point(d[key], a.source + ": " + key) : std::nullopt;
    if (!p) throw InvalidInput(a.source + ": '" + key + "' is required");
    return *p;
  };
  a.entry = point("entry");
  a.direction = point("direction");
  const double n = a.direction.norm();
  if (!(n > 0.0) || !std::isfinite(n)) throw InvalidInput(a.source + ": direction must be a non-zero vector");
  a.direction /= n;
  a.depth = optional("depth");
  a.inner_radius = optional("inner_radius");
  a.outer_radius = optional("outer_radius");
  a.length = optional("length");
  a.offset = optional("offset");
  return a;
}

py::dict preset_dict(const SleevePreset& p) {
  py::dict d;
  d["name"] = p.name;
  d["description"] = p.description;
  d["inner_radius"] = p.inner_radius;
  d["outer_radius"] = p.outer_radius;
  d["length"] = p.length;
  d["offset"] = p.offset;
  d["kind"] = tube_kind_name(p.kind);
  d["counterbore"] =
      p.counterbore
          ? py::object(py::dict(py::arg("radius") = p.counterbore->radius, py::arg("depth") = p.counterbore->depth))
          : py::object(py::none());
  return d;
}

SleevePreset to_preset(const py::dict& d) {
  SleevePreset p;
  p.name = d.contains("name") ? py::str(d["name"]).cast<std::string>() : "";
  if (d.contains("description")) p.description = py::str(d["description"]).cast<std::string>();
  p.inner_radius = d["inner_radius"].cast<double>();
  p.outer_radius = d["outer_radius"].cast<double>();
  p.length = d["length"].cast<double>();
  p.offset = d.contains("offset") ? d["offset"].cast<double>() : 0.0;
  if (d.contains("kind") && !d["kind"].is_none()) {
    const auto kind = tube_kind_named(py::str(d["kind"]).cast<std::string>());
    if (!kind) throw InvalidInput("preset '" + p.name + "': kind must be \"sleeve\" or \"pin\"");
    p.kind = *kind;
  }
  if (d.contains("counterbore") && !d["counterbore"].is_none()) {
    const py::dict cb = d["counterbore"];
    p.counterbore = Counterbore{cb["radius"].cast<double>(), cb["depth"].cast<double>()};
  }
  return p;
}

/// A blade from a dict with blade_presets' keys (name, thickness, clearance optional).
BladePreset to_blade(const py::dict& d) {
  BladePreset b;
  b.name = d.contains("name") ? py::str(d["name"]).cast<std::string>() : "blade";
  b.description = d.contains("description") ? py::str(d["description"]).cast<std::string>() : "";
  b.thickness = d["thickness"].cast<double>();
  b.clearance = d.contains("clearance") ? d["clearance"].cast<double>() : 0.1;
  return b;
}

py::dict blade_dict(const BladePreset& b) {
  py::dict d;
  d["name"] = b.name;
  d["description"] = b.description;
  d["thickness"] = b.thickness;
  d["clearance"] = b.clearance;
  return d;
}

py::dict plane_dict(const PlanPlane& p) {
  const auto value = [](const std::optional<double>& v) {
    return v ? py::object(py::float_(*v)) : py::object(py::none());
  };
  py::dict d;
  d["name"] = p.name;
  d["source"] = p.source;
  d["origin"] = from_points({p.origin}).attr("reshape")(3);
  d["normal"] = from_points({p.normal}).attr("reshape")(3);
  d["direction"] = p.direction ? from_points({*p.direction}).attr("reshape")(3) : py::object(py::none());
  d["blade"] = value(p.blade);
  d["clearance"] = value(p.clearance);
  d["length"] = value(p.length);
  d["height"] = value(p.height);
  d["wall"] = value(p.wall);
  if (p.closed) {
    py::list closed;
    if ((*p.closed)[0]) closed.append("start");
    if ((*p.closed)[1]) closed.append("end");
    d["closed"] = closed;
  } else {
    d["closed"] = py::none();
  }
  return d;
}

} // namespace

void bind_plan(py::module_& m) {
  m.def(
      "read_plan",
      [](const std::string& path, const std::string& space) {
        const Plan plan = read_plan(path, to_space(space));
        py::dict d;
        d["path"] = plan.path;
        d["kind"] = plan.kind;
        d["boundary_points"] =
            plan.boundary_points.empty() ? py::object(py::none()) : py::object(from_points(plan.boundary_points));
        d["inside"] = plan.inside ? py::object(from_points({*plan.inside}).attr("reshape")(3)) : py::object(py::none());
        py::list axes;
        for (const PlanAxis& a : plan.axes) axes.append(axis_dict(a));
        d["axes"] = axes;
        py::list planes;
        for (const PlanPlane& p : plan.planes) planes.append(plane_dict(p));
        d["planes"] = planes;
        d["warnings"] = plan.warnings;
        return d;
      },
      py::arg("path"), py::arg("space") = "LPS",
      "Reads a plan: a case file, a 3D Slicer markups file (.mrk.json) or a CSV of axes or planes, in the frame "
      "`space` of the bone it goes on (\"LPS\" or \"RAS\", see mesh_file_space). Returns {path, kind (\"case\", "
      "\"markups\", \"csv\"), boundary_points (n, 3) or None, "
      "inside, axes: [{name, source, entry, direction, depth, inner_radius, outer_radius, length, offset}], planes: "
      "[{name, source, origin, normal, direction, blade, clearance, length, height, wall, closed}] (None where the "
      "plan gives none), warnings}; raises ValueError naming the file and the entry.");
  m.def(
      "mesh_file_space", [](const std::string& path) { return space_name(mesh_file_space(path)); }, py::arg("path"),
      "\"RAS\" when the mesh file's header says SPACE=RAS, else \"LPS\" (3D Slicer's convention).");
  m.def(
      "sleeve_presets",
      [](const std::optional<std::string>& path) {
        py::list out;
        for (const SleevePreset& p : path ? read_sleeve_presets(*path) : default_sleeve_presets())
          out.append(preset_dict(p));
        return out;
      },
      py::arg("path") = py::none(),
      "The sleeve catalogue (surgical-template-sleeves/1) of the file at `path`, or the one built in: "
      "[{name, description, inner_radius, outer_radius, length, offset}] in mm.");
  m.def(
      "blade_presets",
      [](const std::optional<std::string>& path) {
        py::list out;
        for (const BladePreset& b : path ? read_blade_presets(*path) : default_blade_presets())
          out.append(blade_dict(b));
        return out;
      },
      py::arg("path") = py::none(),
      "The saw blades of a catalogue (its 'blades' section), of the file at `path` or the one built in: "
      "[{name, description, thickness, clearance}] in mm; a slot for one is thickness + 2 x clearance wide.");
  m.def(
      "tube_from_axis",
      [](const py::dict& axis, const std::optional<py::dict>& preset) {
        return tube_dict(tube_from_axis(to_axis(axis), preset ? std::optional(to_preset(*preset)) : std::nullopt));
      },
      py::arg("axis"), py::arg("preset") = py::none(),
      "A tube (case-file keys) from a plan axis, sizes the plan lacks taken from `preset`; ValueError naming the "
      "axis when a size is missing or impossible.");
  m.def(
      "find_blade_preset",
      [](const py::list& blades, const std::string& name) {
        std::vector<BladePreset> catalogue;
        for (const py::handle b : blades) catalogue.push_back(to_blade(py::reinterpret_borrow<py::dict>(b)));
        return blade_dict(find_blade_preset(catalogue, name));
      },
      py::arg("blades"), py::arg("name"),
      "The blade called `name` (exact, then ignoring case) in a list of blade_presets' dicts; ValueError listing "
      "the names when there is none.");
  m.def(
      "find_sleeve_preset",
      [](const py::list& presets, const std::string& name) {
        std::vector<SleevePreset> catalogue;
        for (const py::handle p : presets) catalogue.push_back(to_preset(py::reinterpret_borrow<py::dict>(p)));
        return preset_dict(find_sleeve_preset(catalogue, name));
      },
      py::arg("presets"), py::arg("name"),
      "The preset called `name` (exact, then ignoring case) in a catalogue (sleeve_presets' dicts); ValueError "
      "listing the names when there is none.");
  m.def(
      "apply_plan",
      [](const py::dict& c, const std::string& plan_path, const std::string& space,
         const std::optional<py::dict>& preset, bool add_tubes, const std::optional<py::dict>& blade,
         std::optional<double> slot_length) {
        CaseFile out = to_case(c);
        SlotSizes slot_sizes;
        if (blade) slot_sizes.blade = to_blade(*blade);
        slot_sizes.length = slot_length;
        const std::vector<std::string> warnings = apply_plan(
            out, read_plan(plan_path, to_space(space)), preset ? std::optional(to_preset(*preset)) : std::nullopt,
            add_tubes ? PlanTubes::Add : PlanTubes::Replace, slot_sizes);
        return py::make_tuple(case_dict(out), warnings);
      },
      py::arg("case"), py::arg("plan"), py::arg("space") = "LPS", py::arg("preset") = py::none(),
      py::arg("add_tubes") = false, py::arg("blade") = py::none(), py::arg("slot_length") = py::none(),
      "Puts the plan in the file `plan` (in the frame `space` of the case's bone) into a case (read_case's keys): "
      "its boundary and inside point replace the case's, its axes become tubes (sizes it lacks from `preset`) and "
      "its planes slots (blade and length it lacks from `blade`, a blade_presets dict, and `slot_length`), "
      "replacing the case's or, with add_tubes, added to them. Returns (case, warnings).");
}
