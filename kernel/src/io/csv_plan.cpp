// CSV tables of drilling axes or of cut planes read into a Plan (st/io/plan.h).

#include "st/io/plan.h"

#include "detail/json_reader.h"
#include "detail/text.h"
#include "st/core/errors.h"

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

const std::vector<std::string> kAxisColumns = {
    "name",           "entry_x",        "entry_y",  "entry_z",  "direction_x",  "direction_y",
    "direction_z",    "target_x",       "target_y", "target_z", "inner_radius", "outer_radius",
    "inner_diameter", "outer_diameter", "length",   "offset",   "depth"};

const std::vector<std::string> kPlaneColumns = {
    "name",        "origin_x",    "origin_y", "origin_z",  "normal_x", "normal_y", "normal_z", "direction_x",
    "direction_y", "direction_z", "blade",    "clearance", "length",   "height",   "wall",     "closed"};

using Columns = std::map<std::string, std::size_t>;

/// Checks the columns of a table of axes (`planes` false) or of planes: the required ones present,
/// vectors whole, one of each pair. Throws InvalidInput at `where` (the header line).
void check_columns(const Columns& column, bool planes, const std::string& where) {
  const auto has = [&](const char* c) { return column.count(c) > 0; };
  const auto need = [&](std::initializer_list<const char*> names) {
    for (const char* c : names)
      if (!has(c)) throw InvalidInput(where + ": no column \"" + std::string(c) + "\"");
  };
  const bool direction = has("direction_x") || has("direction_y") || has("direction_z");
  if (planes) {
    need({"origin_x", "origin_y", "origin_z", "normal_x", "normal_y", "normal_z"});
    if (direction) need({"direction_x", "direction_y", "direction_z"});
    return;
  }
  need({"entry_x", "entry_y", "entry_z"});
  const bool target_point = has("target_x") || has("target_y") || has("target_z");
  if (direction == target_point)
    throw InvalidInput(where + ": give either direction_x/_y/_z or target_x/_y/_z columns (one of them)");
  if (direction) need({"direction_x", "direction_y", "direction_z"});
  else need({"target_x", "target_y", "target_z"});
  if (has("inner_radius") && has("inner_diameter"))
    throw InvalidInput(where + ": give inner_radius or inner_diameter, not both");
  if (has("outer_radius") && has("outer_diameter"))
    throw InvalidInput(where + ": give outer_radius or outer_diameter, not both");
}

/// One line's fields by column, as numbers and vectors in the plan's frame.
struct Row {
  const std::vector<std::string>& fields;
  const Columns& column;
  const std::string& where;
  Space from, target;

  [[nodiscard]] bool given(const char* c) const { return column.count(c) && !fields[column.at(c)].empty(); }
  [[nodiscard]] const std::string& text(const char* c) const { return fields[column.at(c)]; }
  [[nodiscard]] double number(const char* c) const { return csv_number(text(c), where + ": " + c); }
  [[nodiscard]] Vec3 vec(const char* x, const char* y, const char* z) const {
    return convert_space(Vec3(number(x), number(y), number(z)), from, target);
  }
  [[nodiscard]] Vec3 unit(const char* x, const char* y, const char* z, const char* what) const {
    const Vec3 d = vec(x, y, z);
    const double n = d.stableNorm();
    if (!(n > 1e-12) || !std::isfinite(n)) throw InvalidInput(where + ": the " + what + " must be a non-zero vector");
    return d / n;
  }
  [[nodiscard]] std::optional<double> optional(const char* c, double scale = 1.0) const {
    if (!given(c)) return std::nullopt;
    return number(c) * scale;
  }
};

PlanAxis axis_row(const Row& row, std::size_t index) {
  PlanAxis axis;
  axis.source = row.where;
  axis.name = row.given("name") ? row.text("name") : std::to_string(index + 1);
  axis.entry = row.vec("entry_x", "entry_y", "entry_z");
  if (row.column.count("direction_x")) {
    axis.direction = row.unit("direction_x", "direction_y", "direction_z", "direction");
  } else {
    const Vec3 along = row.vec("target_x", "target_y", "target_z") - axis.entry;
    const double n = along.norm();
    if (!(n > 1e-9) || !std::isfinite(n))
      throw InvalidInput(row.where + ": the target must differ from the entry (it gives the direction)");
    axis.direction = along / n;
    axis.depth = n;
  }
  axis.inner_radius =
      row.column.count("inner_diameter") ? row.optional("inner_diameter", 0.5) : row.optional("inner_radius");
  axis.outer_radius =
      row.column.count("outer_diameter") ? row.optional("outer_diameter", 0.5) : row.optional("outer_radius");
  axis.length = row.optional("length");
  axis.offset = row.optional("offset");
  if (const auto depth = row.optional("depth")) axis.depth = depth;
  return axis;
}

/// Which ends of a slot are closed, from a CSV field: "both", "none", "start", "end", or "start" and
/// "end" separated by blanks, '+' or '/'.
std::array<bool, 2> closed_ends(const std::string& field, const std::string& where) {
  const std::string s = lower(trim(field));
  if (s == "both") return {true, true};
  if (s == "none") return {false, false};
  std::array<bool, 2> closed{false, false};
  std::size_t at = 0;
  while (at < s.size()) {
    const std::size_t stop = std::min(s.find_first_of(" +/", at), s.size());
    const std::string word = s.substr(at, stop - at);
    if (word == "start") closed[0] = true;
    else if (word == "end") closed[1] = true;
    else if (!word.empty())
      throw InvalidInput(where + ": \"" + field + "\" must be both, none, start, end or \"start end\"");
    at = stop + 1;
  }
  return closed;
}

PlanPlane plane_row(const Row& row, std::size_t index) {
  PlanPlane plane;
  plane.source = row.where;
  plane.name = row.given("name") ? row.text("name") : "cut " + std::to_string(index + 1);
  plane.origin = row.vec("origin_x", "origin_y", "origin_z");
  plane.normal = row.unit("normal_x", "normal_y", "normal_z", "normal");
  if (row.column.count("direction_x") &&
      (row.given("direction_x") || row.given("direction_y") || row.given("direction_z")))
    plane.direction = row.unit("direction_x", "direction_y", "direction_z", "direction");
  plane.blade = row.optional("blade");
  plane.clearance = row.optional("clearance");
  plane.length = row.optional("length");
  plane.height = row.optional("height");
  plane.wall = row.optional("wall");
  if (row.given("closed")) plane.closed = closed_ends(row.text("closed"), row.where + ": closed");
  return plane;
}

} // namespace

Plan parse_plan_csv(const std::string& text, const std::string& path, Space target) {
  Plan plan;
  plan.path = path;
  plan.kind = "csv";
  std::optional<Space> file_space;
  std::vector<std::string> header; // column keys
  char delimiter = ',';
  Columns column;
  bool planes = false; // a table of cut planes (it has normal_x), else of drilling axes
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
      planes = std::find(header.begin(), header.end(), "normal_x") != header.end();
      const std::vector<std::string>& known = planes ? kPlaneColumns : kAxisColumns;
      for (std::size_t i = 0; i < header.size(); ++i) {
        if (std::find(known.begin(), known.end(), header[i]) == known.end()) {
          plan.warnings.push_back(where + ": unknown column \"" + header[i] + "\" ignored" +
                                  (planes ? " (a table of planes: it has normal_x)" : ""));
          continue;
        }
        if (column.count(header[i])) throw InvalidInput(where + ": column \"" + header[i] + "\" appears twice");
        column[header[i]] = i;
      }
      check_columns(column, planes, where);
      continue;
    }
    const std::vector<std::string> fields = split_fields(line, delimiter, where);
    if (fields.size() != header.size())
      throw InvalidInput(where + ": has " + std::to_string(fields.size()) + " fields, the header names " +
                         std::to_string(header.size()));
    const Row row{fields, column, where, file_space.value_or(target), target};
    if (planes) plan.planes.push_back(plane_row(row, plan.planes.size()));
    else plan.axes.push_back(axis_row(row, plan.axes.size()));
  }
  if (header.empty())
    throw InvalidInput(path + ": empty: a CSV plan needs a header line and one line per axis or plane");
  if (plan.axes.empty() && plan.planes.empty())
    throw InvalidInput(path + ": names its columns but holds no " + (planes ? "planes" : "axes"));
  return plan;
}

Plan read_plan_csv(const std::string& path, Space target) {
  return parse_plan_csv(detail::read_text_file(path, "CSV plan"), path, target);
}

} // namespace st
