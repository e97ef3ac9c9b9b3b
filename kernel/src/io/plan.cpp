#include "st/io/plan.h"

#include "detail/gzip.h"
#include "detail/input_file.h"
#include "detail/text.h"
#include "detail/json_reader.h"
#include "st/core/errors.h"
#include "st/core/tolerances.h"
#include "st/sleeve_presets_data.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <map>

namespace st {

namespace {

using detail::json;
using detail::lower;
using detail::without_blanks;

} // namespace

Space mesh_space(std::string_view header) {
  return lower(without_blanks(header)).find("space=ras") != std::string::npos ? Space::RAS : Space::LPS;
}

Space mesh_file_space(const std::string& path) {
  // Only the file's start (inflated when it is gzip; zlib reads plain files as they are): where a mesh
  // says its frame. A binary STL's 80-byte header, an ASCII STL's "solid" line, PLY "comment" lines
  // before end_header, OBJ "#" lines near the top.
  const std::string start = detail::read_file_start(path, "mesh file", 64 * 1024);
  std::string head = start;
  if (detail::is_gzip(start.data(), start.size())) {
    const std::vector<char> inflated = detail::gunzip_prefix(start.data(), start.size(), path, 64 * 1024);
    head.assign(inflated.begin(), inflated.end());
  }
  if (head.rfind("ply", 0) == 0) {
    std::string comments;
    const std::size_t end = head.find("end_header");
    std::size_t at = 0;
    while ((at = head.find("comment", at)) != std::string::npos && at < end) {
      const std::size_t eol = head.find('\n', at);
      comments.append(head, at, eol == std::string::npos ? std::string::npos : eol - at).push_back('\n');
      at = eol;
    }
    return mesh_space(comments);
  }
  std::string text = head.substr(0, std::min<std::size_t>(head.size(), 80)); // binary STL header
  text.push_back('\n');
  text.append(head, 0, head.find('\n'));        // ASCII STL's solid line
  for (std::size_t at = 0; at < head.size();) { // OBJ comments
    const std::size_t eol = std::min(head.find('\n', at), head.size());
    if (head[at] == '#') text.append("\n").append(head, at, eol - at);
    at = eol + 1;
  }
  return mesh_space(text);
}

Vec3 convert_space(const Vec3& p, Space from, Space to) { return from == to ? p : Vec3(-p.x(), -p.y(), p.z()); }

Plan plan_of_case(const CaseFile& c) {
  Plan plan;
  plan.path = c.path;
  plan.kind = "case";
  plan.boundary_points = c.boundary_points;
  plan.inside = c.inside;
  plan.warnings = c.warnings;
  for (const TubeSpec& t : c.tubes) {
    PlanAxis a;
    a.name = t.name;
    a.source = c.path + ": tube " + t.name;
    a.entry = t.entry;
    a.direction = t.direction;
    if (t.depth > 0.0) a.depth = t.depth;
    a.inner_radius = t.inner_radius;
    a.outer_radius = t.outer_radius;
    a.length = t.length;
    a.offset = t.offset;
    plan.axes.push_back(std::move(a));
  }
  for (const SlotSpec& s : c.slots) {
    PlanPlane p;
    p.name = s.name;
    p.source = c.path + ": slot " + s.name;
    p.origin = s.origin;
    p.normal = s.normal;
    if (!s.auto_direction) p.direction = s.direction;
    p.blade = s.blade;
    p.clearance = s.clearance;
    p.length = s.length;
    p.height = s.height;
    p.wall = s.wall;
    p.closed = std::array<bool, 2>{s.closed_start, s.closed_end};
    plan.planes.push_back(std::move(p));
  }
  return plan;
}

Plan read_plan(const std::string& path, Space target) {
  const std::string text = detail::read_text_file(path, "plan");
  const std::size_t first = text.find_first_not_of(" \t\r\n\xEF\xBB\xBF");
  if (first != std::string::npos && text[first] == '{') {
    const detail::JsonReader r(path);
    const json doc = r.parse(text);
    if (doc.contains("format")) return plan_of_case(parse_case(text, path));
    if (doc.contains("markups")) return parse_markups(text, path, target);
    r.fail("(top level)", "a JSON plan must be a case file (\"format\") or a 3D Slicer markups file (\"markups\")");
  }
  return parse_plan_csv(text, path, target);
}

TubeSpec tube_from_axis(const PlanAxis& axis, const std::optional<SleevePreset>& sizes) {
  TubeSpec t;
  t.name = axis.name;
  t.entry = axis.entry;
  t.direction = axis.direction;
  t.depth = axis.depth.value_or(0.0);
  const auto size = [&](const std::optional<double>& given, double SleevePreset::*field, const char* key) {
    if (given) return *given;
    if (sizes) return (*sizes).*field;
    throw InvalidInput(axis.source + ": axis \"" + axis.name + "\": the plan gives no " + key +
                       "; choose a sleeve preset");
  };
  t.inner_radius = size(axis.inner_radius, &SleevePreset::inner_radius, "inner_radius");
  t.outer_radius = size(axis.outer_radius, &SleevePreset::outer_radius, "outer_radius");
  t.length = size(axis.length, &SleevePreset::length, "length");
  t.offset = axis.offset ? *axis.offset : sizes ? sizes->offset : 0.0;
  if (sizes) {
    t.kind = sizes->kind;
    t.counterbore = sizes->counterbore;
  }
  if (const auto problem = tube_size_problem(t))
    throw InvalidInput(axis.source + ": axis \"" + axis.name + "\": " + problem->key + " " + problem->reason);
  if (!t.entry.allFinite() || !t.direction.allFinite())
    throw InvalidInput(axis.source + ": axis \"" + axis.name + "\": coordinates must be finite");
  return t;
}

SlotSpec slot_from_plane(const PlanPlane& plane, const SlotSizes& sizes) {
  SlotSpec s;
  s.name = plane.name;
  s.origin = plane.origin;
  s.normal = plane.normal;
  if (plane.direction) s.direction = *plane.direction;
  else s.auto_direction = true;
  const std::string what = plane.source + ": plane \"" + plane.name + "\": ";
  if (plane.blade) s.blade = *plane.blade;
  else if (sizes.blade) s.blade = sizes.blade->thickness;
  else throw InvalidInput(what + "the plan gives no blade thickness; choose a blade");
  if (plane.clearance) s.clearance = *plane.clearance;
  else if (sizes.blade && !plane.blade) s.clearance = sizes.blade->clearance;
  if (plane.length) s.length = *plane.length;
  else if (sizes.length) s.length = *sizes.length;
  else throw InvalidInput(what + "the plan gives no slot length; give one");
  if (plane.height) s.height = *plane.height;
  if (plane.wall) s.wall = *plane.wall;
  if (plane.closed) {
    s.closed_start = (*plane.closed)[0];
    s.closed_end = (*plane.closed)[1];
  }
  if (const auto problem = slot_problem(s)) throw InvalidInput(what + problem->key + " " + problem->reason);
  return s;
}

std::vector<std::string> apply_plan(CaseFile& c, const Plan& plan, const std::optional<SleevePreset>& sizes,
                                    PlanTubes tubes, const SlotSizes& slot_sizes) {
  std::vector<TubeSpec> planned;
  for (const PlanAxis& axis : plan.axes) planned.push_back(tube_from_axis(axis, sizes)); // may throw: first
  std::vector<SlotSpec> cuts;
  for (const PlanPlane& plane : plan.planes) {
    const auto named = [&](const SlotSpec& o) { return o.name == plane.name; };
    if (std::any_of(cuts.begin(), cuts.end(), named) ||
        (tubes == PlanTubes::Add && std::any_of(c.slots.begin(), c.slots.end(), named)))
      throw InvalidInput(plane.source + ": plane \"" + plane.name + "\": a slot of that name is planned already");
    cuts.push_back(slot_from_plane(plane, slot_sizes));
  }
  std::vector<std::string> warnings = plan.warnings;
  if (!plan.boundary_points.empty()) {
    if (c.inside && !plan.inside)
      warnings.push_back(plan.path + ": a new boundary without an inside point: the case's inside point is dropped "
                                     "(the smaller region is kept)");
    c.boundary_points = plan.boundary_points;
    c.inside = plan.inside;
  } else if (plan.inside) {
    c.inside = plan.inside;
  }
  if (!planned.empty()) {
    if (tubes == PlanTubes::Replace) c.tubes.clear();
    c.tubes.insert(c.tubes.end(), planned.begin(), planned.end());
  }
  if (!cuts.empty()) {
    if (tubes == PlanTubes::Replace) c.slots.clear();
    c.slots.insert(c.slots.end(), cuts.begin(), cuts.end());
  }
  return warnings;
}

} // namespace st
