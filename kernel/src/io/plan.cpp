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

/// `s` without leading and trailing space, as a string.
std::string trim(std::string_view s) { return std::string(detail::trim(s)); }

// ---- 3D Slicer markups ---------------------------------------------------------------------------

struct ControlPoint {
  Vec3 position;
  std::string label;
};

Space markup_space(const detail::JsonReader& r, const json& m, const std::string& key) {
  if (!m.contains("coordinateSystem")) return Space::LPS; // Slicer's default
  const std::string s = lower(r.string(m["coordinateSystem"], key + ".coordinateSystem"));
  if (s == "lps") return Space::LPS;
  if (s == "ras") return Space::RAS;
  r.fail(key + ".coordinateSystem", "must be \"LPS\" or \"RAS\", got \"" + s + "\"");
}

/// mm per unit of the markup's coordinates.
double markup_scale(const detail::JsonReader& r, const json& m, const std::string& key) {
  if (!m.contains("coordinateUnits")) return 1.0;
  const json& u = m["coordinateUnits"];
  // A plain string, or a coded entry (UCUM): [CodeValue, CodingSchemeDesignator, CodeMeaning] as Slicer
  // writes it, or an object with a CodeValue.
  std::string unit;
  if (u.is_array()) {
    if (u.empty()) r.fail(key + ".coordinateUnits", "is an empty coded entry");
    unit = r.string(u[0], key + ".coordinateUnits[0]");
  } else if (u.is_object()) {
    unit = r.string(r.required(u, "CodeValue", key + ".coordinateUnits.CodeValue"), key + ".coordinateUnits.CodeValue");
  } else {
    unit = r.string(u, key + ".coordinateUnits");
  }
  if (unit == "mm") return 1.0;
  if (unit == "um") return 1e-3;
  r.fail(key + ".coordinateUnits", "must be \"mm\" or \"um\", got \"" + unit + "\"");
}

std::vector<ControlPoint> control_points(const detail::JsonReader& r, const json& m, const std::string& key,
                                         Space target, std::vector<std::string>& warnings) {
  std::vector<ControlPoint> out;
  if (!m.contains("controlPoints")) return out;
  const json& cps = m["controlPoints"];
  if (!cps.is_array()) r.fail(key + ".controlPoints", "must be an array");
  const Space space = markup_space(r, m, key);
  const double scale = markup_scale(r, m, key);
  for (std::size_t i = 0; i < cps.size(); ++i) {
    const std::string ck = key + ".controlPoints[" + std::to_string(i) + "]";
    const json& cp = cps[i];
    if (!cp.is_object()) r.fail(ck, "must be an object");
    if (cp.contains("positionStatus")) {
      const std::string status = r.string(cp["positionStatus"], ck + ".positionStatus");
      if (status != "defined") {
        warnings.push_back(r.file() + ": " + ck + ": skipped (positionStatus \"" + status + "\")");
        continue;
      }
    }
    ControlPoint p;
    p.position =
        convert_space(r.point(r.required(cp, "position", ck + ".position"), ck + ".position") * scale, space, target);
    if (cp.contains("label")) p.label = r.string(cp["label"], ck + ".label");
    out.push_back(std::move(p));
  }
  return out;
}

std::vector<Vec3> positions(const std::vector<ControlPoint>& points) {
  std::vector<Vec3> out;
  for (const ControlPoint& p : points) out.push_back(p.position);
  return out;
}

// ---- CSV -------------------------------------------------------------------------------------------

/// The fields of one CSV line; quoted fields may hold the delimiter and "" for a quote.
std::vector<std::string> split_fields(std::string_view line, char delimiter, const std::string& where) {
  std::vector<std::string> fields;
  std::string field;
  bool quoted = false, was_quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char ch = line[i];
    if (quoted) {
      if (ch == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (ch == '"') {
        quoted = false;
      } else {
        field += ch;
      }
    } else if (ch == '"' && trim(field).empty()) {
      quoted = was_quoted = true;
      field.clear();
    } else if (ch == delimiter) {
      fields.push_back(was_quoted ? field : trim(field));
      field.clear();
      was_quoted = false;
    } else {
      field += ch;
    }
  }
  if (quoted) throw InvalidInput(where + ": a quoted field is not closed");
  fields.push_back(was_quoted ? field : trim(field));
  return fields;
}

/// A column name as the plan's key: lower case, blanks and dashes as '_'. A unit after the name,
/// " (mm)" or " [mm]", must be mm: every column is a length (or the name).
std::string column_key(const std::string& name, const std::string& where) {
  std::string s = lower(trim(name));
  if (const auto cut = s.find_first_of("(["); cut != std::string::npos) {
    const std::string unit = without_blanks(s.substr(cut + 1, s.find_first_of(")]", cut) - cut - 1));
    if (unit != "mm")
      throw InvalidInput(where + ": column \"" + trim(name) + "\": lengths must be in mm, not \"" + unit + "\"");
    s = trim(s.substr(0, cut));
  }
  for (char& ch : s)
    if (ch == ' ' || ch == '-') ch = '_';
  return s;
}

/// A decimal number (no hexadecimal, no locale), finite and within double range.
double csv_number(const std::string& field, const std::string& where) {
  if (field.empty()) throw InvalidInput(where + ": is empty");
  const char* begin = field.data() + (field[0] == '+' ? 1 : 0);
  const char* end = field.data() + field.size();
  double v = 0.0;
  const auto [stop, error] = std::from_chars(begin, end, v, std::chars_format::general);
  if (error == std::errc::result_out_of_range) throw InvalidInput(where + ": \"" + field + "\" is out of range");
  if (error != std::errc() || stop != end || begin == end)
    throw InvalidInput(where + ": \"" + field + "\" is not a number");
  if (!std::isfinite(v)) throw InvalidInput(where + ": \"" + field + "\" is not a finite number");
  return v;
}

const std::vector<std::string> kCsvColumns = {
    "name",           "entry_x",        "entry_y",  "entry_z",  "direction_x",  "direction_y",
    "direction_z",    "target_x",       "target_y", "target_z", "inner_radius", "outer_radius",
    "inner_diameter", "outer_diameter", "length",   "offset",   "depth"};

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

Plan parse_markups(const std::string& text, const std::string& path, Space target) {
  const detail::JsonReader r(path);
  const json doc = r.parse(text);
  if (!doc.is_object()) r.fail("(top level)", "must be a JSON object (a 3D Slicer markups file)");
  Plan plan;
  plan.path = path;
  plan.kind = "markups";
  if (!doc.contains("@schema")) plan.warnings.push_back(path + ": no \"@schema\"; read as a 3D Slicer markups file");
  const json& markups = r.required(doc, "markups", "markups");
  if (!markups.is_array()) r.fail("markups", "must be an array");
  bool closed_curve = false;
  std::vector<Vec3> point_list_boundary;
  for (std::size_t i = 0; i < markups.size(); ++i) {
    const std::string key = "markups[" + std::to_string(i) + "]";
    const json& m = markups[i];
    if (!m.is_object()) r.fail(key, "must be an object");
    const std::string type = r.string(r.required(m, "type", key + ".type"), key + ".type");
    const std::string name = m.contains("name") ? r.string(m["name"], key + ".name") : "";
    const std::vector<ControlPoint> points = control_points(r, m, key, target, plan.warnings);
    const std::string what = key + " (" + type + (name.empty() ? "" : " \"" + name + "\"") + ")";
    if (type == "ClosedCurve") {
      if (closed_curve) {
        plan.warnings.push_back(path + ": " + what + ": a second ClosedCurve, ignored");
        continue;
      }
      if (points.size() < 3)
        r.fail(what, "a boundary needs at least 3 defined control points, got " + std::to_string(points.size()));
      plan.boundary_points = positions(points);
      closed_curve = true;
    } else if (type == "Line") {
      if (points.size() != 2)
        r.fail(what, "a drilling axis needs exactly 2 defined control points (entry, then a point inside the "
                     "bone), got " +
                         std::to_string(points.size()));
      PlanAxis axis;
      axis.entry = points[0].position;
      const Vec3 along = points[1].position - points[0].position;
      const double depth = along.norm();
      if (!(depth > 1e-9)) r.fail(what, "its two control points coincide: no direction");
      axis.direction = along / depth;
      axis.depth = depth;
      axis.name = !name.empty()              ? name
                  : !points[0].label.empty() ? points[0].label
                                             : "Line " + std::to_string(plan.axes.size() + 1);
      axis.source = path + ": " + key;
      plan.axes.push_back(std::move(axis));
    } else if (type == "Fiducial") {
      if (points.size() == 1) {
        if (plan.inside) plan.warnings.push_back(path + ": " + what + ": a second inside point, ignored");
        else plan.inside = points[0].position;
      } else if (points.size() >= 3 && point_list_boundary.empty()) {
        point_list_boundary = positions(points);
      } else {
        plan.warnings.push_back(path + ": " + what + ": a point list of " + std::to_string(points.size()) +
                                " points, ignored (1 point: inside the region; 3 or more: the boundary)");
      }
    } else {
      plan.warnings.push_back(path + ": " + what + ": this markups type is not part of a plan, ignored");
    }
  }
  if (!closed_curve && !point_list_boundary.empty()) plan.boundary_points = std::move(point_list_boundary);
  if (plan.boundary_points.empty() && plan.axes.empty())
    r.fail("markups", "holds no ClosedCurve, point list or Line: nothing to plan with");
  return plan;
}

Plan read_markups(const std::string& path, Space target) {
  return parse_markups(detail::read_text_file(path, "markups file"), path, target);
}

Plan parse_plan_csv(const std::string& text, const std::string& path, Space target) {
  Plan plan;
  plan.path = path;
  plan.kind = "csv";
  std::optional<Space> file_space;
  std::vector<std::string> header; // column keys
  char delimiter = ',';
  std::map<std::string, std::size_t> column;
  std::size_t line_number = 0, begin = 0;
  if (text.compare(0, 3, "\xEF\xBB\xBF") == 0) begin = 3; // UTF-8 byte order mark
  while (begin <= text.size()) {
    std::size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(begin, end - begin);
    begin = end + 1;
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string where = path + ":" + std::to_string(line_number);
    const std::string content = trim(line);
    if (content.empty()) continue;
    if (content[0] == '#') {
      const std::string directive = lower(without_blanks(content.substr(1)));
      if (!header.empty() && split_fields(line, delimiter, where).size() == header.size())
        plan.warnings.push_back(where + ": starts with '#' and is ignored as a comment (a name starting with '#' "
                                        "must be quoted)");
      if (directive.rfind("space=", 0) == 0) {
        if (!header.empty()) throw InvalidInput(where + ": the space line must come before the column names");
        const std::string s = directive.substr(6);
        if (s == "lps") file_space = Space::LPS;
        else if (s == "ras") file_space = Space::RAS;
        else throw InvalidInput(where + ": space must be LPS or RAS, got \"" + s + "\"");
      }
      continue;
    }
    if (line.find('\0') != std::string::npos) throw InvalidInput(where + ": holds binary bytes: not a CSV plan");
    if (header.empty()) {
      const std::size_t commas = std::count(line.begin(), line.end(), ',');
      const std::size_t semicolons = std::count(line.begin(), line.end(), ';');
      const std::size_t tabs = std::count(line.begin(), line.end(), '\t');
      if (commas + semicolons + tabs == 0)
        throw InvalidInput(where + ": the first line must name the columns (name, entry_x, entry_y, ...), "
                                   "separated by commas, semicolons or tabs");
      delimiter = tabs >= commas && tabs >= semicolons ? '\t' : semicolons > commas ? ';' : ',';
      for (const std::string& f : split_fields(line, delimiter, where)) header.push_back(column_key(f, where));
      for (std::size_t i = 0; i < header.size(); ++i) {
        if (std::find(kCsvColumns.begin(), kCsvColumns.end(), header[i]) == kCsvColumns.end()) {
          plan.warnings.push_back(where + ": unknown column \"" + header[i] + "\" ignored");
          continue;
        }
        if (column.count(header[i])) throw InvalidInput(where + ": column \"" + header[i] + "\" appears twice");
        column[header[i]] = i;
      }
      const auto has = [&](const char* c) { return column.count(c) > 0; };
      for (const char* c : {"entry_x", "entry_y", "entry_z"})
        if (!has(c)) throw InvalidInput(where + ": no column \"" + std::string(c) + "\"");
      const bool direction = has("direction_x") || has("direction_y") || has("direction_z");
      const bool target_point = has("target_x") || has("target_y") || has("target_z");
      if (direction == target_point)
        throw InvalidInput(where + ": give either direction_x/_y/_z or target_x/_y/_z columns (one of them)");
      static const std::array<const char*, 3> kDirection = {"direction_x", "direction_y", "direction_z"};
      static const std::array<const char*, 3> kTarget = {"target_x", "target_y", "target_z"};
      for (const char* c : direction ? kDirection : kTarget)
        if (!has(c)) throw InvalidInput(where + ": no column \"" + std::string(c) + "\"");
      if (has("inner_radius") && has("inner_diameter"))
        throw InvalidInput(where + ": give inner_radius or inner_diameter, not both");
      if (has("outer_radius") && has("outer_diameter"))
        throw InvalidInput(where + ": give outer_radius or outer_diameter, not both");
      continue;
    }
    const std::vector<std::string> fields = split_fields(line, delimiter, where);
    if (fields.size() != header.size())
      throw InvalidInput(where + ": has " + std::to_string(fields.size()) + " fields, the header names " +
                         std::to_string(header.size()));
    const auto field = [&](const char* c) -> const std::string& { return fields[column.at(c)]; };
    const auto number = [&](const char* c) { return csv_number(field(c), where + ": " + c); };
    const auto vec = [&](const char* x, const char* y, const char* z) { return Vec3(number(x), number(y), number(z)); };
    const auto optional = [&](const char* c, double scale) -> std::optional<double> {
      if (!column.count(c) || field(c).empty()) return std::nullopt;
      return number(c) * scale;
    };
    const Space from = file_space.value_or(target);
    PlanAxis axis;
    axis.source = where;
    axis.name = column.count("name") && !field("name").empty() ? field("name") : std::to_string(plan.axes.size() + 1);
    axis.entry = convert_space(vec("entry_x", "entry_y", "entry_z"), from, target);
    if (column.count("direction_x")) {
      const Vec3 d = convert_space(vec("direction_x", "direction_y", "direction_z"), from, target);
      const double n = d.stableNorm();
      if (!(n > 1e-12) || !std::isfinite(n)) throw InvalidInput(where + ": the direction must be a non-zero vector");
      axis.direction = d / n;
    } else {
      const Vec3 along = convert_space(vec("target_x", "target_y", "target_z"), from, target) - axis.entry;
      const double n = along.norm();
      if (!(n > 1e-9) || !std::isfinite(n))
        throw InvalidInput(where + ": the target must differ from the entry (it gives the direction)");
      axis.direction = along / n;
      axis.depth = n;
    }
    axis.inner_radius =
        column.count("inner_diameter") ? optional("inner_diameter", 0.5) : optional("inner_radius", 1.0);
    axis.outer_radius =
        column.count("outer_diameter") ? optional("outer_diameter", 0.5) : optional("outer_radius", 1.0);
    axis.length = optional("length", 1.0);
    axis.offset = optional("offset", 1.0);
    if (const auto depth = optional("depth", 1.0)) axis.depth = depth;
    plan.axes.push_back(std::move(axis));
  }
  if (header.empty()) throw InvalidInput(path + ": empty: a CSV plan needs a header line and one line per axis");
  if (plan.axes.empty()) throw InvalidInput(path + ": names its columns but holds no axes");
  return plan;
}

Plan read_plan_csv(const std::string& path, Space target) {
  return parse_plan_csv(detail::read_text_file(path, "CSV plan"), path, target);
}

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

// ---- sleeve presets --------------------------------------------------------------------------------

std::vector<SleevePreset> parse_sleeve_presets(const std::string& text, const std::string& path) {
  const detail::JsonReader r(path);
  const json doc = r.parse(text);
  if (!doc.is_object()) r.fail("(top level)", "must be a JSON object");
  const std::string format = r.string(r.required(doc, "format", "format"), "format");
  if (format != "surgical-template-sleeves/1")
    r.fail("format", "must be \"surgical-template-sleeves/1\", got \"" + format + "\"");
  const json& sleeves = r.required(doc, "sleeves", "sleeves");
  if (!sleeves.is_array()) r.fail("sleeves", "must be an array");
  std::vector<SleevePreset> out;
  for (std::size_t i = 0; i < sleeves.size(); ++i) {
    const std::string key = "sleeves[" + std::to_string(i) + "]";
    const json& s = sleeves[i];
    if (!s.is_object()) r.fail(key, "must be an object");
    SleevePreset p;
    p.name = r.string(r.required(s, "name", key + ".name"), key + ".name");
    if (trim(p.name).empty()) r.fail(key + ".name", "must not be empty");
    for (const SleevePreset& q : out)
      if (q.name == p.name) r.fail(key + ".name", "\"" + p.name + "\" appears twice");
    if (s.contains("description")) p.description = r.string(s["description"], key + ".description");
    p.inner_radius = 0.5 * r.number(r.required(s, "inner_diameter", key + ".inner_diameter"), key + ".inner_diameter");
    p.outer_radius = 0.5 * r.number(r.required(s, "outer_diameter", key + ".outer_diameter"), key + ".outer_diameter");
    p.length = r.number(r.required(s, "length", key + ".length"), key + ".length");
    if (s.contains("offset")) p.offset = r.number(s["offset"], key + ".offset");
    TubeSpec t;
    t.inner_radius = p.inner_radius;
    t.outer_radius = p.outer_radius;
    t.length = p.length;
    t.offset = p.offset;
    if (const auto problem = tube_size_problem(t)) {
      std::string k = problem->key;
      if (k == "inner_radius" || k == "outer_radius") k = k.substr(0, 5) + "_diameter";
      r.fail(key + "." + k, problem->reason);
    }
    out.push_back(std::move(p));
  }
  return out;
}

std::vector<SleevePreset> read_sleeve_presets(const std::string& path) {
  return parse_sleeve_presets(detail::read_text_file(path, "sleeve catalogue"), path);
}

const std::vector<SleevePreset>& default_sleeve_presets() {
  static const std::vector<SleevePreset> presets =
      parse_sleeve_presets(kDefaultSleevePresets, "data/sleeve-presets.json (built in)");
  return presets;
}

const SleevePreset& find_sleeve_preset(const std::vector<SleevePreset>& presets, const std::string& name) {
  for (const SleevePreset& p : presets)
    if (p.name == name) return p;
  for (const SleevePreset& p : presets)
    if (lower(p.name) == lower(name)) return p;
  std::string names;
  for (const SleevePreset& p : presets) names += (names.empty() ? "" : ", ") + ("\"" + p.name + "\"");
  throw InvalidInput("no sleeve preset \"" + name + "\"; the catalogue has " + (names.empty() ? "none" : names));
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
  if (const auto problem = tube_size_problem(t))
    throw InvalidInput(axis.source + ": axis \"" + axis.name + "\": " + problem->key + " " + problem->reason);
  if (!t.entry.allFinite() || !t.direction.allFinite())
    throw InvalidInput(axis.source + ": axis \"" + axis.name + "\": coordinates must be finite");
  return t;
}

} // namespace st
