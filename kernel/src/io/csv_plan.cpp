// CSV tables of drilling axes read into a Plan (st/io/plan.h).

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

const std::vector<std::string> kCsvColumns = {
    "name",           "entry_x",        "entry_y",  "entry_z",  "direction_x",  "direction_y",
    "direction_z",    "target_x",       "target_y", "target_z", "inner_radius", "outer_radius",
    "inner_diameter", "outer_diameter", "length",   "offset",   "depth"};

} // namespace

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

} // namespace st
