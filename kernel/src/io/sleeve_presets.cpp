// The sleeve and blade catalogue (st/io/plan.h): the built-in one and users' files.

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

/// The catalogue's document, its format checked.
json catalogue(const detail::JsonReader& r, const std::string& text) {
  json doc = r.parse(text);
  if (!doc.is_object()) r.fail("(top level)", "must be a JSON object");
  const std::string format = r.string(r.required(doc, "format", "format"), "format");
  if (format != "surgical-template-sleeves/1")
    r.fail("format", "must be \"surgical-template-sleeves/1\", got \"" + format + "\"");
  return doc;
}

/// The entry's name: required, not blank, not an earlier entry's.
template <class Preset> std::string entry_name(const detail::JsonReader& r, const json& e, const std::string& key,
                                               const std::vector<Preset>& earlier) {
  std::string name = r.string(r.required(e, "name", key + ".name"), key + ".name");
  if (trim(name).empty()) r.fail(key + ".name", "must not be empty");
  for (const Preset& q : earlier)
    if (q.name == name) r.fail(key + ".name", "\"" + name + "\" appears twice");
  return name;
}

/// The preset called `name` (exact, then case-insensitive); InvalidInput listing the names otherwise.
template <class Preset>
const Preset& find_named(const std::vector<Preset>& presets, const std::string& name, const std::string& what) {
  for (const Preset& p : presets)
    if (p.name == name) return p;
  for (const Preset& p : presets)
    if (lower(p.name) == lower(name)) return p;
  std::string names;
  for (const Preset& p : presets) names += (names.empty() ? "" : ", ") + ("\"" + p.name + "\"");
  throw InvalidInput("no " + what + " preset \"" + name + "\"; the catalogue has " + (names.empty() ? "none" : names));
}

} // namespace

std::vector<SleevePreset> parse_sleeve_presets(const std::string& text, const std::string& path) {
  const detail::JsonReader r(path);
  const json doc = catalogue(r, text);
  const json& sleeves = r.required(doc, "sleeves", "sleeves");
  if (!sleeves.is_array()) r.fail("sleeves", "must be an array");
  std::vector<SleevePreset> out;
  for (std::size_t i = 0; i < sleeves.size(); ++i) {
    const std::string key = "sleeves[" + std::to_string(i) + "]";
    const json& s = sleeves[i];
    if (!s.is_object()) r.fail(key, "must be an object");
    SleevePreset p;
    p.name = entry_name(r, s, key, out);
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
  return find_named(presets, name, "sleeve");
}

std::vector<BladePreset> parse_blade_presets(const std::string& text, const std::string& path) {
  const detail::JsonReader r(path);
  const json doc = catalogue(r, text);
  std::vector<BladePreset> out;
  if (!doc.contains("blades")) return out;
  const json& blades = doc["blades"];
  if (!blades.is_array()) r.fail("blades", "must be an array");
  for (std::size_t i = 0; i < blades.size(); ++i) {
    const std::string key = "blades[" + std::to_string(i) + "]";
    const json& b = blades[i];
    if (!b.is_object()) r.fail(key, "must be an object");
    BladePreset p;
    p.name = entry_name(r, b, key, out);
    if (b.contains("description")) p.description = r.string(b["description"], key + ".description");
    p.thickness = r.number(r.required(b, "thickness", key + ".thickness"), key + ".thickness");
    if (b.contains("clearance")) p.clearance = r.number(b["clearance"], key + ".clearance");
    // The slot's own rules (slot.h) on the blade's numbers, the rest of the slot left valid.
    SlotSpec slot;
    slot.direction = Vec3::UnitY();
    slot.blade = p.thickness;
    slot.clearance = p.clearance;
    slot.length = 1.0;
    if (const auto problem = slot_problem(slot))
      r.fail(key + "." + (problem->key == "blade" ? std::string("thickness") : problem->key), problem->reason);
    out.push_back(std::move(p));
  }
  return out;
}

std::vector<BladePreset> read_blade_presets(const std::string& path) {
  return parse_blade_presets(detail::read_text_file(path, "sleeve catalogue"), path);
}

const std::vector<BladePreset>& default_blade_presets() {
  static const std::vector<BladePreset> presets =
      parse_blade_presets(kDefaultSleevePresets, "data/sleeve-presets.json (built in)");
  return presets;
}

const BladePreset& find_blade_preset(const std::vector<BladePreset>& presets, const std::string& name) {
  return find_named(presets, name, "blade");
}

} // namespace st
