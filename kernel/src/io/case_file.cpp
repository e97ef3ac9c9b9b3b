#include "st/io/case_file.h"
#include "detail/format.h"

#include "detail/json_reader.h"
#include "st/core/errors.h"
#include "st/io/plan.h"

#include <cmath>
#include <filesystem>

namespace st {

namespace {

namespace fs = std::filesystem;
using detail::json;

/// A markups file named by the case, in the bone's frame (the bone's header is read once, when the
/// first markups file needs it).
Plan case_markups(const std::string& file, const CaseFile& c, std::optional<Space>& space) {
  if (!space) space = mesh_file_space(c.bone);
  return read_markups(file, *space);
}

/// slots[i] of a case (docs/CASE-FORMAT.md): the plane, the saw's travel, the blade and the housing.
SlotSpec parse_slot(const detail::JsonReader& r, const json& s, std::size_t i, std::vector<std::string>& warnings) {
  const std::string key = "slots[" + std::to_string(i) + "]";
  if (!s.is_object()) r.fail(key, "must be an object");
  r.unknown_keys(s,
                 {"name", "origin", "normal", "direction", "blade", "clearance", "length", "height", "wall", "closed"},
                 key + ".", warnings);
  SlotSpec slot;
  slot.name = r.string(r.required(s, "name", key + ".name"), key + ".name");
  slot.origin = r.point(r.required(s, "origin", key + ".origin"), key + ".origin");
  slot.normal = r.point(r.required(s, "normal", key + ".normal"), key + ".normal");
  if (s.contains("direction")) slot.direction = r.point(s["direction"], key + ".direction");
  else slot.auto_direction = true; // into the bone in the plane (slot_direction), when designed
  slot.blade = r.number(r.required(s, "blade", key + ".blade"), key + ".blade");
  slot.length = r.number(r.required(s, "length", key + ".length"), key + ".length");
  if (s.contains("clearance")) slot.clearance = r.number(s["clearance"], key + ".clearance");
  if (s.contains("height")) slot.height = r.number(s["height"], key + ".height");
  if (s.contains("wall")) slot.wall = r.number(s["wall"], key + ".wall");
  if (s.contains("closed")) {
    const json& closed = s["closed"];
    if (!closed.is_array()) r.fail(key + ".closed", "must be an array of \"start\" and \"end\"");
    slot.closed_start = slot.closed_end = false;
    for (const json& end : closed) {
      const std::string which = r.string(end, key + ".closed");
      if (which == "start") slot.closed_start = true;
      else if (which == "end") slot.closed_end = true;
      else r.fail(key + ".closed", "must hold \"start\" and \"end\" only, got \"" + which + "\"");
    }
  }
  if (const auto problem = slot_problem(slot)) r.fail(key + "." + problem->key, problem->reason);
  normalise_slot(slot);
  return slot;
}

/// labels[i] of a case (docs/CASE-FORMAT.md): the text, where it is centred, its up direction, size,
/// depth and mode. Its outlines are left to the caller (st/occt/occt_text.h).
LabelSpec parse_label(const detail::JsonReader& r, const json& l, std::size_t i, std::vector<std::string>& warnings) {
  const std::string key = "labels[" + std::to_string(i) + "]";
  if (!l.is_object()) r.fail(key, "must be an object");
  r.unknown_keys(l, {"name", "text", "at", "up", "height", "depth", "mode"}, key + ".", warnings);
  LabelSpec label;
  label.text = r.string(r.required(l, "text", key + ".text"), key + ".text");
  label.name = l.contains("name") ? r.string(l["name"], key + ".name") : "label " + std::to_string(i + 1);
  label.at = r.point(r.required(l, "at", key + ".at"), key + ".at");
  label.up = r.point(r.required(l, "up", key + ".up"), key + ".up");
  if (l.contains("height")) label.height = r.number(l["height"], key + ".height");
  if (l.contains("depth")) label.depth = r.number(l["depth"], key + ".depth");
  if (l.contains("mode")) {
    const std::string mode = r.string(l["mode"], key + ".mode");
    const auto m = label_mode_named(mode);
    if (!m) r.fail(key + ".mode", "must be \"engrave\" or \"emboss\", got \"" + mode + "\"");
    label.mode = *m;
  }
  if (const auto problem = label_problem(label)) r.fail(key + "." + problem->key, problem->reason);
  return label;
}

} // namespace

TemplateOptions template_options(const CaseFile& c) {
  TemplateOptions o;
  o.boundary_points = c.boundary_points;
  o.inside = c.inside;
  o.thickness = c.thickness;
  o.clearance = c.clearance;
  o.resolution = c.resolution.value_or(0.0);
  o.sampling_step = c.sampling_step.value_or(0);
  o.tubes = c.tubes;
  o.slots = c.slots;
  o.labels = c.labels;
  o.analyse_insertion = true;
  o.insertion = c.insertion;
  o.block_out = c.insertion.has_value() || c.insertion_auto;
  return o;
}

CaseFile parse_case(const std::string& text, const std::string& path) {
  const detail::JsonReader r(path);
  const json doc = r.parse(text);
  if (!doc.is_object()) r.fail("(top level)", "must be a JSON object");
  CaseFile c;
  c.path = path;
  const fs::path folder = fs::absolute(fs::path(path)).parent_path();
  auto resolve = [&](const std::string& p) { return (folder / p).lexically_normal().string(); };

  const std::string format = r.string(r.required(doc, "format", "format"), "format");
  if (format != kCaseFormat) r.fail("format", "must be \"" + std::string(kCaseFormat) + "\", got \"" + format + "\"");
  r.unknown_keys(doc, {"format", "name", "bone", "boundary", "template", "tubes", "slots", "labels", "output"}, "",
                 c.warnings);

  c.name = doc.contains("name") ? r.string(doc["name"], "name") : fs::path(path).stem().string();
  c.bone = resolve(r.string(r.required(doc, "bone", "bone"), "bone"));

  const json& boundary = r.required(doc, "boundary", "boundary");
  if (!boundary.is_object()) r.fail("boundary", "must be an object");
  r.unknown_keys(boundary, {"points", "inside", "markups"}, "boundary.", c.warnings);
  std::optional<Space> space; // the bone's frame, read only when markups need it
  if (boundary.contains("points") && boundary.contains("markups"))
    r.fail("boundary", "give either points or markups, not both");
  if (boundary.contains("markups")) {
    const std::string file = resolve(r.string(boundary["markups"], "boundary.markups"));
    const Plan plan = case_markups(file, c, space);
    if (plan.boundary_points.empty())
      r.fail("boundary.markups", file + " holds no ClosedCurve (or point list) for the boundary");
    c.boundary_points = plan.boundary_points;
  } else {
    const json& points = r.required(boundary, "points", "boundary.points");
    if (!points.is_array()) r.fail("boundary.points", "must be an array of [x, y, z] points");
    if (points.size() < 3) r.fail("boundary.points", "needs at least 3 points, got " + std::to_string(points.size()));
    for (std::size_t i = 0; i < points.size(); ++i)
      c.boundary_points.push_back(r.point(points[i], "boundary.points[" + std::to_string(i) + "]"));
  }
  if (boundary.contains("inside")) c.inside = r.point(boundary["inside"], "boundary.inside");

  const json& tpl = r.required(doc, "template", "template");
  if (!tpl.is_object()) r.fail("template", "must be an object");
  r.unknown_keys(tpl, {"thickness", "clearance", "resolution", "sampling_step", "insertion"}, "template.", c.warnings);
  c.thickness = r.number(r.required(tpl, "thickness", "template.thickness"), "template.thickness");
  if (!(c.thickness > 0.0)) r.fail("template.thickness", "must be > 0, got " + detail::number(c.thickness));
  if (tpl.contains("clearance")) {
    c.clearance = r.number(tpl["clearance"], "template.clearance");
    if (c.clearance < 0.0) r.fail("template.clearance", "must be >= 0, got " + detail::number(c.clearance));
  }
  if (tpl.contains("resolution")) {
    c.resolution = r.number(tpl["resolution"], "template.resolution");
    if (!(*c.resolution > 0.0)) r.fail("template.resolution", "must be > 0, got " + detail::number(*c.resolution));
  }
  if (tpl.contains("sampling_step")) {
    const json& s = tpl["sampling_step"];
    if (!s.is_number_integer() && !(s.is_number() && std::floor(s.get<double>()) == s.get<double>()))
      r.fail("template.sampling_step", "must be an integer");
    const double v = s.get<double>();
    if (v < 1 || v > 1e6) r.fail("template.sampling_step", "must be between 1 and 1000000");
    c.sampling_step = static_cast<int>(v);
  }
  if (tpl.contains("insertion")) {
    const json& i = tpl["insertion"];
    if (i.is_string()) {
      if (i.get<std::string>() != "auto")
        r.fail("template.insertion",
               "must be \"auto\" or an [x, y, z] direction, got \"" + i.get<std::string>() + "\"");
      c.insertion_auto = true;
    } else {
      const Vec3 d = r.point(i, "template.insertion");
      if (!(d.norm() > 0.0)) r.fail("template.insertion", "must be a non-zero direction");
      c.insertion = d.normalized();
    }
  }

  if (doc.contains("tubes")) {
    const json& tubes = doc["tubes"];
    if (!tubes.is_array()) r.fail("tubes", "must be an array");
    for (std::size_t i = 0; i < tubes.size(); ++i) {
      const std::string key = "tubes[" + std::to_string(i) + "]";
      const json& t = tubes[i];
      if (!t.is_object()) r.fail(key, "must be an object");
      r.unknown_keys(t,
                     {"name", "entry", "direction", "inner_radius", "outer_radius", "length", "offset", "depth",
                      "markups", "kind", "counterbore"},
                     key + ".", c.warnings);
      TubeSpec tube;
      tube.name = t.contains("name") ? r.string(t["name"], key + ".name") : std::to_string(i + 1);
      if (t.contains("kind")) {
        const std::string kind = r.string(t["kind"], key + ".kind");
        const auto named = tube_kind_named(kind);
        if (!named) r.fail(key + ".kind", "must be \"sleeve\" or \"pin\", got \"" + kind + "\"");
        tube.kind = *named;
      }
      if (t.contains("counterbore")) {
        const json& cb = t["counterbore"];
        if (!cb.is_object()) r.fail(key + ".counterbore", "must be an object {\"radius\": r, \"depth\": d}");
        r.unknown_keys(cb, {"radius", "depth"}, key + ".counterbore.", c.warnings);
        tube.counterbore =
            Counterbore{r.number(r.required(cb, "radius", key + ".counterbore.radius"), key + ".counterbore.radius"),
                        r.number(r.required(cb, "depth", key + ".counterbore.depth"), key + ".counterbore.depth")};
      }
      if (t.contains("markups")) {
        if (t.contains("entry") || t.contains("direction"))
          r.fail(key, "give either markups or entry and direction, not both");
        const std::string file = resolve(r.string(t["markups"], key + ".markups"));
        const Plan plan = case_markups(file, c, space);
        if (plan.axes.size() != 1)
          r.fail(key + ".markups", file + " must hold exactly one Line, found " + std::to_string(plan.axes.size()));
        tube.entry = plan.axes[0].entry;
        tube.direction = plan.axes[0].direction;
        if (plan.axes[0].depth) tube.depth = *plan.axes[0].depth;
        if (!t.contains("name")) tube.name = plan.axes[0].name;
      } else {
        tube.entry = r.point(r.required(t, "entry", key + ".entry"), key + ".entry");
        if (tube.kind == TubeKind::pin && !t.contains("direction")) {
          tube.auto_direction = true; // into the bone from the entry (pin_direction), when designed
        } else {
          tube.direction = r.point(r.required(t, "direction", key + ".direction"), key + ".direction");
          const double len = tube.direction.stableNorm(); // no overflow for huge components
          if (!(len > 1e-12)) r.fail(key + ".direction", "must be non-zero");
          tube.direction /= len;
          if (!tube.direction.allFinite()) r.fail(key + ".direction", "must be a finite, non-zero vector");
        }
      }
      tube.inner_radius = r.number(r.required(t, "inner_radius", key + ".inner_radius"), key + ".inner_radius");
      tube.outer_radius = r.number(r.required(t, "outer_radius", key + ".outer_radius"), key + ".outer_radius");
      tube.length = r.number(r.required(t, "length", key + ".length"), key + ".length");
      if (t.contains("offset")) tube.offset = r.number(t["offset"], key + ".offset");
      if (t.contains("depth")) tube.depth = r.number(t["depth"], key + ".depth");
      if (const auto problem = tube_size_problem(tube)) r.fail(key + "." + problem->key, problem->reason);
      c.tubes.push_back(tube);
    }
  }
  if (doc.contains("slots")) {
    const json& slots = doc["slots"];
    if (!slots.is_array()) r.fail("slots", "must be an array");
    for (std::size_t i = 0; i < slots.size(); ++i) {
      c.slots.push_back(parse_slot(r, slots[i], i, c.warnings));
      for (std::size_t j = 0; j < i; ++j)
        if (c.slots[j].name == c.slots[i].name)
          r.fail("slots[" + std::to_string(i) + "].name", "\"" + c.slots[i].name + "\" names an earlier slot too");
    }
  }
  if (doc.contains("labels")) {
    const json& labels = doc["labels"];
    if (!labels.is_array()) r.fail("labels", "must be an array");
    for (std::size_t i = 0; i < labels.size(); ++i) {
      c.labels.push_back(parse_label(r, labels[i], i, c.warnings));
      for (std::size_t j = 0; j < i; ++j)
        if (c.labels[j].name == c.labels[i].name)
          r.fail("labels[" + std::to_string(i) + "].name", "\"" + c.labels[i].name + "\" names an earlier label too");
    }
  }
  if (doc.contains("output")) c.output = resolve(r.string(doc["output"], "output"));
  return c;
}

CaseFile read_case(const std::string& path) { return parse_case(detail::read_text_file(path, "case file"), path); }

std::string case_json(const CaseFile& c, const std::string& path) {
  const fs::path folder = fs::absolute(fs::path(path)).parent_path();
  const auto relative = [&](const std::string& p) { return fs::absolute(p).lexically_relative(folder).string(); };
  const auto point = [](const Vec3& p) { return json::array({p.x(), p.y(), p.z()}); };
  json doc;
  doc["format"] = kCaseFormat;
  doc["name"] = c.name;
  doc["bone"] = relative(c.bone);
  doc["boundary"]["points"] = json::array();
  for (const Vec3& p : c.boundary_points) doc["boundary"]["points"].push_back(point(p));
  if (c.inside) doc["boundary"]["inside"] = point(*c.inside);
  doc["template"] = {{"thickness", c.thickness}, {"clearance", c.clearance}};
  if (c.resolution) doc["template"]["resolution"] = *c.resolution;
  if (c.sampling_step) doc["template"]["sampling_step"] = *c.sampling_step;
  if (c.insertion) doc["template"]["insertion"] = point(*c.insertion);
  else if (c.insertion_auto) doc["template"]["insertion"] = "auto";
  doc["tubes"] = json::array();
  for (const TubeSpec& t : c.tubes) {
    json tube = {{"name", t.name},
                 {"entry", point(t.entry)},
                 {"inner_radius", t.inner_radius},
                 {"outer_radius", t.outer_radius},
                 {"length", t.length},
                 {"offset", t.offset}};
    if (!t.auto_direction) tube["direction"] = point(t.direction);
    if (t.kind != TubeKind::sleeve) tube["kind"] = tube_kind_name(t.kind);
    if (t.counterbore) tube["counterbore"] = {{"radius", t.counterbore->radius}, {"depth", t.counterbore->depth}};
    if (t.depth > 0.0) tube["depth"] = t.depth;
    doc["tubes"].push_back(tube);
  }
  if (!c.slots.empty()) doc["slots"] = json::array();
  for (const SlotSpec& s : c.slots) {
    json closed = json::array();
    if (s.closed_start) closed.push_back("start");
    if (s.closed_end) closed.push_back("end");
    json slot = {
        {"name", s.name},           {"origin", point(s.origin)}, {"normal", point(s.normal)}, {"blade", s.blade},
        {"clearance", s.clearance}, {"length", s.length},        {"height", s.height},        {"wall", s.wall},
        {"closed", closed}};
    if (!s.auto_direction) slot["direction"] = point(s.direction);
    doc["slots"].push_back(slot);
  }
  if (!c.labels.empty()) doc["labels"] = json::array();
  for (const LabelSpec& l : c.labels)
    doc["labels"].push_back({{"name", l.name},
                             {"text", l.text},
                             {"at", point(l.at)},
                             {"up", point(l.up)},
                             {"height", l.height},
                             {"depth", l.depth},
                             {"mode", label_mode_name(l.mode)}});
  if (c.output) doc["output"] = relative(*c.output);
  return doc.dump(2) + "\n";
}

void write_case(const CaseFile& c, const std::string& path) {
  const std::string text = case_json(c, path);
  parse_case(text, path); // every rule of the format, before a byte is written
  detail::write_text_atomically(path, text, "case file");
}

} // namespace st
