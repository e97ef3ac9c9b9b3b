// The sleeve catalogue (st/io/plan.h): the built-in one and users' files.

#include "st/io/plan.h"

#include "detail/json_reader.h"
#include "detail/text.h"
#include "st/core/errors.h"
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
using detail::trim;

} // namespace

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
    if (s.contains("kind")) {
      const std::string kind = r.string(s["kind"], key + ".kind");
      const auto named = tube_kind_named(kind);
      if (!named) r.fail(key + ".kind", "must be \"sleeve\" or \"pin\", got \"" + kind + "\"");
      p.kind = *named;
    }
    if (s.contains("counterbore_diameter") != s.contains("counterbore_depth"))
      r.fail(key, "give counterbore_diameter and counterbore_depth together");
    if (s.contains("counterbore_diameter"))
      p.counterbore = Counterbore{0.5 * r.number(s["counterbore_diameter"], key + ".counterbore_diameter"),
                                  r.number(s["counterbore_depth"], key + ".counterbore_depth")};
    TubeSpec t;
    t.inner_radius = p.inner_radius;
    t.outer_radius = p.outer_radius;
    t.length = p.length;
    t.offset = p.offset;
    t.counterbore = p.counterbore;
    if (const auto problem = tube_size_problem(t)) {
      std::string k = problem->key;
      if (k == "inner_radius" || k == "outer_radius") k = k.substr(0, 5) + "_diameter";
      if (k == "counterbore.radius") k = "counterbore_diameter";
      if (k == "counterbore.depth") k = "counterbore_depth";
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

} // namespace st
