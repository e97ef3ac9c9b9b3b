#pragma once
// numpy <-> kernel conversions shared by the bind_*.cpp files. Arrays are copied by value:
// positions (n, 3) float64, triangles (m, 3) int32/uint32/int64 (checked against n).

#include "st/io/case_file.h"
#include "st/io/report.h"
#include "st/core/errors.h"
#include "st/core/mesh.h"
#include "st/validate/validate.h"
#ifdef ST_HAVE_OCCT
#include "st/occt/occt_text.h"
#endif

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <optional>
#include <tuple>
#include <string>
#include <vector>

namespace st::py_convert {

namespace py = pybind11;
using Points = py::array_t<double, py::array::c_style | py::array::forcecast>;
using Faces = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

inline std::vector<Vec3> to_points(const Points& a, const std::string& what) {
  if (a.ndim() != 2 || a.shape(1) != 3) throw InvalidInput(what + ": expected an (n, 3) array of coordinates");
  std::vector<Vec3> out(static_cast<std::size_t>(a.shape(0)));
  const double* d = a.data();
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = Vec3(d[3 * i], d[3 * i + 1], d[3 * i + 2]);
  return out;
}

inline TriangleMesh to_mesh(const Points& v, const Faces& f, const std::string& what) {
  TriangleMesh m;
  m.positions = to_points(v, what + " vertices");
  if (f.ndim() != 2 || f.shape(1) != 3) throw InvalidInput(what + " triangles: expected an (m, 3) integer array");
  m.triangles.resize(static_cast<std::size_t>(f.shape(0)));
  const std::int64_t* d = f.data();
  for (std::size_t i = 0; i < m.triangles.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const std::int64_t idx = d[3 * i + static_cast<std::size_t>(k)];
      if (idx < 0 || idx >= static_cast<std::int64_t>(m.positions.size()))
        throw InvalidInput(what + " triangles: triangle " + std::to_string(i) + " refers to vertex " +
                           std::to_string(idx) + " of " + std::to_string(m.positions.size()));
      m.triangles[i][static_cast<std::size_t>(k)] = static_cast<Index>(idx);
    }
  check_mesh(m, what);
  return m;
}

inline py::array_t<double> from_points(const std::vector<Vec3>& p) {
  py::array_t<double> a({static_cast<py::ssize_t>(p.size()), py::ssize_t{3}});
  double* d = a.mutable_data();
  for (std::size_t i = 0; i < p.size(); ++i)
    for (int k = 0; k < 3; ++k) d[3 * i + static_cast<std::size_t>(k)] = p[i][k];
  return a;
}

inline py::array_t<std::int32_t> from_triangles(const std::vector<Triangle>& t) {
  py::array_t<std::int32_t> a({static_cast<py::ssize_t>(t.size()), py::ssize_t{3}});
  std::int32_t* d = a.mutable_data();
  for (std::size_t i = 0; i < t.size(); ++i)
    for (int k = 0; k < 3; ++k)
      d[3 * i + static_cast<std::size_t>(k)] = static_cast<std::int32_t>(t[i][static_cast<std::size_t>(k)]);
  return a;
}

inline py::tuple from_mesh(const TriangleMesh& m) {
  return py::make_tuple(from_points(m.positions), from_triangles(m.triangles));
}

/// A JSON value (st/io/report.h) as the Python object json.loads makes of it.
inline py::object from_json(const nlohmann::json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

/// The solid check (st/io/report.h's keys) with the places of its problems.
/// The report's stability keys (to_json) with the contacts themselves: contact_points, contact_normals.
inline py::dict stability_dict(const StabilityResult& r) {
  py::dict d = from_json(to_json(r));
  std::vector<Vec3> points, normals;
  for (const Contact& c : r.contacts) {
    points.push_back(c.point);
    normals.push_back(c.normal);
  }
  d["contact_points"] = from_points(points);
  d["contact_normals"] = from_points(normals);
  return d;
}

inline py::dict solid_dict(const SolidReport& r) {
  py::dict d = from_json(to_json(r));
  d["problem_points"] = from_points(r.problem_points);
  return d;
}

inline std::optional<Vec3> to_optional_point(const py::object& o, const std::string& what) {
  if (o.is_none()) return std::nullopt;
  const auto pts = to_points(
      Points(py::array(py::module_::import("numpy").attr("asarray")(o, "float64").attr("reshape")(1, 3))), what);
  return pts[0];
}

/// Typed reads from a dict of the case file's keys; `where` names it in errors.
struct DictFields {
  const py::dict& d;
  const std::string& where;
  /// The number at `key`, or `fallback` when it is missing (or None); InvalidInput without a fallback.
  [[nodiscard]] double number(const char* key, std::optional<double> fallback) const {
    if (!d.contains(key) || d[key].is_none()) {
      if (fallback) return *fallback;
      throw InvalidInput(where + ": missing '" + key + "'");
    }
    try {
      return d[key].cast<double>();
    } catch (const py::cast_error&) {
      throw InvalidInput(where + ": '" + key + "' must be a number");
    }
  }
  [[nodiscard]] Vec3 point(const char* key) const {
    if (!d.contains(key)) throw InvalidInput(where + ": missing '" + key + "'");
    const auto p = to_optional_point(py::reinterpret_borrow<py::object>(d[key]), where + "." + key);
    if (!p) throw InvalidInput(where + ": '" + key + "' must be a point, not None");
    return *p;
  }
};

/// A tube from a dict (or any mapping) with the case file's keys; `where` names it in errors.
inline TubeSpec to_tube(const py::handle& item, const std::string& where) {
  if (!py::isinstance<py::dict>(item)) throw InvalidInput(where + ": expected a dict with the case file's tube keys");
  const py::dict d = py::reinterpret_borrow<py::dict>(item);
  const DictFields fields{d, where};
  auto number = [&](const char* key, std::optional<double> fallback) { return fields.number(key, fallback); };
  auto point = [&](const char* key) { return fields.point(key); };
  TubeSpec t;
  t.name = d.contains("name") ? py::str(d["name"]).cast<std::string>() : where;
  if (d.contains("kind") && !d["kind"].is_none()) {
    const std::string kind = py::str(d["kind"]).cast<std::string>();
    const auto named = tube_kind_named(kind);
    if (!named) throw InvalidInput(where + ": 'kind' must be \"sleeve\" or \"pin\", got \"" + kind + "\"");
    t.kind = *named;
  }
  if (d.contains("counterbore") && !d["counterbore"].is_none()) {
    if (!py::isinstance<py::dict>(d["counterbore"]))
      throw InvalidInput(where + ": 'counterbore' must be a dict {'radius': r, 'depth': d}");
    const py::dict cb = d["counterbore"];
    const std::string at = where + ".counterbore";
    const DictFields cf{cb, at};
    t.counterbore = Counterbore{cf.number("radius", std::nullopt), cf.number("depth", std::nullopt)};
  }
  t.entry = point("entry");
  if (t.kind == TubeKind::pin && (!d.contains("direction") || d["direction"].is_none())) t.auto_direction = true;
  else t.direction = point("direction");
  if (t.direction.allFinite() && t.direction.norm() > 0.0) t.direction.normalize();
  t.inner_radius = number("inner_radius", std::nullopt);
  t.outer_radius = number("outer_radius", std::nullopt);
  t.length = number("length", std::nullopt);
  t.offset = number("offset", 0.0);
  t.depth = number("depth", 0.0);
  return t;
}

inline std::vector<TubeSpec> to_tubes(const py::object& list) {
  std::vector<TubeSpec> out;
  if (list.is_none()) return out;
  std::size_t i = 0;
  for (const py::handle item : list) out.push_back(to_tube(item, "tubes[" + std::to_string(i++) + "]"));
  return out;
}

/// A saw slot from a dict with the case file's slot keys (docs/CASE-FORMAT.md); `where` names it in errors.
inline SlotSpec to_slot(const py::handle& item, const std::string& where) {
  if (!py::isinstance<py::dict>(item)) throw InvalidInput(where + ": expected a dict with the case file's slot keys");
  const py::dict d = py::reinterpret_borrow<py::dict>(item);
  const DictFields fields{d, where};
  auto number = [&](const char* key, std::optional<double> fallback) { return fields.number(key, fallback); };
  auto point = [&](const char* key) { return fields.point(key); };
  SlotSpec s;
  s.name = d.contains("name") ? py::str(d["name"]).cast<std::string>() : where;
  s.origin = point("origin");
  s.normal = point("normal");
  if (d.contains("direction") && !d["direction"].is_none()) s.direction = point("direction");
  else s.auto_direction = true; // into the bone in the plane (slot_direction), when built
  s.blade = number("blade", std::nullopt);
  s.length = number("length", std::nullopt);
  s.clearance = number("clearance", 0.1);
  s.height = number("height", 5.0);
  s.wall = number("wall", 3.0);
  if (d.contains("closed") && !d["closed"].is_none()) {
    s.closed_start = s.closed_end = false;
    for (const py::handle end : d["closed"]) {
      const std::string which = py::str(end).cast<std::string>();
      if (which == "start") s.closed_start = true;
      else if (which == "end") s.closed_end = true;
      else throw InvalidInput(where + ": 'closed' must hold \"start\" and \"end\" only, got \"" + which + "\"");
    }
  }
  if (const auto problem = slot_problem(s)) throw InvalidInput(where + "." + problem->key + ": " + problem->reason);
  normalise_slot(s);
  return s;
}

inline std::vector<SlotSpec> to_slots(const py::object& list) {
  std::vector<SlotSpec> out;
  if (list.is_none()) return out;
  std::size_t i = 0;
  for (const py::handle item : list) out.push_back(to_slot(item, "slots[" + std::to_string(i++) + "]"));
  return out;
}

inline py::dict slot_dict(const SlotSpec& s) {
  py::dict d;
  d["name"] = s.name;
  d["origin"] = from_points({s.origin}).attr("reshape")(3);
  d["normal"] = from_points({s.normal}).attr("reshape")(3);
  d["direction"] = s.auto_direction ? py::object(py::none()) : from_points({s.direction}).attr("reshape")(3);
  d["blade"] = s.blade;
  d["clearance"] = s.clearance;
  d["length"] = s.length;
  d["height"] = s.height;
  d["wall"] = s.wall;
  py::list closed;
  if (s.closed_start) closed.append("start");
  if (s.closed_end) closed.append("end");
  d["closed"] = closed;
  return d;
}

/// A label from a dict with the case file's label keys (docs/CASE-FORMAT.md), its text's outlines
/// from the font when the module has OpenCASCADE (else design_template refuses it by name).
inline LabelSpec to_label(const py::handle& item, const std::string& where) {
  if (!py::isinstance<py::dict>(item)) throw InvalidInput(where + ": expected a dict with the case file's label keys");
  const py::dict d = py::reinterpret_borrow<py::dict>(item);
  const DictFields fields{d, where};
  LabelSpec l;
  l.name = d.contains("name") && !d["name"].is_none() ? py::str(d["name"]).cast<std::string>() : where;
  if (!d.contains("text") || d["text"].is_none()) throw InvalidInput(where + ".text: is required");
  l.text = py::str(d["text"]).cast<std::string>();
  l.at = fields.point("at");
  l.up = fields.point("up");
  l.height = fields.number("height", 4.0);
  l.depth = fields.number("depth", 0.6);
  if (d.contains("mode") && !d["mode"].is_none()) {
    const std::string mode = py::str(d["mode"]).cast<std::string>();
    const auto m = label_mode_named(mode);
    if (!m) throw InvalidInput(where + ".mode: must be \"engrave\" or \"emboss\", got \"" + mode + "\"");
    l.mode = *m;
  }
  if (const auto problem = label_problem(l)) throw InvalidInput(where + "." + problem->key + ": " + problem->reason);
  return l;
}

/// The labels of a list of dicts; with `outlines`, their text's outlines too (OpenCASCADE's fonts).
inline std::vector<LabelSpec> to_labels(const py::object& list, bool outlines) {
  std::vector<LabelSpec> out;
  if (list.is_none()) return out;
  std::size_t i = 0;
  for (const py::handle item : list) out.push_back(to_label(item, "labels[" + std::to_string(i++) + "]"));
#ifdef ST_HAVE_OCCT
  if (outlines) fill_label_outlines(out);
#else
  (void)outlines;
#endif
  return out;
}

inline py::dict label_dict(const LabelSpec& l) {
  py::dict d;
  d["name"] = l.name;
  d["text"] = l.text;
  d["at"] = from_points({l.at}).attr("reshape")(3);
  d["up"] = from_points({l.up}).attr("reshape")(3);
  d["height"] = l.height;
  d["depth"] = l.depth;
  d["mode"] = label_mode_name(l.mode);
  return d;
}

inline py::dict tube_dict(const TubeSpec& t) {
  py::dict td;
  td["name"] = t.name;
  td["kind"] = tube_kind_name(t.kind);
  td["entry"] = from_points({t.entry}).attr("reshape")(3);
  td["direction"] =
      t.auto_direction ? py::object(py::none()) : py::object(from_points({t.direction}).attr("reshape")(3));
  if (t.counterbore) {
    py::dict cb;
    cb["radius"] = t.counterbore->radius;
    cb["depth"] = t.counterbore->depth;
    td["counterbore"] = cb;
  }
  td["inner_radius"] = t.inner_radius;
  td["outer_radius"] = t.outer_radius;
  td["length"] = t.length;
  td["offset"] = t.offset;
  td["depth"] = t.depth;
  return td;
}

/// The insertion argument of the module: "auto" (true, no direction), an [x, y, z] direction, or
/// None (false, no direction). InvalidInput for anything else.
inline std::pair<bool, std::optional<Vec3>> to_insertion(const py::object& o) {
  if (o.is_none()) return {false, std::nullopt};
  if (py::isinstance<py::str>(o)) {
    if (o.cast<std::string>() != "auto")
      throw InvalidInput("insertion: must be \"auto\", an [x, y, z] direction or None");
    return {true, std::nullopt};
  }
  return {false, to_optional_point(o, "insertion")};
}

/// A case (CaseFile) as read_case returns it: {path, name, bone, boundary_points, inside, thickness,
/// clearance, resolution, sampling_step, insertion ("auto", an (3,) array or None), tubes, slots,
/// labels, output, warnings}; missing optionals are None.
inline py::dict case_dict(const CaseFile& c) {
  const auto optional = [](const auto& v) { return v ? py::cast(*v) : py::object(py::none()); };
  py::dict d;
  d["path"] = c.path;
  d["name"] = c.name;
  d["bone"] = c.bone;
  d["boundary_points"] = from_points(c.boundary_points);
  d["inside"] = c.inside ? py::object(from_points({*c.inside}).attr("reshape")(3)) : py::object(py::none());
  d["thickness"] = c.thickness;
  d["clearance"] = c.clearance;
  d["resolution"] = optional(c.resolution);
  d["sampling_step"] = optional(c.sampling_step);
  d["insertion"] = c.insertion        ? py::object(from_points({*c.insertion}).attr("reshape")(3))
                   : c.insertion_auto ? py::object(py::str("auto"))
                                      : py::object(py::none());
  py::list tubes;
  for (const TubeSpec& t : c.tubes) tubes.append(tube_dict(t));
  d["tubes"] = tubes;
  py::list slots;
  for (const SlotSpec& s : c.slots) slots.append(slot_dict(s));
  d["slots"] = slots;
  py::list labels;
  for (const LabelSpec& l : c.labels) labels.append(label_dict(l));
  d["labels"] = labels;
  d["output"] = optional(c.output);
  d["warnings"] = c.warnings;
  return d;
}

/// The CaseFile of a dict with case_dict's keys (missing keys, or None, leave their defaults).
inline CaseFile to_case(const py::dict& d) {
  const auto has = [&](const char* key) { return d.contains(key) && !d[key].is_none(); };
  CaseFile c;
  if (has("path")) c.path = py::str(d["path"]).cast<std::string>();
  if (has("name")) c.name = py::str(d["name"]).cast<std::string>();
  if (has("bone")) c.bone = py::str(d["bone"]).cast<std::string>();
  if (has("boundary_points")) {
    const py::array pts = py::module_::import("numpy").attr("asarray")(d["boundary_points"], "float64");
    if (pts.size() > 0) c.boundary_points = to_points(Points(pts.attr("reshape")(-1, 3)), "boundary_points");
  }
  c.inside = to_optional_point(has("inside") ? py::object(d["inside"]) : py::object(py::none()), "inside");
  if (has("thickness")) c.thickness = d["thickness"].cast<double>();
  if (has("clearance")) c.clearance = d["clearance"].cast<double>();
  if (has("resolution")) c.resolution = d["resolution"].cast<double>();
  if (has("sampling_step")) c.sampling_step = d["sampling_step"].cast<int>();
  if (has("insertion")) std::tie(c.insertion_auto, c.insertion) = to_insertion(d["insertion"]);
  if (has("tubes")) c.tubes = to_tubes(d["tubes"]);
  if (has("slots")) c.slots = to_slots(d["slots"]);
  if (has("labels")) c.labels = to_labels(d["labels"], false);
  if (has("output")) c.output = py::str(d["output"]).cast<std::string>();
  return c;
}

} // namespace st::py_convert
